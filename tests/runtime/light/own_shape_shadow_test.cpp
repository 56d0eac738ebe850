// A sphere or disk area light cannot block the shadow ray to a point sampled
// on it, so its own occlusion test may be skipped (LightSample::own_shape,
// SceneGeometry::occluded's skip_shape). These tests check that claim against
// the full test on the light's own shape, from outside and inside, for whole
// and cut shapes, and that the skip never hides another shape.
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
  std::string error;
  if (!geometry.build(s.archive, s.shapes, nullptr, &error)) {
    ADD_FAILURE() << error;
    return c;
  }
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

}  // namespace
}  // namespace rt
