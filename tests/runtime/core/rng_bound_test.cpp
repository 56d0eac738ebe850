// Rng::next_u32(bound): every value below the bound, each equally likely. The shuffles of the
// pixel samplers and Halton's digit permutations draw from it, so a bias would skew them.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "runtime/core/rng.h"

namespace rt {
namespace {

TEST(RngBound, EveryValueBelowTheBoundEquallyOften) {
  Rng rng(7);
  for (uint32_t bound : {1u, 2u, 3u, 7u, 10u, 1000u}) {
    const int per_value = 2000;
    const int n = int(bound) * per_value;
    std::vector<int> count(bound, 0);
    for (int i = 0; i < n; ++i) {
      const uint32_t v = rng.next_u32(bound);
      ASSERT_LT(v, bound);
      ++count[v];
    }
    // Each count is binomial(n, 1 / bound): within 5 standard deviations.
    const double sigma = std::sqrt(n * (1.0 / bound) * (1 - 1.0 / bound));
    for (uint32_t v = 0; v < bound; ++v)
      EXPECT_LE(std::fabs(count[v] - per_value), 5 * sigma + 1e-9) << "bound " << bound;
  }
}

// Bounds near 2^32 are where taking r * bound / 2^32 without redrawing is most biased: with
// bound 3 * 2^30, values that are multiples of 3 would come half the time instead of a third.
TEST(RngBound, LargeBoundsAreUnbiased) {
  Rng rng(11);
  const uint32_t bound = 3u << 30;
  const int n = 60000;
  int multiples = 0;
  for (int i = 0; i < n; ++i) {
    const uint32_t v = rng.next_u32(bound);
    ASSERT_LT(v, bound);
    multiples += v % 3 == 0;
  }
  EXPECT_NEAR(double(multiples) / n, 1.0 / 3, 0.01);
  for (int i = 0; i < 1000; ++i) ASSERT_LT(rng.next_u32(0xffffffffu), 0xffffffffu);
}

}  // namespace
}  // namespace rt
