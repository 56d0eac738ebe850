// Bump mapping from compiled scene text: a constant displacement of a flat
// surface leaves the shading frame alone; ramps tilt the shading normal away
// from the rising side by exactly the slope, and the BSDF uses that frame.
#include <gtest/gtest.h>

#include "material_test_scene.h"
#include "runtime/material/bump.h"

namespace rt {
namespace {

using material_test::MaterialScene;

// z = 0 plane, u along +x, v along +y, no curvature, at uv (0.5, 0.5).
SurfaceInteraction plane_hit() {
  SurfaceInteraction si;
  si.n = Vec3{0, 0, 1};
  si.uv = {0.5f, 0.5f};
  si.dpdu = Vec3{1, 0, 0};
  si.dpdv = Vec3{0, 1, 0};
  si.shading = {si.n, si.dpdu, si.dpdv, Vec3{}, Vec3{}};
  return si;
}

const char* kScene = R"(
Texture "ramp_u" "float" "bilerp" "float v00" 0 "float v01" 0 "float v10" 1 "float v11" 1
Texture "ramp_v" "float" "bilerp" "float v00" 0 "float v01" .5 "float v10" 0 "float v11" .5
AttributeBegin
  Material "matte" "float bumpmap" .1
  Shape "sphere"
AttributeEnd
AttributeBegin
  Material "matte" "texture bumpmap" "ramp_u"
  Shape "sphere"
AttributeEnd
AttributeBegin
  Material "plastic" "texture bumpmap" "ramp_v"
  Shape "sphere"
AttributeEnd
AttributeBegin
  Material "matte"
  Shape "sphere"
AttributeEnd
)";

void expect_vec_near(Vec3 a, Vec3 b, float tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST(Bump, ConstantDisplacementKeepsTheFrameAndRampsTilt) {
  MaterialScene scene;
  ASSERT_TRUE(scene.load("bump", kScene)) << scene.error;
  EXPECT_TRUE(scene.materials.node(scene.material_of_shape(0)).has_bump);
  EXPECT_FALSE(scene.materials.node(scene.material_of_shape(3)).has_bump);

  auto shade = [&](uint32_t shape, SurfaceInteraction si) {
    Bsdf b;
    EXPECT_TRUE(scene.materials.compute_bsdf(scene.material_of_shape(shape), &si,
                                             TransportMode::kRadiance, true, &b));
    // The BSDF is expressed in the bumped frame.
    expect_vec_near(b.shading_normal(), si.shading.n, 1e-6f);
    expect_vec_near(b.geometric_normal(), Vec3{0, 0, 1}, 0);
    return si;
  };

  SurfaceInteraction flat = shade(0, plane_hit());
  expect_vec_near(flat.shading.n, Vec3{0, 0, 1}, 1e-6f);
  expect_vec_near(flat.shading.dpdu, Vec3{1, 0, 0}, 1e-6f);
  expect_vec_near(flat.n, Vec3{0, 0, 1}, 0);

  // d = u: the surface rises along +x with slope 1, so the normal leans to -x by 45 degrees.
  SurfaceInteraction ramp = shade(1, plane_hit());
  expect_vec_near(ramp.shading.n, normalize(Vec3{-1, 0, 1}), 1e-3f);
  expect_vec_near(ramp.shading.dpdu, Vec3{1, 0, 1}, 1e-3f);

  // With screen-space differentials the step changes, not the (linear) result.
  SurfaceInteraction with_diffs = plane_hit();
  with_diffs.dudx = 0.02f;
  with_diffs.dvdy = 0.04f;
  with_diffs = shade(1, with_diffs);
  expect_vec_near(with_diffs.shading.n, normalize(Vec3{-1, 0, 1}), 1e-3f);

  // d = v / 2: slope 1/2 along +y.
  SurfaceInteraction ramp_v = shade(2, plane_hit());
  expect_vec_near(ramp_v.shading.n, normalize(Vec3{0, -0.5f, 1}), 1e-3f);

  SurfaceInteraction none = shade(3, plane_hit());
  expect_vec_near(none.shading.n, Vec3{0, 0, 1}, 0);
}

TEST(Bump, CurvedSurfaceConstantDisplacementMovesAlongTheNormalDerivative) {
  // On a unit sphere (dn/du = dp/du), displacing by a constant c scales the
  // tangents by (1 + c) but leaves the normal where it was.
  MaterialScene scene;
  ASSERT_TRUE(scene.load("bump_curved", kScene)) << scene.error;
  SurfaceInteraction si = plane_hit();
  si.dndu = si.dpdu;
  si.dndv = si.dpdv;
  si.shading.dndu = si.dpdu;
  si.shading.dndv = si.dpdv;
  apply_bump(scene.textures, FloatInput{0.1f, kNone}, &si);
  expect_vec_near(si.shading.dpdu, Vec3{1.1f, 0, 0}, 1e-5f);
  expect_vec_near(si.shading.dpdv, Vec3{0, 1.1f, 0}, 1e-5f);
  expect_vec_near(si.shading.n, Vec3{0, 0, 1}, 1e-5f);
}

}  // namespace
}  // namespace rt
