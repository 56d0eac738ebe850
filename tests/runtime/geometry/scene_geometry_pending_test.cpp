// SceneGeometry's hit in two steps: intersect_ids() already gives what was hit (shape, prim,
// instance: all a caller looking for one light reads), and complete() then gives intersect()'s
// interaction bit for bit; for world meshes (with normals and uv), meshes inside mirrored and
// plain instances, and quadrics in both. (Fails when intersect_ids leaves prim out: tried.)
#include <gtest/gtest.h>

#include <cstring>

#include "runtime/core/rng.h"
#include "runtime/core/sampling.h"
#include "scene_geometry_test_support.h"

namespace rt {
namespace {

bool same_bits(const void* a, const void* b, size_t n) {
  return std::memcmp(a, b, n) == 0;
}
#define EXPECT_SAME_BITS(a, b) EXPECT_TRUE(same_bits(&(a), &(b), sizeof(a))) << #a

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
ObjectBegin "piece"
  Shape "trianglemesh" "integer indices" [0 1 2] "point P" [-1 -1 0  1 -1 0.2  0 1 0.1]
  Translate 0 0 0.5
  Shape "sphere" "float radius" 0.3
ObjectEnd
AttributeBegin
  Translate 2 1 0
  ObjectInstance "piece"
AttributeEnd
AttributeBegin
  Translate -2 -1 0
  Scale -1 1 1
  ObjectInstance "piece"
AttributeEnd
)");
  ASSERT_TRUE(s->built) << s->error;
  Rng rng(17);
  int triangles = 0, quadrics = 0, instanced = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 o{8 * rng.next_float() - 4, 8 * rng.next_float() - 4, 6 * rng.next_float() - 1};
    const Vec3 d = uniform_sample_sphere({rng.next_float(), rng.next_float()});
    const Ray ray = make_ray(o, d);
    SurfaceInteraction whole, two_step;
    SceneGeometry::PendingHit pending;
    const bool hit = s->geometry.intersect(ray, &whole);
    ASSERT_EQ(s->geometry.intersect_ids(ray, &two_step, &pending), hit) << i;
    if (!hit) continue;
    EXPECT_EQ(two_step.shape, whole.shape);
    EXPECT_EQ(two_step.prim, whole.prim);
    EXPECT_EQ(two_step.instance, whole.instance);
    s->geometry.complete(pending, ray, &two_step);
    EXPECT_SAME_BITS(two_step.p, whole.p);
    EXPECT_SAME_BITS(two_step.p_error, whole.p_error);
    EXPECT_SAME_BITS(two_step.n, whole.n);
    EXPECT_SAME_BITS(two_step.wo, whole.wo);
    EXPECT_SAME_BITS(two_step.uv, whole.uv);
    EXPECT_SAME_BITS(two_step.dpdu, whole.dpdu);
    EXPECT_SAME_BITS(two_step.dpdv, whole.dpdv);
    EXPECT_SAME_BITS(two_step.dndu, whole.dndu);
    EXPECT_SAME_BITS(two_step.shading.n, whole.shading.n);
    EXPECT_SAME_BITS(two_step.shading.dpdu, whole.shading.dpdu);
    EXPECT_SAME_BITS(two_step.t_hit, whole.t_hit);
    EXPECT_EQ(two_step.face_index, whole.face_index);
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
