// DigitPermutations::scrambled() must equal the reference digit loop
// scrambled_radical_inverse() bit for bit, for every Halton dimension and
// for indices below and above 2^32 (its divide-free path covers only 32-bit
// values).
#include <gtest/gtest.h>

#include <cstring>

#include "runtime/core/rng.h"
#include "runtime/sampler/radical_inverse.h"

namespace rt {
namespace {

uint64_t bits(double x) {
  uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

TEST(ScrambledFast, BitIdenticalToReferenceLoop) {
  DigitPermutations perms(7);
  Rng rng(12345);
  const uint64_t edges[] = {0,
                            1,
                            2,
                            6,
                            7,
                            8,
                            242,
                            243,
                            0xfffffffeull,
                            0xffffffffull,
                            0x100000000ull,
                            0x123456789abull,
                            ~0ull >> 12,
                            ~0ull};
  for (int d = 0; d < kHaltonDimensions; d += (d < 64 ? 1 : 37)) {
    uint32_t base = halton_prime(d);
    const uint16_t* perm = perms.for_dimension(d);
    for (uint64_t a : edges)
      ASSERT_EQ(bits(perms.scrambled(d, a)), bits(scrambled_radical_inverse(base, a, perm)))
          << "dim " << d << " index " << a;
    for (int i = 0; i < 2000; ++i) {
      // Small, 32-bit and 64-bit indices alike.
      uint64_t a = uint64_t(rng.next_u32()) >> (rng.next_u32() % 32);
      if (i % 5 == 0) a |= uint64_t(rng.next_u32()) << (rng.next_u32() % 32);
      ASSERT_EQ(bits(perms.scrambled(d, a)), bits(scrambled_radical_inverse(base, a, perm)))
          << "dim " << d << " index " << a;
    }
  }
}

// radical_inverse() takes a compile-time path for base 3; it must match the
// plain digit loop exactly.
TEST(ScrambledFast, BaseThreeMatchesDigitLoop) {
  Rng rng(99);
  for (int i = 0; i < 20000; ++i) {
    uint64_t a = (uint64_t(rng.next_u32()) << 32 | rng.next_u32()) >> (rng.next_u32() % 64);
    uint64_t x = a, reversed = 0;
    double inv_n = 1;
    while (x) {
      reversed = reversed * 3 + x % 3;
      inv_n *= 1.0 / 3;
      x /= 3;
    }
    ASSERT_EQ(bits(radical_inverse(3, a)), bits(double(reversed) * inv_n)) << a;
  }
}

// radical_inverse_of_dimension() and radical_inverse() divide by a reciprocal below 2^32; they
// must equal the plain digit loop (a hardware divide per digit) bit for bit, for every
// dimension and index size.
TEST(ScrambledFast, UnscrambledDimensionMatchesDigitLoop) {
  Rng rng(4242);
  for (int d = 0; d < kHaltonDimensions; d += (d < 64 ? 1 : 29)) {
    const uint64_t base = halton_prime(d);
    for (int i = 0; i < 3000; ++i) {
      uint64_t a = uint64_t(rng.next_u32()) >> (rng.next_u32() % 32);
      if (i % 4 == 0) a |= uint64_t(rng.next_u32()) << (rng.next_u32() % 33);
      if (i < 4) a = i < 2 ? 0xffffffffull + uint64_t(i) : base * base * base - uint64_t(i - 2);
      uint64_t x = a, reversed = 0;
      double inv_n = 1;
      while (x) {
        reversed = reversed * base + x % base;
        inv_n *= 1.0 / double(base);
        x /= base;
      }
      ASSERT_EQ(bits(radical_inverse_of_dimension(d, a)), bits(double(reversed) * inv_n))
          << "dim " << d << " index " << a;
      ASSERT_EQ(bits(radical_inverse(uint32_t(base), a)), bits(double(reversed) * inv_n))
          << "base " << base << " index " << a;
    }
  }
}

}  // namespace
}  // namespace rt
