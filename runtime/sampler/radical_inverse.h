// runtime/sampler/radical_inverse.h — radical inverses in prime bases (the
// Halton sequence), their digit-permuted (scrambled) form, and the tables
// they need: the first kHaltonDimensions primes and one random digit
// permutation per prime.
//
// Dimension d of the Halton sequence uses the d-th prime (2, 3, 5, ...).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

namespace rt {

inline constexpr int kHaltonDimensions = 1000;  // as pbrt-v3's prime table

// The d-th prime, d in [0, kHaltonDimensions).
uint32_t halton_prime(int d);

// Digits of a in base b mirrored about the radix point: 0.d0 d1 d2 ...
double radical_inverse(uint32_t base, uint64_t a);
// The same with every digit (including the infinite tail of zeros) mapped
// through perm, a permutation of 0..base-1.
double scrambled_radical_inverse(uint32_t base, uint64_t a, const uint16_t* perm);
// The index whose first `digits` base-b digits, mirrored, are `inverse`.
uint64_t inverse_radical_inverse(uint32_t base, uint64_t inverse, int digits);

// One random permutation of the digits per Halton dimension.
class DigitPermutations {
 public:
  explicit DigitPermutations(uint64_t seed);
  const uint16_t* for_dimension(int d) const { return &digits_[offsets_[size_t(d)]]; }

 private:
  std::vector<uint16_t> digits_;
  std::vector<uint32_t> offsets_;
};

}  // namespace rt
