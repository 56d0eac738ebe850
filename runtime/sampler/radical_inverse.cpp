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

namespace {

// Base 3 (Halton's second dimension, every camera sample) five digits at a time: the loop's
// reversed digits are an exact integer and its scale is 3^-n rounded after each of n
// multiplications, so a table of 5-digit reversals, one of the last (shorter) chunk with its
// digit count, and the n-th scale as the loop rounds it give the loop's value bit for bit.
struct Base3 {
  static constexpr uint32_t kChunk = 243;  // 3^5
  uint8_t reversed5[kChunk];               // digits d0..d4 of r as d0 d1 d2 d3 d4
  uint8_t reversed_short[kChunk];          // r's own digits (no leading zeros) reversed
  uint8_t digits_short[kChunk];            // how many there are
  uint64_t pow[6];                         // 3^k, k = 0..5
  double scale[42];                        // 3^-n as the loop rounds it (3^41 > 2^64)
};

const Base3& base3() {
  static const Base3 table = [] {
    Base3 t{};
    for (uint32_t r = 0; r < Base3::kChunk; ++r) {
      uint32_t x = r, rev = 0, n = 0;
      for (int k = 0; k < 5; ++k, x /= 3) rev = rev * 3 + x % 3;
      t.reversed5[r] = uint8_t(rev);
      for (x = r, rev = 0; x; x /= 3, ++n) rev = rev * 3 + x % 3;
      t.reversed_short[r] = uint8_t(rev);
      t.digits_short[r] = uint8_t(n);
    }
    t.pow[0] = 1;
    for (int k = 1; k < 6; ++k) t.pow[k] = t.pow[k - 1] * 3;
    t.scale[0] = 1;
    for (int n = 1; n < 42; ++n) t.scale[n] = t.scale[n - 1] * (1.0 / 3);
    return t;
  }();
  return table;
}

double radical_inverse_base3(uint64_t a) {
  const Base3& t = base3();
  uint64_t reversed = 0;
  int n = 0;
  for (; a >= Base3::kChunk; n += 5) {
    const uint64_t next = a / Base3::kChunk;
    reversed = reversed * Base3::kChunk + t.reversed5[a - next * Base3::kChunk];
    a = next;
  }
  const int last = t.digits_short[a];
  reversed = reversed * t.pow[last] + t.reversed_short[a];
  return double(reversed) * t.scale[n + last];
}

// Bases up to this have a table of digit pairs (61^2 entries fit in 16 bits).
constexpr uint32_t kMaxPairBase = 61;

// ceil(2^64 / base), the multiplier div_by_reciprocal divides by base with.
uint64_t reciprocal(uint32_t base) {
  return ~uint64_t(0) / base + 1;
}

inline uint32_t div_by_reciprocal(uint64_t recip, uint32_t a) {
  return uint32_t((static_cast<unsigned __int128>(recip) * a) >> 64);
}

// The digit loop of a base above 3, given the base's rounded-up reciprocal: below 2^32 the
// quotient is a multiplication by it, not a hardware divide a digit (tens of cycles; sppm's
// photons draw every value this way).
double radical_inverse_by_reciprocal(uint32_t base, uint64_t recip, uint64_t a) {
  const double inv_base = 1.0 / base;
  uint64_t reversed = 0;
  double inv_base_n = 1;
  for (; a > 0xffffffffull; a /= base) {
    reversed = reversed * base + a % base;
    inv_base_n *= inv_base;
  }
  for (uint32_t a32 = uint32_t(a); a32;) {
    const uint32_t next = div_by_reciprocal(recip, a32);
    reversed = reversed * base + (a32 - next * base);
    inv_base_n *= inv_base;
    a32 = next;
  }
  return double(reversed) * inv_base_n;
}

}  // namespace

double radical_inverse(uint32_t base, uint64_t a) {
  if (base == 2) {
    // Mirroring binary digits is a bit reversal.
    return double(reverse_bits(a)) * 0x1p-64;
  }
  if (base == 3) return radical_inverse_base3(a);
  return radical_inverse_by_reciprocal(base, reciprocal(base), a);
}

