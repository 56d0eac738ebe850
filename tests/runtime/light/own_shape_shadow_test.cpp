// A sphere or disk area light cannot block the shadow ray to a point sampled
// on it, so its own occlusion test may be skipped (LightSample::own_shape,
// SceneGeometry::occluded's skip_shape). These tests check that claim against
// the full test on the light's own shape, from outside and inside, for whole
// and cut shapes, and that the skip never hides another shape; and the same for rays leaving
// the light (LightSet::shape_left_behind, SceneGeometry::intersect's skip_shape).
#include <gtest/gtest.h>

#include <string>

#include "light_test_scene.h"
#include "runtime/geometry/scene_geometry.h"

namespace rt {
namespace {

struct Counts {
  int samples = 0, own_shape_set = 0, blocked = 0, blocked_with_skip = 0;
};

// Samples light 0 from n random points in [lo, hi] (random normals) and
// counts the shadow rays to the samples that the scene blocks, with and
// without the skip.
Counts shadow_rays(const std::string& name, const std::string& world, Vec3 lo, Vec3 hi, int n) {
  LightScene s;
  Counts c;
  if (!load_light_scene(name, world, box(lo, hi), &s)) return c;
  SceneGeometry geometry;
  if (!build_light_scene_geometry(s, &geometry)) return c;
  Rng rng(11);
  for (int i = 0; i < n; ++i) {
    Vec3 p{lo.x + rng.next_float() * (hi.x - lo.x), lo.y + rng.next_float() * (hi.y - lo.y),
           lo.z + rng.next_float() * (hi.z - lo.z)};
    Vec3 dir{rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f};
    Interaction ref = surface_point(p, dir);
    LightSample ls;
    s.lights.sample_li(0, ref, {rng.next_float(), rng.next_float()}, &ls);
    if (ls.pdf == 0) continue;
    ++c.samples;
    if (ls.own_shape != kNone) ++c.own_shape_set;
    Ray r = ref.spawn_ray_to(ls.p_light);
    if (geometry.occluded(r)) ++c.blocked;
    if (geometry.occluded(r, ls.own_shape)) ++c.blocked_with_skip;
  }
  return c;
}

TEST(OwnShapeShadow, ASphereNeverBlocksItsOwnSamples) {
  // Points outside the sphere (cone sampling) and inside it (area sampling).
  Counts c = shadow_rays("own_sphere", R"(
AreaLightSource "diffuse" "rgb L" [1 1 1]
Translate 0.3 -0.2 0.1
Shape "sphere" "float radius" 1
)",
                         {-3, -3, -3}, {3, 3, 3}, 20000);
  EXPECT_GT(c.samples, 19000);
  EXPECT_EQ(c.own_shape_set, c.samples);
  EXPECT_EQ(c.blocked, 0);
  EXPECT_EQ(c.blocked_with_skip, 0);
}

TEST(OwnShapeShadow, ACutSphereOrDiskNeverBlocksItsOwnSamples) {
  Counts sphere = shadow_rays("own_cut_sphere", R"(
AreaLightSource "diffuse" "rgb L" [1 1 1] "bool twosided" "true"
Rotate 30 1 0 0
Shape "sphere" "float radius" 2 "float zmin" -1 "float zmax" 1.5 "float phimax" 250
)",
                              {-4, -4, -4}, {4, 4, 4}, 20000);
  EXPECT_GT(sphere.samples, 19000);
  EXPECT_EQ(sphere.own_shape_set, sphere.samples);
  EXPECT_EQ(sphere.blocked, 0);
  Counts disk = shadow_rays("own_disk", R"(
AreaLightSource "diffuse" "rgb L" [1 1 1] "bool twosided" "true"
Translate 0 0 0.5
Shape "disk" "float radius" 2 "float innerradius" 0.5 "float phimax" 300
)",
                            {-4, -4, -4}, {4, 4, 4}, 20000);
  EXPECT_GT(disk.samples, 19000);
  EXPECT_EQ(disk.own_shape_set, disk.samples);
  EXPECT_EQ(disk.blocked, 0);
}

TEST(OwnShapeShadow, TheSkipHidesNoOtherShape) {
  // A second sphere (not a light) sits between the sample points and the
  // light: every shadow ray through it stays blocked with the skip.
  Counts c = shadow_rays("own_sphere_blocked", R"(
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [1 1 1]
  Translate 0 0 5
  Shape "sphere" "float radius" 1
AttributeEnd
Shape "sphere" "float radius" 3
)",
                         {-0.3f, -0.3f, -6}, {0.3f, 0.3f, -5}, 2000);
  EXPECT_EQ(c.samples, 2000);
  EXPECT_EQ(c.blocked, c.samples);
  EXPECT_EQ(c.blocked_with_skip, c.samples);
}

TEST(OwnShapeShadow, TrianglesAndCylindersAreNotSkipped) {
  // An open cylinder can block the ray to its own far inside wall.
  Counts c = shadow_rays("own_cylinder", R"(
AreaLightSource "diffuse" "rgb L" [1 1 1] "bool twosided" "true"
Shape "cylinder" "float radius" 1 "float zmin" -1 "float zmax" 1
)",
                         {-3, -3, -0.5f}, {3, 3, 0.5f}, 5000);
  EXPECT_GT(c.samples, 4000);
  EXPECT_EQ(c.own_shape_set, 0);
  EXPECT_GT(c.blocked, 0);
  EXPECT_EQ(c.blocked_with_skip, c.blocked);
}

// Rays leaving an area light (LightSet::sample_le) skip its shape when shape_left_behind says
// they cannot meet it again: the hit with the skip is the full test's, bit for bit, with the
// shapes listed and in Embree, and the full test never hits the light's own shape on such a
// ray. Where the rule says no (a two-sided sphere's inward rays, a reversed sphere's), the full
// test does meet the sphere again, so the rule is not vacuous.
struct Leaving {
  int rays = 0, skipped = 0, own_hits_unskipped = 0;
};

