// runtime/sampler/sobol_matrices.h — Sobol' generator matrices (Joe & Kuo's
// direction numbers) and the inversion pbrt-v3's SobolSampler needs: the
// sequence index of the frame-th point that falls in a given pixel.
//
// A Sobol' point's coordinate d is the xor of the matrix columns selected by
// the index bits (32-bit fixed point, most significant bit first).
#pragma once

#include <cstdint>

namespace rt {

inline constexpr int kSobolDimensions = 128;  // dimension 0 is van der Corput
inline constexpr int kSobolColumns = 64;      // one per bit of a 64-bit index

// The kSobolColumns columns of dimension d's generator matrix.
const uint32_t* sobol_columns(int d);

// Dimension d's columns four at a time: entry [j * 16 + x] is the xor of
// columns 4j..4j+3 selected by the bits of x (so a lookup per index nibble,
// with no branch per index bit, gives the same xor). Dimension d's table is
// sobol_nibble_table(0) + d * kSobolNibbleTable.
inline constexpr int kSobolNibbleTable = kSobolColumns / 4 * 16;
const uint32_t* sobol_nibble_table(int d);

// Coordinate of point `index` from a dimension's nibble table, as 32 fraction bits.
inline uint32_t sobol_bits(uint64_t index, const uint32_t* nibbles) {
  uint32_t v = 0;
  for (; index; index >>= 4, nibbles += 16) v ^= nibbles[index & 15];
  return v;
}

// Coordinate d of point `index`, as 32 fraction bits.
inline uint32_t sobol_bits(uint64_t index, int d) {
  return sobol_bits(index, sobol_nibble_table(d));
}

// For an image of 2^m x 2^m pixels: every block of 4^m consecutive points of
// dims (0, 1) has exactly one point in each pixel (the (0,2)-sequence
// property). index(frame, x, y) is the index of the one in pixel (x, y) from
// block `frame`, i.e. top m bits of dim 0 == x and of dim 1 == y.
class SobolPixelIndexer {
 public:
  explicit SobolPixelIndexer(int m);
  uint64_t index(uint64_t frame, uint32_t x, uint32_t y) const;
  int log2_resolution() const { return m_; }

 private:
  int m_;
  // solve_[b]: index bits m..2m-1 that flip only bit b of dim 1's top m bits.
  uint32_t solve_[32] = {};
};

}  // namespace rt
