// Transforms: inverses, error bounds that contain the exact result, handedness.
#include <gtest/gtest.h>

#include <random>

#include "runtime/core/sampling.h"
#include "runtime/core/transform.h"

namespace rt {
namespace {

TEST(Transform, FromDoublesInvertsAndComposesToIdentity) {
  double m[16] = {2, 0, 0, 1, 0, 3, 0, -2, 0, 0, -1, 5, 0, 0, 0, 1};
  Transform t = Transform::from_doubles(m);
  ASSERT_TRUE(t.invertible());
  EXPECT_TRUE(t.swaps_handedness());
  EXPECT_TRUE(t.has_scale());
  Vec3 p{0.3f, -7.f, 2.f};
  Vec3 back = t.inverse().point(t.point(p));
  EXPECT_NEAR(back.x, p.x, 1e-5);
  EXPECT_NEAR(back.y, p.y, 1e-5);
  EXPECT_NEAR(back.z, p.z, 1e-5);
}

TEST(Transform, SingularMatrixIsReportedNotInverted) {
  double m[16] = {1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  EXPECT_FALSE(Transform::from_doubles(m).invertible());
}

TEST(Transform, PointErrorBoundContainsTheExactResult) {
  std::mt19937 gen(7);
  std::uniform_real_distribution<float> d(-1000, 1000);
  for (int i = 0; i < 10000; ++i) {
    double m[16];
    for (int k = 0; k < 12; ++k) m[k] = d(gen) / 100;
    m[12] = m[13] = m[14] = 0;
    m[15] = 1;
    Transform t = Transform::from_doubles(m);
    Vec3 p{d(gen), d(gen), d(gen)}, err;
    Vec3 r = t.point(p, &err);
    const Matrix4& f = t.matrix();
    for (int row = 0; row < 3; ++row) {
      double exact = double(f.m[row][0]) * p.x + double(f.m[row][1]) * p.y +
                     double(f.m[row][2]) * p.z + double(f.m[row][3]);
      ASSERT_LE(std::fabs(exact - r[row]), err[row]) << "row " << row;
    }
  }
}

TEST(Distribution1D, SamplesInProportionToItsValues) {
  float f[4] = {1, 0, 3, 4};
  Distribution1D d(f, 4);
  int counts[4] = {};
  for (int i = 0; i < 8000; ++i) counts[d.sample_discrete((i + 0.5f) / 8000)]++;
  EXPECT_EQ(counts[1], 0);
  EXPECT_NEAR(counts[0], 1000, 2);
  EXPECT_NEAR(counts[2], 3000, 2);
  EXPECT_NEAR(counts[3], 4000, 2);
  float pdf;
  float x = d.sample_continuous(0.95f, &pdf);
  EXPECT_GE(x, 0.75f);
  EXPECT_NEAR(pdf, 4 / 2.f, 1e-5);  // value / integral, integral = 8/4
}

}  // namespace
}  // namespace rt
