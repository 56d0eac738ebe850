// runtime/core/rng.h — a small, fast, seedable generator (PCG-XSH-RR 64/32,
// after M. O'Neill's published description of the PCG family).
//
// Each pixel's generator is seeded from (scene seed, pixel), never from the
// thread that happens to render it, so images are identical for any
// --nthreads.
#pragma once

#include <cstdint>

#include "runtime/core/math.h"

namespace rt {

class Rng {
 public:
  Rng() { seed(0, 0x14057b7ef767814full); }
  Rng(uint64_t index, uint64_t stream = 0x14057b7ef767814full) { seed(index, stream); }
  void seed(uint64_t index, uint64_t stream = 0x14057b7ef767814full) {
    state_ = 0;
    inc_ = (stream << 1) | 1;
    next_u32();
    state_ += index;
    next_u32();
  }
  uint32_t next_u32() {
    uint64_t old = state_;
    state_ = old * 0x5851f42d4c957f2dull + inc_;
    uint32_t xorshifted = uint32_t(((old >> 18) ^ old) >> 27);
    uint32_t rot = uint32_t(old >> 59);
    return (xorshifted >> rot) | (xorshifted << ((32 - rot) & 31));
  }
  // Uniform in [0, bound): the high half of r * bound, with r redrawn in the rare case that
  // would favour some values (D. Lemire, "Fast random integer generation in an interval",
  // ACM TOMACS 2019). A division only then: the samplers' shuffles call this once a point.
  uint32_t next_u32(uint32_t bound) {
    uint64_t m = uint64_t(next_u32()) * bound;
    if (uint32_t(m) < bound) {
      const uint32_t threshold = (0u - bound) % bound;
      while (uint32_t(m) < threshold) m = uint64_t(next_u32()) * bound;
    }
    return uint32_t(m >> 32);
  }
  // Uniform in [0, 1).
  float next_float() { return std::min(kOneMinusEpsilon, float(next_u32()) * 0x1p-32f); }
  // Skips ahead (or back) delta steps in O(log delta).
  void advance(int64_t delta) {
    uint64_t cur_mult = 0x5851f42d4c957f2dull, cur_plus = inc_, acc_mult = 1u, acc_plus = 0u;
    uint64_t d = uint64_t(delta);
    while (d > 0) {
      if (d & 1) {
        acc_mult *= cur_mult;
        acc_plus = acc_plus * cur_mult + cur_plus;
      }
      cur_plus = (cur_mult + 1) * cur_plus;
      cur_mult *= cur_mult;
      d /= 2;
    }
    state_ = acc_mult * state_ + acc_plus;
  }

 private:
  uint64_t state_, inc_;
};

}  // namespace rt
