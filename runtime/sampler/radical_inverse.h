// runtime/sampler/radical_inverse.h — radical inverses in prime bases (the
// Halton sequence), their digit-permuted (scrambled) form, and the tables
// they need: the first kHaltonDimensions primes and one random digit
// permutation per prime.
//
// Dimension d of the Halton sequence uses the d-th prime (2, 3, 5, ...).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

namespace rt {

inline constexpr int kHaltonDimensions = 1000;  // as pbrt-v3's prime table

// The d-th prime, d in [0, kHaltonDimensions).
uint32_t halton_prime(int d);

// Digits of a in base b mirrored about the radix point: 0.d0 d1 d2 ...
// a's 64 bits in reverse order: base 2's digit mirror.
inline uint64_t reverse_bits(uint64_t r) {
  r = ((r >> 1) & 0x5555555555555555ull) | ((r & 0x5555555555555555ull) << 1);
  r = ((r >> 2) & 0x3333333333333333ull) | ((r & 0x3333333333333333ull) << 2);
  r = ((r >> 4) & 0x0f0f0f0f0f0f0f0full) | ((r & 0x0f0f0f0f0f0f0f0full) << 4);
  r = ((r >> 8) & 0x00ff00ff00ff00ffull) | ((r & 0x00ff00ff00ff00ffull) << 8);
  r = ((r >> 16) & 0x0000ffff0000ffffull) | ((r & 0x0000ffff0000ffffull) << 16);
  return (r >> 32) | (r << 32);
}

double radical_inverse(uint32_t base, uint64_t a);
// radical_inverse(halton_prime(d), a), bit for bit, without a hardware divide per digit.
double radical_inverse_of_dimension(int d, uint64_t a);
// The same with every digit (including the infinite tail of zeros) mapped
// through perm, a permutation of 0..base-1.
double scrambled_radical_inverse(uint32_t base, uint64_t a, const uint16_t* perm);
// The index whose first `digits` base-kBase digits, mirrored, are `inverse`. The base is a
// template argument so that the divisions become multiplications: Halton's start_pixel runs
// this (bases 2 and 3) for every pixel of every pass.
template <uint32_t kBase>
uint64_t inverse_radical_inverse(uint64_t inverse, int digits) {
  uint64_t index = 0;
  for (int i = 0; i < digits; ++i) {
    index = index * kBase + inverse % kBase;
    inverse /= kBase;
  }
  return index;
}

// One random permutation of the digits per Halton dimension, with what
// scrambled() needs to evaluate that dimension without a hardware divide.
// Each dimension's permutation comes from its own random stream and is made
// the first time it is asked for (thread-safe): all 1000 would take 7.4 MB,
// a path tracer uses a few dozen.
class DigitPermutations {
 public:
  explicit DigitPermutations(uint64_t seed);
  DigitPermutations(const DigitPermutations&) = delete;
  DigitPermutations& operator=(const DigitPermutations&) = delete;

  const uint16_t* for_dimension(int d) const { return permutation(d); }
  // Bit-identical to scrambled_radical_inverse(halton_prime(d), a,
  // for_dimension(d)), several times faster: the digit count and the scale
  // base^-digits depend only on the base and are precomputed, digits are
  // split off (two at a time for small bases) by multiplying with a per-base
  // reciprocal (exact for 32-bit values), and once a runs out of digits the remaining perm[0]
  // digits are added in one step.
  double scrambled(int d, uint64_t a) const;

 private:
  // What depends only on the base is set up front; the permutation and what depends on it
  // (pairs, fill, tail) when the dimension is first used, published by the store to perm.
  struct Dimension {
    std::atomic<const uint16_t*> perm{nullptr};
    // Small bases also split two digits at a time: pairs[r] for r < base^2
    // is the permuted, mirrored pair of digits (r % base, r / base).
    const uint16_t* pairs = nullptr;
    const uint64_t* fill = nullptr;  // perm[0] * (1 + base + ... + base^(k-1)), k = 0..digits
    double tail = 0;                 // the digits past `digits`, a geometric series in perm[0]
    const uint64_t* pow = nullptr;   // base^k, k = 0..digits
    uint32_t base = 0, base2 = 0;
    int digits = 0;       // how many digits pbrt-v3's loop takes in this base
    uint64_t recip = 0;   // ceil(2^64 / base): a / base = (recip * a) >> 64 for a < 2^32
    uint64_t recip2 = 0;  // ceil(2^64 / base^2)
    double scale = 0;     // base^-digits, rounded exactly as the reference loop rounds it
  };
  struct Made {  // a dimension's tables, once made
    std::vector<uint16_t> perm, pairs;
    std::vector<uint64_t> fill;
  };
  const uint16_t* permutation(int d) const {
    const uint16_t* perm = dims_[size_t(d)].perm.load(std::memory_order_acquire);
    return perm ? perm : make_dimension(d);
  }
  const uint16_t* make_dimension(int d) const;

  uint64_t seed_;
  std::unique_ptr<Dimension[]> dims_;
  std::vector<uint64_t> pow_;
  mutable std::unique_ptr<Made[]> made_;
  mutable std::mutex making_;
};

}  // namespace rt
