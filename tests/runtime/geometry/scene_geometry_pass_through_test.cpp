// A mesh rays only pass through (ShapeInfo::passes_through: no material, or the interface one)
// gets a shortened interaction: p, its error bound, n and the shading normal (= n), wo, time,
// prim, face index and t. Those must be the full interaction's, bit for bit, or a ray crossing
// a medium's boundary would start elsewhere or enter the wrong medium: meshes plain, with
// ReverseOrientation, inside plain and mirrored instances. (Fails when the shortcut forgets
// the orientation flip: tried.)
#include <gtest/gtest.h>

#include <string>

#include "scene_geometry_test_support.h"

namespace rt {
namespace {

const std::string kWorld = std::string(R"(
Shape "trianglemesh" "integer indices" [0 1 2  0 2 3]
  "point P" [-4 -4 -3  4 -4 -3  4 4 -3.5  -4 4 -3]
AttributeBegin
  ReverseOrientation
  Shape "trianglemesh" "integer indices" [0 1 2  2 1 3]
    "point P" [-3 -3 2  3 -3 2.5  -3 3 2  3 3 2.2]
AttributeEnd
)") + kTwoInstancesOfAPiece;

TEST(PassThroughMesh, ShortInteractionIsTheFullOnesPart) {
  auto full = load_world("pass_through_full", kWorld);
  auto short_ = load_world("pass_through_short", kWorld);
  ASSERT_TRUE(full->built) << full->error;
  ASSERT_TRUE(short_->built) << short_->error;
  for (uint32_t i = 0; i < short_->shapes.size(); ++i) short_->shapes.set_passes_through(i, true);
  Rng rng(5);
  int hits = 0, instanced = 0, flipped = 0;
  for (int i = 0; i < 4000; ++i) {
    const Ray ray = random_ray(rng, {-4, -4, -2}, {8, 8, 6});
    SurfaceInteraction a, b;
    const bool hit = full->geometry.intersect(ray, &a);
    ASSERT_EQ(short_->geometry.intersect(ray, &b), hit) << i;
    if (!hit) continue;
    ++hits;
    instanced += a.instance != kNone;
    flipped += a.shape == 1;
    expect_same_hit_point(a, b);
    EXPECT_SAME_BITS(a.time, b.time);
  }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(instanced, 50);
  EXPECT_GT(flipped, 200);
}

}  // namespace
}  // namespace rt
