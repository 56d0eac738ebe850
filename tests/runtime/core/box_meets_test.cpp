// Bounds3::meets, the slab test light sampling and Embree's user-geometry callbacks use to turn
// rays away before an exact test: it must never refuse a ray that meets the box (a refusal
// there is a missing hit), and it must refuse the rays that plainly miss it.
#include <gtest/gtest.h>

#include "runtime/core/rng.h"
#include "runtime/core/vec.h"

namespace rt {
namespace {

Bounds3 unit_box() {
  Bounds3 b;
  b.extend(Vec3{0, 0, 0});
  b.extend(Vec3{1, 1, 1});
  return b;
}

TEST(BoxMeets, RaysThroughPointsOfTheBoxAreNeverRefused) {
  // From random origins around the box through random points in it and on its faces, edges
  // and corners, t up to exactly the distance of that point.
  const Bounds3 b = unit_box();
  Rng rng(1);
  for (int i = 0; i < 200000; ++i) {
    Vec3 p{rng.next_float(), rng.next_float(), rng.next_float()};
    // On a face, an edge or a corner, where two or three slabs' distances meet at the point.
    for (int k = 0; k < i % 4; ++k) p[(i + k) % 3] = float(rng.next_float() < 0.5f);
    const Vec3 o{rng.next_float() * 8 - 4, rng.next_float() * 8 - 4, rng.next_float() * 8 - 4};
    const Vec3 d = p - o;
    ASSERT_TRUE(b.meets(o, d, 1)) << i;
    ASSERT_TRUE(b.meets(o, d * 0.25f, 4)) << i;
  }
}

TEST(BoxMeets, RaysBesideOrShortOfTheBoxAreRefused) {
  const Bounds3 b = unit_box();
  EXPECT_FALSE(b.meets({-1, 0.5f, 0.5f}, {-1, 0, 0}, kInfinity));  // pointing away
  EXPECT_FALSE(b.meets({-1, 0.5f, 0.5f}, {1, 0, 0}, 0.9f));        // stops short
  EXPECT_TRUE(b.meets({-1, 0.5f, 0.5f}, {1, 0, 0}, 1.1f));
  EXPECT_FALSE(b.meets({-1, 1.5f, 0.5f}, {1, 0, 0}, kInfinity));  // passes beside
  EXPECT_FALSE(b.meets({-1, -1, 0.5f}, {1, 3, 0}, kInfinity));    // passes the corner
  EXPECT_TRUE(b.meets({-1, -1, 0.5f}, {1, 1.5f, 0}, kInfinity));
  EXPECT_TRUE(b.meets({0.5f, 0.5f, 0.5f}, {0.3f, -0.2f, 0.1f}, 0));  // starts inside
}

TEST(BoxMeets, ARayAlongAFaceIsNotRefusedForIt) {
  // d.y == 0 with the origin on the face y = 1: the slab distances are 0 * inf, NaN.
  const Bounds3 b = unit_box();
  EXPECT_TRUE(b.meets({-1, 1, 0.5f}, {1, 0, 0}, kInfinity));
  EXPECT_TRUE(b.meets({-1, 0, 0.5f}, {1, 0, 0}, kInfinity));
  EXPECT_FALSE(b.meets({-1, 1.001f, 0.5f}, {1, 0, 0}, kInfinity));
}

}  // namespace
}  // namespace rt
