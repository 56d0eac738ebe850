// Rays spawned from hits never re-hit their own triangle, even far from the
// origin (coordinates ~1e4) where float spacing is ~1e-3, through every path
// a mesh can take into Embree: in place at the top level, copied through its transform,
// an object instance, and a copied mesh inside an instance.
#include <gtest/gtest.h>

#include <cstdio>

#include "runtime/core/rng.h"
#include "runtime/core/sampling.h"
#include "scene_geometry_test_support.h"

namespace rt {
namespace {

// A closed UV sphere of radius r about c, as trianglemesh text.
std::string sphere_mesh(Vec3 c, float r, int rings, int segments) {
  std::string P, idx;
  char buf[96];
  for (int i = 0; i <= rings; ++i) {
    float theta = kPi * i / rings;
    for (int j = 0; j < segments; ++j) {
      float phi = 2 * kPi * j / segments;
      Vec3 p = c + r * Vec3{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                            std::cos(theta)};
      std::snprintf(buf, sizeof buf, " %.9g %.9g %.9g", p.x, p.y, p.z);
      P += buf;
    }
  }
  auto id = [&](int i, int j) { return std::to_string(i * segments + (j % segments)); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      if (i > 0) idx += " " + id(i, j) + " " + id(i + 1, j) + " " + id(i, j + 1);
      if (i + 1 < rings) idx += " " + id(i, j + 1) + " " + id(i + 1, j) + " " + id(i + 1, j + 1);
    }
  return "Shape \"trianglemesh\" \"integer indices\" [" + idx + "] \"point P\" [" + P + "]\n";
}

// Fires `count` rays at the mesh around `center`, spawns a ray in a uniformly
// random direction from every hit, and counts spawned rays that hit the
// same triangle again.
void expect_no_self_hits(const LoadedScene& s, Vec3 center, float radius, int count) {
  Rng rng(11);
  int hits = 0, self_hits = 0, occluded_self = 0;
  for (int i = 0; i < count; ++i) {
    Vec3 target =
        center + radius * 0.7f * uniform_sample_sphere({rng.next_float(), rng.next_float()});
    Vec3 o = center + 3 * radius * uniform_sample_sphere({rng.next_float(), rng.next_float()});
    SurfaceInteraction si;
    if (!s.geometry.intersect(make_ray(o, target - o), &si)) continue;
    ++hits;
    Vec3 d = uniform_sample_sphere({rng.next_float(), rng.next_float()});
    Ray spawned = si.spawn_ray(d);
    SurfaceInteraction next;
    if (s.geometry.intersect(spawned, &next) && next.shape == si.shape && next.prim == si.prim &&
        next.instance == si.instance)
      ++self_hits;
    // A shadow ray towards a point just off the surface on the same side
    // must not be blocked by the surface itself.
    Vec3 above = si.p + si.n * (dot(si.n, d) > 0 ? 0.5f : -0.5f);
    if (s.geometry.occluded(si.spawn_ray_to(above))) ++occluded_self;
  }
  EXPECT_GT(hits, count / 2);
  EXPECT_EQ(self_hits, 0) << "of " << hits << " hits";
  EXPECT_EQ(occluded_self, 0) << "of " << hits << " hits";
}

constexpr int kRays = 100000;

TEST(SceneGeometryRobustness, InPlaceMeshFarFromOrigin) {
  Vec3 c{1.2e4f, -0.9e4f, 1.1e4f};
  auto s = load_world("sg_robust_inplace", sphere_mesh(c, 20, 24, 48));
  ASSERT_TRUE(s->built) << s->error;
  expect_no_self_hits(*s, c, 20, kRays);
}

TEST(SceneGeometryRobustness, TransformedMeshFarFromOrigin) {
  auto s = load_world("sg_robust_group", "Translate 1.2e4 -0.9e4 1.1e4\nRotate 27 0.3 1 0.4\n" +
                                             sphere_mesh({3, 1, -2}, 20, 24, 48));
  ASSERT_TRUE(s->built) << s->error;
  Vec3 c = s->shapes[0].object_to_world.point({3, 1, -2});
  expect_no_self_hits(*s, c, 20, kRays / 2);
}

TEST(SceneGeometryRobustness, InstanceAndCopiedMeshFarFromOrigin) {
  auto s = load_world("sg_robust_instance", "ObjectBegin \"ball\"\nRotate 40 1 1 0\n" +
                                                sphere_mesh({3, 1, -2}, 20, 24, 48) + R"(
ObjectEnd
Translate 1.2e4 -0.9e4 1.1e4
Rotate 27 0.3 1 0.4
ObjectInstance "ball"
)");
  ASSERT_TRUE(s->built) << s->error;
  ASSERT_EQ(s->geometry.stats().copied_meshes, 1u);
  Bounds3 b = s->geometry.world_bounds();
  expect_no_self_hits(*s, b.center(), 20, kRays / 2);
}

}  // namespace
}  // namespace rt
