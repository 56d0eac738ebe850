// tests/format/texel_format_test.cpp — the texel formats' encodings (format/texel_format.h):
// every half decodes to its IEEE value (one at a time or through the table large arrays use)
// and encodes back to itself; floats between two halves
// round to the nearer, ties to even, and overflow exactly where binary16 says; every unorm8
// byte round-trips and values round to the nearest step; representability is what pbrtc's
// --texture-precision refuses on.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "format/texel_format.h"

namespace pbrta {
namespace {

TEST(TexelFormat, BytesAndNames) {
  EXPECT_EQ(texel_bytes(0), 4u);
  EXPECT_EQ(texel_bytes(1), 2u);
  EXPECT_EQ(texel_bytes(2), 1u);
  EXPECT_EQ(texel_bytes(3), 0u);
  EXPECT_STREQ(texel_format_name(1), "f16");
  EXPECT_STREQ(texel_format_name(2), "unorm8");
}

TEST(TexelFormat, HalfKnownValues) {
  EXPECT_EQ(half_to_float(0x3c00), 1.f);
  EXPECT_EQ(half_to_float(0xc000), -2.f);
  EXPECT_EQ(half_to_float(0x7bff), 65504.f);
  EXPECT_EQ(half_to_float(0x0001), std::ldexp(1.f, -24));  // smallest subnormal
  EXPECT_EQ(half_to_float(0x0400), std::ldexp(1.f, -14));  // smallest normal
  EXPECT_EQ(half_to_float(0x3555), 0.333251953125f);
  EXPECT_TRUE(std::isinf(half_to_float(0x7c00)));
  EXPECT_TRUE(std::isnan(half_to_float(0x7e00)));
  EXPECT_TRUE(std::signbit(half_to_float(0x8000)));
  EXPECT_EQ(float_to_half(1.f / 3.f), 0x3555);
  EXPECT_EQ(float_to_half(-0.f), 0x8000);
  EXPECT_EQ(float_to_half(std::ldexp(1.f, -30)), 0x0000);  // below half the smallest subnormal
}

// Every finite or infinite half survives the trip through float and back; NaNs stay NaNs.
TEST(TexelFormat, EveryHalfRoundTrips) {
  for (uint32_t h = 0; h < 0x10000; ++h) {
    const float f = half_to_float(uint16_t(h));
    if ((h & 0x7c00) == 0x7c00 && (h & 0x3ff)) {
      EXPECT_TRUE(std::isnan(f)) << h;
      EXPECT_EQ(float_to_half(f) & 0x7c00, 0x7c00) << h;
      EXPECT_NE(float_to_half(f) & 0x3ff, 0) << h;
      continue;
    }
    ASSERT_EQ(float_to_half(f), h) << h;
  }
}

// Between two adjacent positive halves a and b: just above the midpoint goes to b, just below to
// a, the midpoint itself to whichever is even. Covers subnormals, normals and the carry into the
// next exponent.
TEST(TexelFormat, HalfRoundsToNearestEven) {
  for (uint32_t h = 0; h < 0x7bff; ++h) {
    const double a = half_to_float(uint16_t(h)), b = half_to_float(uint16_t(h + 1));
    const float mid = float((a + b) / 2);  // exact: halves have 11 significant bits
    ASSERT_EQ(double(mid), (a + b) / 2);
    const uint16_t even = (h & 1) ? uint16_t(h + 1) : uint16_t(h);
    ASSERT_EQ(float_to_half(mid), even) << h;
    ASSERT_EQ(float_to_half(std::nextafter(mid, 1e9f)), h + 1) << h;
    ASSERT_EQ(float_to_half(std::nextafter(mid, -1e9f)), h) << h;
    ASSERT_EQ(float_to_half(-mid), even | 0x8000) << h;
  }
}

TEST(TexelFormat, HalfOverflowsAtBinary16sBoundary) {
  EXPECT_EQ(float_to_half(65519.99f), 0x7bff);
  EXPECT_EQ(float_to_half(kHalfOverflow), 0x7c00);
  EXPECT_EQ(float_to_half(-1e30f), 0xfc00);
  EXPECT_TRUE(texel_representable(1, 65519.99f));
  EXPECT_FALSE(texel_representable(1, kHalfOverflow));
  EXPECT_FALSE(texel_representable(1, -1e6f));
  // Already infinite or NaN: f16 holds those as they are.
  EXPECT_TRUE(texel_representable(1, std::numeric_limits<float>::infinity()));
  EXPECT_TRUE(texel_representable(1, std::numeric_limits<float>::quiet_NaN()));
}

TEST(TexelFormat, Unorm8) {
  for (int q = 0; q < 256; ++q) {
    EXPECT_EQ(unorm8_to_float(uint8_t(q)), float(q) / 255.f);
    ASSERT_EQ(float_to_unorm8(unorm8_to_float(uint8_t(q))), q);
  }
  // Nearest step: 0.5/255 is the worst case.
  for (int i = 0; i <= 10000; ++i) {
    const float v = float(i) / 10000.f;
    ASSERT_LE(std::fabs(unorm8_to_float(float_to_unorm8(v)) - v), 0.5f / 255.f + 1e-7f) << v;
  }
  EXPECT_EQ(float_to_unorm8(0.5f), 128);  // 127.5 rounds away from zero
  EXPECT_TRUE(texel_representable(2, 0.f));
  EXPECT_TRUE(texel_representable(2, 1.f));
  EXPECT_FALSE(texel_representable(2, 1.0001f));
  EXPECT_FALSE(texel_representable(2, -1e-9f));
  EXPECT_FALSE(texel_representable(2, std::numeric_limits<float>::quiet_NaN()));
  EXPECT_TRUE(texel_representable(0, std::numeric_limits<float>::quiet_NaN()));
}

TEST(TexelFormat, EncodeDecodeArrays) {
  const std::vector<float> v = {0.f, 0.25f, 1.f / 3.f, 1.f, 0.9999f, 1e-6f};
  for (uint32_t format = 0; format < 3; ++format) {
    std::vector<uint8_t> bytes(v.size() * texel_bytes(format));
    encode_texels(format, v.data(), v.size(), bytes.data());
    std::vector<float> back(v.size());
    decode_texels(format, bytes.data(), v.size(), back.data());
    for (size_t i = 0; i < v.size(); ++i) {
      const float want = format == 0   ? v[i]
                         : format == 1 ? half_to_float(float_to_half(v[i]))
                                       : unorm8_to_float(float_to_unorm8(v[i]));
      EXPECT_EQ(back[i], want);
    }
    if (format == 1) {
      uint16_t h;
      std::memcpy(&h, &bytes[2 * 3], 2);
      EXPECT_EQ(h, 0x3c00);  // little-endian binary16 in place
    }
  }
}

// Large arrays decode through a table: the same bits as one value at a time, NaNs included.
TEST(TexelFormat, LargeHalfArraysDecodeAsSingleValues) {
  std::vector<uint8_t> bytes(2 * 65536);
  for (uint32_t h = 0; h < 65536; ++h) std::memcpy(&bytes[2 * h], &h, 2);  // little-endian
  std::vector<float> out(65536);
  decode_texels(1, bytes.data(), out.size(), out.data());
  for (uint32_t h = 0; h < 65536; ++h) {
    const float one = half_to_float(uint16_t(h));
    ASSERT_EQ(0, std::memcmp(&out[h], &one, 4)) << h;
  }
}

}  // namespace
}  // namespace pbrta