Leaving leaving_rays(const std::string& name, const std::string& light, size_t max_listed) {
  LightScene s;
  Leaving c;
  // A wall and a floor the rays go on to hit, and a second sphere.
  const std::string world = "AttributeBegin\n" + light +
                            "AttributeEnd\n"
                            "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" "
                            "[-9 -9 -3  9 -9 -3  9 9 -3  -9 9 -3]\n"
                            "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] \"point P\" "
                            "[-9 6 -3  9 6 -3  9 6 9  -9 6 9]\n"
                            "Translate 2.5 0 0\nShape \"sphere\" \"float radius\" 0.7\n";
  if (!load_light_scene(name, world, box({-9, -9, -9}, {9, 9, 9}), &s)) return c;
  SceneGeometry geometry;
  geometry.set_max_listed(max_listed);
  if (!build_light_scene_geometry(s, &geometry)) return c;
  Rng rng(17);
  for (int i = 0; i < 20000; ++i) {
    Ray ray;
    Vec3 n;
    float pdf_pos = 0, pdf_dir = 0;
    s.lights.sample_le(0, {rng.next_float(), rng.next_float()},
                       {rng.next_float(), rng.next_float()}, 0, &ray, &n, &pdf_pos, &pdf_dir);
    if (pdf_pos == 0 || pdf_dir == 0) continue;
    ++c.rays;
    const uint32_t skip = s.lights.shape_left_behind(0, ray, n);
    SurfaceInteraction full, skipping;
    const bool hit = geometry.intersect(ray, &full);
    const bool hit_skipping = geometry.intersect(ray, &skipping, skip);
    if (skip == kNone) {
      if (hit && full.shape == 0) ++c.own_hits_unskipped;
      continue;
    }
    ++c.skipped;
    EXPECT_NE(hit && full.shape == skip, true) << i;
    EXPECT_EQ(hit, hit_skipping) << i;
    if (hit) {
      EXPECT_EQ(full.shape, skipping.shape) << i;
      EXPECT_EQ(full.t_hit, skipping.t_hit) << i;
    }
  }
  return c;
}

TEST(OwnShapeShadow, RaysLeavingTheLightSkipItsShape) {
  for (size_t max_listed : {size_t(32), size_t(0)}) {
    SCOPED_TRACE(max_listed);
    const Leaving one = leaving_rays(
        "leave_sphere",
        "AreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\nShape \"sphere\" \"float radius\" 1\n",
        max_listed);
    EXPECT_GT(one.rays, 19000);
    EXPECT_EQ(one.skipped, one.rays);  // one-sided: every ray leaves outward
    const Leaving two = leaving_rays("leave_sphere2",
                                     "AreaLightSource \"diffuse\" \"rgb L\" [1 1 1] \"bool "
                                     "twosided\" \"true\"\nShape \"sphere\" \"float radius\" 1\n",
                                     max_listed);
    EXPECT_NEAR(two.skipped, two.rays / 2, two.rays / 20);
    EXPECT_GT(two.own_hits_unskipped, two.rays / 3);  // inward rays meet the far side
    const Leaving reversed = leaving_rays("leave_sphere_rev",
                                          "ReverseOrientation\nAreaLightSource \"diffuse\" \"rgb "
                                          "L\" [1 1 1]\nShape \"sphere\" \"float radius\" 1\n",
                                          max_listed);
    EXPECT_EQ(reversed.skipped, 0);
    EXPECT_GT(reversed.own_hits_unskipped, reversed.rays * 9 / 10);
    const Leaving cut = leaving_rays("leave_cut_sphere",
                                     "AreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\nShape "
                                     "\"sphere\" \"float radius\" 1 \"float zmax\" 0.5 \"float "
                                     "phimax\" 200\n",
                                     max_listed);
    EXPECT_EQ(cut.skipped, cut.rays);
    const Leaving disk = leaving_rays("leave_disk",
                                      "AreaLightSource \"diffuse\" \"rgb L\" [1 1 1] \"bool "
                                      "twosided\" \"true\"\nShape \"disk\" \"float radius\" 1\n",
                                      max_listed);
    EXPECT_EQ(disk.skipped, disk.rays);
  }
}

TEST(OwnShapeShadow, ASkippedShapeIsNotHit) {
  // A ray through the light sphere at the wall behind it: with the sphere skipped, the wall.
  LightScene s;
  ASSERT_TRUE(load_light_scene(
      "skip_through",
      "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\nShape \"sphere\" \"float "
      "radius\" 1\nAttributeEnd\nShape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3] "
      "\"point P\" [-9 6 -9  9 6 -9  9 6 9  -9 6 9]\n",
      box({-9, -9, -9}, {9, 9, 9}), &s));
  for (size_t max_listed : {size_t(32), size_t(0)}) {
    SceneGeometry geometry;
    geometry.set_max_listed(max_listed);
    ASSERT_TRUE(build_light_scene_geometry(s, &geometry));
    Ray ray;
    ray.o = {0.1f, -5, 0.2f};
    ray.d = {0, 1, 0};
    ray.tmax = kInfinity;
    SurfaceInteraction a, b;
    ASSERT_TRUE(geometry.intersect(ray, &a));
    EXPECT_EQ(a.shape, 0u);
    ASSERT_TRUE(geometry.intersect(ray, &b, 0));
    EXPECT_EQ(b.shape, 1u);
    EXPECT_NEAR(b.t_hit, 11, 1e-4f);
  }
}

}  // namespace
}  // namespace rt
