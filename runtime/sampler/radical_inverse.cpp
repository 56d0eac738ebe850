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

// The generic loop with the base known at compile time, so the division
// becomes a multiplication; the same operations, so the same result.
template <uint32_t kBase>
double radical_inverse_in(uint64_t a) {
  const double inv_base = 1.0 / kBase;
  uint64_t reversed = 0;
  double inv_base_n = 1;
  while (a > 0xffffffffull) {
    uint64_t next = a / kBase;
    reversed = reversed * kBase + (a - next * kBase);
    inv_base_n *= inv_base;
    a = next;
  }
  // The rest in 32 bits, where the division by a constant is cheaper.
  for (uint32_t a32 = uint32_t(a); a32;) {
    uint32_t next = a32 / kBase;
    reversed = reversed * kBase + (a32 - next * kBase);
    inv_base_n *= inv_base;
    a32 = next;
  }
  return double(reversed) * inv_base_n;
}

// Bases up to this have a table of digit pairs (61^2 entries fit in 16 bits).
constexpr uint32_t kMaxPairBase = 61;

inline uint32_t div_by_reciprocal(uint64_t recip, uint32_t a) {
  return uint32_t((static_cast<unsigned __int128>(recip) * a) >> 64);
}

}  // namespace

double radical_inverse(uint32_t base, uint64_t a) {
  if (base == 2) {
    // Mirroring binary digits is a bit reversal.
    return double(reverse_bits(a)) * 0x1p-64;
  }
  if (base == 3) return radical_inverse_in<3>(a);  // Halton's second dimension
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

DigitPermutations::DigitPermutations(uint64_t seed)
    : seed_(seed),
      dims_(new Dimension[size_t(kHaltonDimensions)]),
      made_(new Made[size_t(kHaltonDimensions)]) {
  std::vector<size_t> pow_at(static_cast<size_t>(kHaltonDimensions));
  for (int d = 0; d < kHaltonDimensions; ++d) {
    Dimension& dim = dims_[size_t(d)];
    dim.base = halton_prime(d);
    dim.recip = ~uint64_t(0) / dim.base + 1;
    dim.base2 = dim.base * dim.base;
    dim.recip2 = ~uint64_t(0) / dim.base2 + 1;
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
