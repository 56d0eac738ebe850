// A mesh rays only pass through (ShapeInfo::passes_through: no material, or the interface one)
// gets a shortened interaction: p, its error bound, n and the shading normal (= n), wo, time,
// prim, face index and t. Those must be the full interaction's, bit for bit, or a ray crossing
// a medium's boundary would start elsewhere or enter the wrong medium: meshes plain, with
// ReverseOrientation, inside plain and mirrored instances. (Fails when the shortcut forgets
// the orientation flip: tried.)
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

constexpr const char* kWorld = R"(
Shape "trianglemesh" "integer indices" [0 1 2  0 2 3]
  "point P" [-4 -4 -3  4 -4 -3  4 4 -3.5  -4 4 -3]
AttributeBegin
  ReverseOrientation
  Shape "trianglemesh" "integer indices" [0 1 2  2 1 3]
    "point P" [-3 -3 2  3 -3 2.5  -3 3 2  3 3 2.2]
AttributeEnd
ObjectBegin "piece"
  Shape "trianglemesh" "integer indices" [0 1 2] "point P" [-1 -1 0  1 -1 0.2  0 1 0.1]
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
)";

TEST(PassThroughMesh, ShortInteractionIsTheFullOnesPart) {
  auto full = load_world("pass_through_full", kWorld);
  auto short_ = load_world("pass_through_short", kWorld);
  ASSERT_TRUE(full->built) << full->error;
  ASSERT_TRUE(short_->built) << short_->error;
  for (uint32_t i = 0; i < short_->shapes.size(); ++i) short_->shapes.set_passes_through(i, true);
  Rng rng(5);
  int hits = 0, instanced = 0, flipped = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 o{8 * rng.next_float() - 4, 8 * rng.next_float() - 4, 6 * rng.next_float() - 2};
    const Vec3 d = uniform_sample_sphere({rng.next_float(), rng.next_float()});
    const Ray ray = make_ray(o, d);
    SurfaceInteraction a, b;
    const bool hit = full->geometry.intersect(ray, &a);
    ASSERT_EQ(short_->geometry.intersect(ray, &b), hit) << i;
    if (!hit) continue;
    ++hits;
    instanced += a.instance != kNone;
    flipped += a.shape == 1;
    EXPECT_EQ(a.shape, b.shape);
    EXPECT_EQ(a.prim, b.prim);
    EXPECT_EQ(a.instance, b.instance);
    EXPECT_EQ(a.face_index, b.face_index);
    EXPECT_SAME_BITS(a.t_hit, b.t_hit);
    EXPECT_SAME_BITS(a.p, b.p);
    EXPECT_SAME_BITS(a.p_error, b.p_error);
    EXPECT_SAME_BITS(a.n, b.n);
    EXPECT_SAME_BITS(a.shading.n, b.shading.n);
    EXPECT_SAME_BITS(a.wo, b.wo);
    EXPECT_SAME_BITS(a.time, b.time);
  }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(instanced, 50);
  EXPECT_GT(flipped, 200);
}

}  // namespace
}  // namespace rt
