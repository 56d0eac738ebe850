// fast_acos and fast_atan2 (fast_trig.h) against double-precision libm: within 5e-7 radians
// everywhere (pi's float is itself 8.7e-8 off) and 3 float ulps relative in the first
// quadrant, over dense grids, the endpoints and octant boundaries, and atan2's signs and zeros.
// (Fails with a wrong coefficient, octant fold or mirror: tried.)
#include "runtime/core/fast_trig.h"

#include <gtest/gtest.h>

#include <cmath>

#include "runtime/core/rng.h"
#include "runtime/core/sampling.h"

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

TEST(FastTrig, SinCosQuarterWithinTwoUlps) {
  double worst_s = 0, worst_c = 0;
  const int n = 2000000;
  for (int i = 0; i <= n; ++i) {
    const float phi = kPiOver4 * (-1 + 2 * float(i) / n);
    float s, c;
    sin_cos_quarter(phi, &s, &c);
    worst_s = std::max(worst_s, std::fabs(s - std::sin(double(phi))));
    worst_c = std::max(worst_c, std::fabs(c - std::cos(double(phi))));
  }
  // Absolute: two ulps of a float in [1/2, 1) (2^-24 each), where cos is and |sin| ends.
  EXPECT_LT(worst_s, 2 * 0x1p-24);
  EXPECT_LT(worst_c, 2 * 0x1p-24);
  float s, c;
  sin_cos_quarter(0, &s, &c);
  EXPECT_EQ(s, 0.f);
  EXPECT_EQ(c, 1.f);
}

TEST(FastTrig, ConcentricDiskAsPbrtsAngles) {
  // The disk mapping by pbrt's angles and libm, to rounding: every octant, the diagonals and
  // the axes.
  Rng rng(9);
  double worst = 0;
  for (int i = 0; i < 1000000; ++i) {
    Vec2 u{rng.next_float(), rng.next_float()};
    if (i % 11 == 0) u.y = u.x;      // a diagonal
    if (i % 13 == 0) u.y = 1 - u.x;  // the other
    if (i % 17 == 0) u.x = 0.5f;     // an axis
    const double ox = 2.0 * u.x - 1, oy = 2.0 * u.y - 1;
    double x = 0, y = 0;
    if (ox != 0 || oy != 0) {
      const bool wide = std::fabs(ox) > std::fabs(oy);
      const double r = wide ? ox : oy;
      const double theta = wide ? kPi / 4 * (oy / ox) : kPi / 2 - kPi / 4 * (ox / oy);
      x = r * std::cos(theta);
      y = r * std::sin(theta);
    }
    const Vec2 d = concentric_sample_disk(u);
    worst = std::max({worst, std::fabs(d.x - x), std::fabs(d.y - y)});
  }
  EXPECT_LT(worst, 3e-7);
}

}  // namespace
}  // namespace rt
