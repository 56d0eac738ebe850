// next_float_up / next_float_down against std::nextafter, which they must
// match exactly (the interval bounds of quadric tests depend on every ulp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "runtime/core/math.h"
#include "runtime/core/rng.h"

namespace rt {
namespace {

bool same_bits(float a, float b) {
  return std::memcmp(&a, &b, 4) == 0;
}

void expect_like_nextafter(float v) {
  const float inf = std::numeric_limits<float>::infinity();
  // nextafter(+inf, +inf) is +inf and nextafter(+-0, +inf) the smallest denormal, as required.
  EXPECT_TRUE(same_bits(next_float_up(v), std::nextafter(v, inf))) << v;
  EXPECT_TRUE(same_bits(next_float_down(v), std::nextafter(v, -inf))) << v;
}

TEST(NextFloat, MatchesNextafterAtSpecialValues) {
  const float inf = std::numeric_limits<float>::infinity();
  const float lims[] = {0.f,
                        -0.f,
                        inf,
                        -inf,
                        std::numeric_limits<float>::denorm_min(),
                        -std::numeric_limits<float>::denorm_min(),
                        std::numeric_limits<float>::min(),
                        -std::numeric_limits<float>::min(),
                        std::numeric_limits<float>::max(),
                        -std::numeric_limits<float>::max(),
                        1.f,
                        -1.f,
                        0x1.fffffep-1f,
                        -0x1.fffffep-1f};
  for (float v : lims) expect_like_nextafter(v);
  EXPECT_TRUE(same_bits(next_float_up(-0.f), std::numeric_limits<float>::denorm_min()));
  EXPECT_TRUE(same_bits(next_float_down(0.f), -std::numeric_limits<float>::denorm_min()));
  EXPECT_TRUE(std::isnan(next_float_up(std::nanf(""))));
  EXPECT_TRUE(std::isnan(next_float_down(std::nanf(""))));
}

TEST(NextFloat, MatchesNextafterOnRandomBitPatterns) {
  Rng rng(7);
  int checked = 0;
  for (int i = 0; i < 200000; ++i) {
    float v;
    uint32_t bits = rng.next_u32();
    std::memcpy(&v, &bits, 4);
    if (std::isnan(v)) continue;
    expect_like_nextafter(v);
    ++checked;
  }
  EXPECT_GT(checked, 190000);
}

}  // namespace
}  // namespace rt
