// tests/compiler/lexer_numbers_test.cpp — the short-decimal fast path agrees with fast_float.
#include <gtest/gtest.h>

#include <fast_float/fast_float.h>

#include <cstdio>
#include <cstring>
#include <random>
#include <string>

#include "compiler/lexer.h"

namespace pbrtc {
namespace {

float reference(const std::string& s) {
  const char* b = s.data();
  if (*b == '+') ++b;
  float v = 0;
  auto r = fast_float::from_chars(b, s.data() + s.size(), v);
  EXPECT_EQ(r.ptr, s.data() + s.size()) << s;
  return v;
}

void expect_same(const std::string& s) {
  float fast;
  const char* end = parse_short_float(s.data(), s.data() + s.size(), &fast);
  if (!end) return;  // left to fast_float
  ASSERT_EQ(end, s.data() + s.size()) << s;
  float ref = reference(s);
  uint32_t a, b;
  std::memcpy(&a, &fast, 4);
  std::memcpy(&b, &ref, 4);
  EXPECT_EQ(a, b) << s << ": fast path " << fast << ", fast_float " << ref;
}

TEST(LexerNumbers, ShortDecimalsMatchFastFloatBitForBit) {
  for (const char* s :
       {"0", "-0", "+3", ".5", "1.", "-2.5e-3", "1e5", "1E+05", "0.1", "0.3", "3.1415927",
        "16777215", "9999999", "0.0000001", "1e10", "1e-10", "-0.000", "123.4567", "7e-4"})
    expect_same(s);
  std::mt19937 rng(3);
  char buf[64];
  int taken = 0;
  for (int i = 0; i < 300000; ++i) {
    float x = std::ldexp(float(rng() % 100000000) / 1e8f, int(rng() % 40) - 20);
    if (rng() % 2) x = -x;
    const char* fmts[] = {"%.6g", "%.7g", "%.3f", "%.5e", "%g", "%.1f"};
    std::snprintf(buf, sizeof buf, fmts[rng() % 6], double(x));
    std::string s = buf;
    float v;
    if (parse_short_float(s.data(), s.data() + s.size(), &v)) ++taken;
    expect_same(s);
  }
  EXPECT_GT(taken, 100000);  // the fast path is really taken
}

TEST(LexerNumbers, LongOrOddNumbersAreLeftToFastFloat) {
  float v;
  for (const char* s :
       {"16777217", "123456789", "0.123456789", "1e11", "1e-11", "-", ".", "e5", "1e", "1e+"}) {
    std::string t = s;
    const char* end = parse_short_float(t.data(), t.data() + t.size(), &v);
    EXPECT_TRUE(end == nullptr || end != t.data() + t.size()) << s;
  }
}

}  // namespace
}  // namespace pbrtc
