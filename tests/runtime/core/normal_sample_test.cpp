// normal_sample: a standard normal, tails included. Metropolis light transport's small steps
// are its draws; a wrong layer table or a lost tail would skew every mutation. (Fails with the
// layer widths 1% too wide, with the tail returned at r, with the wedge always accepted:
// tried.)
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "runtime/core/normal_sample.h"

namespace rt {
namespace {

double normal_cdf(double x) {
  return 0.5 * std::erfc(-x / std::sqrt(2.0));
}

TEST(NormalSample, MomentsAndBinsOfAStandardNormal) {
  Rng rng(11);
  const int n = 2000000;
  const double lo = -4, hi = 4;
  const int bins = 64;
  std::vector<int> count(bins + 2, 0);  // below lo, the bins, above hi
  double sum = 0, sum2 = 0, sum4 = 0;
  for (int i = 0; i < n; ++i) {
    const double x = normal_sample(rng);
    ASSERT_TRUE(std::isfinite(x));
    sum += x;
    sum2 += x * x;
    sum4 += x * x * x * x;
    const int b = x < lo ? 0 : x >= hi ? bins + 1 : 1 + int((x - lo) / (hi - lo) * bins);
    ++count[size_t(b)];
  }
  // Mean 0, variance 1, fourth moment 3: within 5 standard errors.
  EXPECT_NEAR(sum / n, 0, 5 * std::sqrt(1.0 / n));
  EXPECT_NEAR(sum2 / n, 1, 5 * std::sqrt(2.0 / n));
  EXPECT_NEAR(sum4 / n, 3, 5 * std::sqrt(96.0 / n));
  // Pearson's chi-square over the bins and the two tails (66 cells, 65 degrees of freedom:
  // its 99.99% quantile is about 117).
  double chi2 = 0;
  for (int b = 0; b < bins + 2; ++b) {
    const double a = b == 0 ? -INFINITY : lo + (hi - lo) * (b - 1) / bins;
    const double c = b == bins + 1 ? INFINITY : lo + (hi - lo) * b / bins;
    const double expected = n * (normal_cdf(c) - normal_cdf(a));
    chi2 += (count[size_t(b)] - expected) * (count[size_t(b)] - expected) / expected;
  }
  EXPECT_LT(chi2, 117);
}

TEST(NormalSample, TailBeyondTheBaseLayer) {
  // The ziggurat's tail starts at 3.4426: about 2.9e-4 of the draws on each side, beyond it,
  // and spread as the normal spreads there (half of them beyond 3.64).
  Rng rng(5);
  const int n = 4000000;
  int beyond = 0, far = 0, below = 0;
  for (int i = 0; i < n; ++i) {
    const float x = normal_sample(rng);
    beyond += x > 3.4426f;
    far += x > 3.64f;
    below += x < -3.4426f;
  }
  const double p = 1 - normal_cdf(3.4426), p_far = 1 - normal_cdf(3.64);
  EXPECT_NEAR(beyond, n * p, 5 * std::sqrt(n * p));
  EXPECT_NEAR(below, n * p, 5 * std::sqrt(n * p));
  EXPECT_NEAR(far, n * p_far, 5 * std::sqrt(n * p_far));
}

TEST(NormalSample, SameStateSameNumbers) {
  Rng a(3, 9), b(3, 9);
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(normal_sample(a), normal_sample(b));
}

}  // namespace
}  // namespace rt
