// Radical inverses (pbrt book 3rd ed., section 7.4.1).
#include "runtime/sampler/radical_inverse.h"

#include <algorithm>
#include <utility>

#include "runtime/core/rng.h"
#include "runtime/sampler/pixel_seed.h"

namespace rt {
namespace {

// The primes are computed once (sieve of Eratosthenes; the 1000th prime is 7919).
const std::vector<uint32_t>& primes() {
  static const std::vector<uint32_t> table = [] {
    std::vector<uint32_t> p;
    const uint32_t limit = 8000;
    std::vector<bool> composite(limit, false);
    for (uint32_t i = 2; i < limit && p.size() < size_t(kHaltonDimensions); ++i) {
      if (composite[i]) continue;
      p.push_back(i);
      for (uint32_t j = i * i; j < limit; j += i) composite[j] = true;
    }
    return p;
  }();
  return table;
}

}  // namespace

uint32_t halton_prime(int d) {
  return primes()[size_t(d)];
}

double radical_inverse(uint32_t base, uint64_t a) {
  if (base == 2) {
    // Mirroring binary digits is a bit reversal.
    uint64_t r = a;
    r = ((r >> 1) & 0x5555555555555555ull) | ((r & 0x5555555555555555ull) << 1);
    r = ((r >> 2) & 0x3333333333333333ull) | ((r & 0x3333333333333333ull) << 2);
    r = ((r >> 4) & 0x0f0f0f0f0f0f0f0full) | ((r & 0x0f0f0f0f0f0f0f0full) << 4);
    r = ((r >> 8) & 0x00ff00ff00ff00ffull) | ((r & 0x00ff00ff00ff00ffull) << 8);
    r = ((r >> 16) & 0x0000ffff0000ffffull) | ((r & 0x0000ffff0000ffffull) << 16);
    r = (r >> 32) | (r << 32);
    return double(r) * 0x1p-64;
  }
  const double inv_base = 1.0 / base;
  uint64_t reversed = 0;
  double inv_base_n = 1;
  while (a) {
    uint64_t next = a / base;
    reversed = reversed * base + (a - next * base);
    inv_base_n *= inv_base;
    a = next;
  }
  return double(reversed) * inv_base_n;
}

double scrambled_radical_inverse(uint32_t base, uint64_t a, const uint16_t* perm) {
  const double inv_base = 1.0 / base;
  double reversed = 0, inv_base_n = 1;
  // Digits continue (as perm[0]) past a's last one; stop once they fall below
  // single precision, as pbrt-v3 does, and add the rest as a geometric series.
  while (1.f - float((base - 1) * inv_base_n) < 1.f) {
    uint64_t next = a / base;
    reversed = reversed * base + perm[a - next * base];
    inv_base_n *= inv_base;
    a = next;
  }
  return inv_base_n * (reversed + inv_base * perm[0] / (1 - inv_base));
}

uint64_t inverse_radical_inverse(uint32_t base, uint64_t inverse, int digits) {
  uint64_t index = 0;
  for (int i = 0; i < digits; ++i) {
    index = index * base + inverse % base;
    inverse /= base;
  }
  return index;
}

DigitPermutations::DigitPermutations(uint64_t seed) {
  Rng rng(mix_seed(seed, SeedPurpose::kGlobalTable, 0x4a17));
  offsets_.resize(size_t(kHaltonDimensions));
  size_t total = 0;
  for (int d = 0; d < kHaltonDimensions; ++d) {
    offsets_[size_t(d)] = uint32_t(total);
    total += halton_prime(d);
  }
  digits_.resize(total);
  for (int d = 0; d < kHaltonDimensions; ++d) {
    uint32_t base = halton_prime(d);
    uint16_t* perm = &digits_[offsets_[size_t(d)]];
    for (uint32_t i = 0; i < base; ++i) perm[i] = uint16_t(i);
    for (uint32_t i = 0; i < base; ++i) std::swap(perm[i], perm[i + rng.next_u32(base - i)]);
  }
}

}  // namespace rt
