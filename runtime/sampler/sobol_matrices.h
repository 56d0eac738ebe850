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

// Coordinate d of point `index`, as 32 fraction bits.
inline uint32_t sobol_bits(uint64_t index, int d) {
  const uint32_t* c = sobol_columns(d);
  uint32_t v = 0;
  for (int k = 0; index; index >>= 1, ++k)
    if (index & 1) v ^= c[k];
  return v;
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
