// fast_acos and fast_atan2 (fast_trig.h) against double-precision libm: within 5e-7 radians
// everywhere (pi's float is itself 8.7e-8 off) and 3 float ulps relative in the first
// quadrant, over dense grids, the endpoints and octant boundaries, and atan2's signs and zeros.
// (Fails with a wrong coefficient, octant fold or mirror: tried.)
#include "runtime/core/fast_trig.h"

#include <gtest/gtest.h>

#include <cmath>

#include "runtime/core/rng.h"

namespace rt {
namespace {

TEST(FastTrig, AcosWithinThreeUlps) {
  double worst_abs = 0, worst_rel = 0;
  const int n = 2000000;
  for (int i = 0; i <= n; ++i) {
    const float z = -1 + 2 * float(i) / n;
    const double exact = std::acos(double(z)), got = fast_acos(z);
    worst_abs = std::max(worst_abs, std::fabs(got - exact));
    if (z >= 0 && exact > 0) worst_rel = std::max(worst_rel, std::fabs(got - exact) / exact);
  }
  EXPECT_LT(worst_abs, 5e-7);
  EXPECT_LT(worst_rel, 3 * 1.19e-7);
  // The ends: exact 0 at 1 (no density's sine is taken from it), pi's float at -1, and
  // clamped beyond.
  EXPECT_EQ(fast_acos(1.f), 0.f);
  EXPECT_EQ(fast_acos(-1.f), kPi);
  EXPECT_EQ(fast_acos(1.0000001f), 0.f);
  EXPECT_EQ(fast_acos(-1.0000001f), kPi);
  EXPECT_NEAR(fast_acos(0.f), kPiOver2, 1.5e-7);
}

TEST(FastTrig, Atan2WithinThreeUlpsInEveryOctant) {
  double worst_abs = 0, worst_rel = 0;
  Rng rng(5);
  for (int i = 0; i < 2000000; ++i) {
    float x = 2 * rng.next_float() - 1, y = 2 * rng.next_float() - 1;
    if (i % 5 == 0) y *= 1e-6f;                                      // near the x axis
    if (i % 7 == 0) x = y * (1 + 1e-6f * (rng.next_float() - .5f));  // near a diagonal
    const double exact = std::atan2(double(y), double(x)), got = fast_atan2(y, x);
    worst_abs = std::max(worst_abs, std::fabs(got - exact));
    if (x > 0 && y > 0) worst_rel = std::max(worst_rel, std::fabs(got - exact) / exact);
  }
  EXPECT_LT(worst_abs, 5e-7);
  EXPECT_LT(worst_rel, 3 * 1.19e-7);
  // Axes, signs and zeros as std::atan2 gives them (for +-0 only the value 0).
  EXPECT_EQ(fast_atan2(0.f, 0.f), 0.f);
  EXPECT_EQ(fast_atan2(0.f, 1.f), 0.f);
  EXPECT_EQ(fast_atan2(0.f, -1.f), kPi);
  EXPECT_EQ(fast_atan2(1.f, 0.f), kPiOver2);
  EXPECT_EQ(fast_atan2(-1.f, 0.f), -kPiOver2);
  EXPECT_NEAR(fast_atan2(-1.f, -1.f), -3 * kPiOver4, 2.4e-7);
  EXPECT_NEAR(fast_atan2(1.f, -1.f), 3 * kPiOver4, 2.4e-7);
}

}  // namespace
}  // namespace rt
