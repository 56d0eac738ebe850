// Rays spawned from quadric hits (offset by the hits' error bounds) never
// hit the same surface again where they cannot, at unit scale and for big
// spheres far from the origin, where float spacing is coarse.
#include <gtest/gtest.h>

#include <string>

#include "runtime/geometry/quadric_intersect.h"
#include "tests/runtime/geometry/quadric_test_shapes.h"

namespace rt {
namespace {

using namespace quadric_test;

Vec3 random_direction(Rng& rng) {
  for (;;) {
    Vec3 v = random_point(rng, {0, 0, 0}, 1);
    float l2 = length_squared(v);
    if (l2 > 1e-4f && l2 <= 1) return v / std::sqrt(l2);
  }
}

struct SpawnStats {
  int hits = 0, outward_rehits = 0, inward_checked = 0, inward_wrong = 0;
};

// Shoots n rays at the shape (centred at c, size r); from each hit spawns one
// ray away from the surface (outwards: must miss when the shape is convex
// from outside, `convex`) and one into it (must reach the far side, not the
// starting point).
SpawnStats run(const ShapeInfo& s, Vec3 c, float r, bool convex, int n, uint64_t seed) {
  SpawnStats st;
  Rng rng(seed);
  for (int i = 0; i < n; ++i) {
    Vec3 o = c + random_direction(rng) * (3 * r);
    Vec3 target = c + random_direction(rng) * (0.9f * r * rng.next_float());
    float t;
    SurfaceInteraction si;
    if (!intersect_quadric(s, Ray{o, target - o}, &t, &si)) continue;
    ++st.hits;
    Vec3 n_out = s.flip_normals() ? -si.n : si.n;
    Vec3 w = random_direction(rng);
    if (dot(w, n_out) < 0) w = -w;
    float t2;
    SurfaceInteraction si2;
    if (intersect_quadric(s, si.spawn_ray(w), &t2, &si2)) {
      if (convex) ++st.outward_rehits;
    }
    // Into the shape at a steep enough angle that the far side is well away.
    if (dot(w, n_out) > 0.2f && convex) {
      ++st.inward_checked;
      if (!intersect_quadric(s, si.spawn_ray(-w), &t2, &si2) || distance(si2.p, si.p) < 0.1f * r)
        ++st.inward_wrong;
    }
  }
  return st;
}

TEST(QuadricSpawn, UnitSphereAtOrigin) {
  ShapeInfo s = make_shape(ShapeKind::kSphere);
  SpawnStats st = run(s, {0, 0, 0}, 1, true, 100000, 1);
  EXPECT_GT(st.hits, 95000);
  EXPECT_EQ(st.outward_rehits, 0);
  EXPECT_GT(st.inward_checked, 30000);
  EXPECT_EQ(st.inward_wrong, 0);
}

TEST(QuadricSpawn, BigSphereFarFromOrigin) {
  // Radius in the parameters, and radius from a scale: both far away.
  QuadricParams q;
  q.radius = 1e4f;
  q.zmin = -1e4f;
  q.zmax = 1e4f;
  Vec3 c{1e5f, -1e5f, 1e5f};
  for (int variant = 0; variant < 2; ++variant) {
    SCOPED_TRACE(variant);
    ShapeInfo s = variant == 0 ? make_shape(ShapeKind::kSphere, q, translate(c))
                               : make_shape(ShapeKind::kSphere, QuadricParams{},
                                            translate(c) * scale(1e4f, 1e4f, 1e4f));
    SpawnStats st = run(s, c, 1e4f, true, 100000, 2 + variant);
    EXPECT_GT(st.hits, 95000);
    EXPECT_EQ(st.outward_rehits, 0);
    EXPECT_EQ(st.inward_wrong, 0);
  }
}

TEST(QuadricSpawn, MirroredReversedSphereCylinderAndDisk) {
  Transform m = translate({3, 4, -5}) * scale(-2, 2, 2);
  ShapeInfo sphere = make_shape(ShapeKind::kSphere, QuadricParams{}, m);
  sphere.reverse_orientation = true;
  SpawnStats st = run(sphere, {3, 4, -5}, 2, true, 20000, 5);
  EXPECT_GT(st.hits, 19000);
  EXPECT_EQ(st.outward_rehits, 0);
  EXPECT_EQ(st.inward_wrong, 0);

  // A closed-phi cylinder is convex across z; the disk is flat, so no
  // spawned ray may hit it again on either side.
  ShapeInfo cyl = make_shape(ShapeKind::kCylinder, QuadricParams{}, translate({0, 0, 100}));
  st = run(cyl, {0, 0, 100}, 1, true, 20000, 6);
  EXPECT_GT(st.hits, 10000);
  EXPECT_EQ(st.outward_rehits, 0);

  QuadricParams dq;
  dq.height = 0.25f;
  ShapeInfo disk = make_shape(ShapeKind::kDisk, dq, rotate(40, {1, 1, 0}) * translate({0, 0, 50}));
  Rng rng(9);
  int hits = 0;
  for (int i = 0; i < 20000; ++i) {
    Vec3 c = disk.object_to_world.point({0, 0, 0.25f});
    Vec3 o = c + random_direction(rng) * 3.f;
    Vec3 target =
        disk.object_to_world.point({rng.next_float() - 0.5f, rng.next_float() - 0.5f, 0.25f});
    float t;
    SurfaceInteraction si;
    if (!intersect_quadric(disk, Ray{o, target - o}, &t, &si)) continue;
    ++hits;
    Vec3 w = random_direction(rng);
    SurfaceInteraction si2;
    EXPECT_FALSE(intersect_quadric(disk, si.spawn_ray(w), &t, &si2));
  }
  EXPECT_GT(hits, 15000);
}

}  // namespace
}  // namespace rt
