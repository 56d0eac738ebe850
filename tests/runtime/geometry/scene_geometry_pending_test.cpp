// SceneGeometry's hit in two steps: intersect_ids() already gives what was hit (shape, prim,
// instance: all a caller looking for one light reads), and complete() then gives intersect()'s
// interaction bit for bit; for world meshes (with normals and uv), meshes inside mirrored and
// plain instances, and quadrics in both. (Fails when intersect_ids leaves prim out: tried.)
#include <gtest/gtest.h>

#include <string>

#include "scene_geometry_test_support.h"

namespace rt {
namespace {

TEST(SceneGeometryPending, CompletedHitIsIntersectsHit) {
  auto s = load_world("sg_pending", R"(
Shape "trianglemesh" "integer indices" [0 1 2  0 2 3]
  "point P" [-4 -4 -3  4 -4 -3  4 4 -3.5  -4 4 -3]
  "normal N" [0 0.1 1  0.1 0 1  0 0 1  -0.1 0 1]
  "float uv" [0 0  2 0  2 3  0 3]
AttributeBegin
  Translate 0 0 2
  Shape "sphere" "float radius" 0.7
AttributeEnd
)" + std::string(kTwoInstancesOfAPiece));
  ASSERT_TRUE(s->built) << s->error;
  Rng rng(17);
  int triangles = 0, quadrics = 0, instanced = 0;
  for (int i = 0; i < 4000; ++i) {
    const Ray ray = random_ray(rng, {-4, -4, -1}, {8, 8, 6});
    SurfaceInteraction whole, two_step;
    SceneGeometry::PendingHit pending;
    const bool hit = s->geometry.intersect(ray, &whole);
    ASSERT_EQ(s->geometry.intersect_ids(ray, &two_step, &pending), hit) << i;
    if (!hit) continue;
    EXPECT_EQ(two_step.shape, whole.shape);
    EXPECT_EQ(two_step.prim, whole.prim);
    EXPECT_EQ(two_step.instance, whole.instance);
    s->geometry.complete(pending, ray, &two_step);
    expect_same_hit_point(two_step, whole);
    EXPECT_SAME_BITS(two_step.uv, whole.uv);
    EXPECT_SAME_BITS(two_step.dpdu, whole.dpdu);
    EXPECT_SAME_BITS(two_step.dpdv, whole.dpdv);
    EXPECT_SAME_BITS(two_step.dndu, whole.dndu);
    EXPECT_SAME_BITS(two_step.shading.dpdu, whole.shading.dpdu);
    const bool quadric = s->shapes[whole.shape].kind != ShapeKind::kTriangles;
    quadrics += quadric;
    triangles += !quadric;
    instanced += whole.instance != kNone;
  }
  // Every kind of hit was compared many times.
  EXPECT_GT(triangles, 300);
  EXPECT_GT(quadrics, 100);
  EXPECT_GT(instanced, 50);
}

}  // namespace
}  // namespace rt