double radical_inverse_of_dimension(int d, uint64_t a) {
  const uint32_t base = halton_prime(d);
  if (base <= 3) return radical_inverse(base, a);
  // The reciprocals made once: a divide a call is a visible part of sppm's photon values.
  static const std::vector<uint64_t> recips = [] {
    std::vector<uint64_t> r(static_cast<size_t>(kHaltonDimensions));
    for (int i = 0; i < kHaltonDimensions; ++i) r[size_t(i)] = reciprocal(halton_prime(i));
    return r;
  }();
  return radical_inverse_by_reciprocal(base, recips[size_t(d)], a);
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

DigitPermutations::DigitPermutations(uint64_t seed)
    : seed_(seed),
      dims_(new Dimension[size_t(kHaltonDimensions)]),
      made_(new Made[size_t(kHaltonDimensions)]) {
  std::vector<size_t> pow_at(static_cast<size_t>(kHaltonDimensions));
  for (int d = 0; d < kHaltonDimensions; ++d) {
    Dimension& dim = dims_[size_t(d)];
    dim.base = halton_prime(d);
    dim.recip = reciprocal(dim.base);
    dim.base2 = dim.base * dim.base;
    dim.recip2 = reciprocal(dim.base2);
    // The reference loop's digit count and scale, replayed with its own
    // operations so the rounding is the same.
    const double inv_base = 1.0 / dim.base;
    double inv_base_n = 1;
    int n = 0;
    while (1.f - float((dim.base - 1) * inv_base_n) < 1.f) {
      inv_base_n *= inv_base;
      ++n;
    }
    dim.digits = n;
    dim.scale = inv_base_n;
    pow_at[size_t(d)] = pow_.size();
    uint64_t pw = 1;
    for (int k = 0; k <= n; ++k, pw *= dim.base) pow_.push_back(pw);
  }
  for (int d = 0; d < kHaltonDimensions; ++d) dims_[size_t(d)].pow = &pow_[pow_at[size_t(d)]];
}

const uint16_t* DigitPermutations::make_dimension(int d) const {
  std::lock_guard<std::mutex> lock(making_);
  Dimension& dim = dims_[size_t(d)];
  if (const uint16_t* made = dim.perm.load(std::memory_order_acquire)) return made;
  Made& m = made_[size_t(d)];
  const uint32_t base = dim.base;
  Rng rng(mix_seed(seed_, SeedPurpose::kGlobalTable, 0x4a17, uint64_t(d)));
  m.perm.resize(base);
  for (uint32_t i = 0; i < base; ++i) m.perm[i] = uint16_t(i);
  for (uint32_t i = 0; i < base; ++i) std::swap(m.perm[i], m.perm[i + rng.next_u32(base - i)]);
  if (base <= kMaxPairBase) {
    for (uint32_t r = 0; r < base * base; ++r)
      m.pairs.push_back(uint16_t(m.perm[r % base] * base + m.perm[r / base]));
    dim.pairs = m.pairs.data();
  }
  uint64_t fill = 0;
  for (int k = 0; k <= dim.digits; ++k, fill = fill * base + m.perm[0]) m.fill.push_back(fill);
  dim.fill = m.fill.data();
  const double inv_base = 1.0 / base;
  dim.tail = inv_base * m.perm[0] / (1 - inv_base);
  dim.perm.store(m.perm.data(), std::memory_order_release);
  return m.perm.data();
}

double DigitPermutations::scrambled(int d, uint64_t a) const {
  const uint16_t* perm = permutation(d);  // before dim's other lazily made fields are read
  const Dimension& dim = dims_[size_t(d)];
  const uint32_t base = dim.base;
  // The reference accumulates the reversed digits in a double; they are an
  // integer below 2^53, so a 64-bit integer holds the same value exactly.
  uint64_t reversed = 0;
  int k = dim.digits;
  for (; k > 0 && a > 0xffffffffull; --k) {
    uint64_t next = a / base;
    reversed = reversed * base + perm[a - next * base];
    a = next;
  }
  uint32_t a32 = uint32_t(a);
  if (dim.pairs) {
    // Past a's last digit the pair's upper digit is 0, mapped to perm[0] as
    // the reference maps it.
    for (; k >= 2 && a32 != 0; k -= 2) {
      uint32_t next = div_by_reciprocal(dim.recip2, a32);
      reversed = reversed * dim.base2 + dim.pairs[a32 - next * dim.base2];
      a32 = next;
    }
  }
  for (; k > 0 && a32 != 0; --k) {
    uint32_t next = div_by_reciprocal(dim.recip, a32);
    reversed = reversed * base + perm[a32 - next * base];
    a32 = next;
  }
  // The remaining k digits of a are zeros, each mapped to perm[0].
  reversed = reversed * dim.pow[k] + dim.fill[k];
  return dim.scale * (double(reversed) + dim.tail);
}

}  // namespace rt
