// Per-pixel point sets (pbrt book 3rd ed., sections 7.3 and 7.4.3).
#include "runtime/sampler/sample_patterns.h"

#include <algorithm>
#include <utility>

namespace rt {
namespace {

float below_one(float v) {
  return std::min(v, kOneMinusEpsilon);
}

// Generator matrix columns (MSB-aligned) of the two (0,2)-sequence dimensions:
// van der Corput (the identity, reversed) and Sobol's second dimension, whose
// matrix is Pascal's triangle mod 2 (each column is the previous one xor
// itself shifted right by one).
struct ZeroTwoMatrices {
  uint32_t vdc[32], sobol[32];
  ZeroTwoMatrices() {
    for (int k = 0; k < 32; ++k) vdc[k] = 1u << (31 - k);
    sobol[0] = 1u << 31;
    for (int k = 1; k < 32; ++k) sobol[k] = sobol[k - 1] ^ (sobol[k - 1] >> 1);
  }
};
const ZeroTwoMatrices& zero_two_matrices() {
  static const ZeroTwoMatrices m;
  return m;
}

// Consecutive points of a digital sequence differ in one column per step
// when enumerated in Gray-code order, so each costs one xor. The set of the
// first 2^k points is the same as in natural order.
int gray_code_column(uint32_t i) {
  return __builtin_ctz(i + 1);
}

}  // namespace

void stratified_1d(float* out, int n, Rng& rng, bool jitter) {
  float inv = 1.f / float(n);
  for (int i = 0; i < n; ++i) {
    float delta = jitter ? rng.next_float() : 0.5f;
    out[i] = below_one((float(i) + delta) * inv);
  }
}

void stratified_2d(Vec2* out, int nx, int ny, Rng& rng, bool jitter) {
  float dx = 1.f / float(nx), dy = 1.f / float(ny);
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      float jx = jitter ? rng.next_float() : 0.5f;
      float jy = jitter ? rng.next_float() : 0.5f;
      *out++ = {below_one((float(x) + jx) * dx), below_one((float(y) + jy) * dy)};
    }
}

void latin_hypercube(float* out, int n, int dims, Rng& rng) {
  float inv = 1.f / float(n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < dims; ++j)
      out[dims * i + j] = below_one((float(i) + rng.next_float()) * inv);
  // Permuting each axis independently keeps one value per stratum per axis
  // while decorrelating the axes.
  for (int j = 0; j < dims; ++j)
    for (int i = 0; i < n; ++i) {
      int other = i + int(rng.next_u32(uint32_t(n - i)));
      std::swap(out[dims * i + j], out[dims * other + j]);
    }
}

void shuffle_blocks(float* data, int count, int block, Rng& rng) {
  for (int i = 0; i < count; ++i) {
    int other = i + int(rng.next_u32(uint32_t(count - i)));
    for (int j = 0; j < block; ++j) std::swap(data[block * i + j], data[block * other + j]);
  }
}

void shuffle_points(Vec2* data, int count, int block, Rng& rng) {
  for (int i = 0; i < count; ++i) {
    int other = i + int(rng.next_u32(uint32_t(count - i)));
    for (int j = 0; j < block; ++j) std::swap(data[block * i + j], data[block * other + j]);
  }
}

namespace {
// Each sample's own n_per_sample values shuffled (shuffle(i) for every sample i). A sample of
// one value (the samplers' dimensions) stays as it is, yet its shuffle draws one value in
// [0, 1), which Rng::next_u32(1) never redraws: the generator only steps once per sample.
template <typename Shuffle>
void shuffle_within_samples(int n_per_sample, int n_samples, Rng& rng, Shuffle&& shuffle) {
  if (n_per_sample == 1) {
    rng.advance(n_samples);
    return;
  }
  for (int i = 0; i < n_samples; ++i) shuffle(i);
}
}  // namespace

void van_der_corput_pattern(int n_per_sample, int n_samples, float* out, Rng& rng) {
  const uint32_t* c = zero_two_matrices().vdc;
  uint32_t v = rng.next_u32();  // random xor scramble
  int total = n_per_sample * n_samples;
  for (int i = 0; i < total; ++i) {
    out[i] = below_one(float(v) * 0x1p-32f);
    v ^= c[gray_code_column(uint32_t(i))];
  }
  shuffle_within_samples(n_per_sample, n_samples, rng, [&](int i) {
    shuffle_blocks(out + i * n_per_sample, n_per_sample, 1, rng);
  });
  shuffle_blocks(out, n_samples, n_per_sample, rng);
}

void sobol_2d_pattern(int n_per_sample, int n_samples, Vec2* out, Rng& rng) {
  const ZeroTwoMatrices& m = zero_two_matrices();
  uint32_t vx = rng.next_u32(), vy = rng.next_u32();
  int total = n_per_sample * n_samples;
  for (int i = 0; i < total; ++i) {
    out[i] = {below_one(float(vx) * 0x1p-32f), below_one(float(vy) * 0x1p-32f)};
    int col = gray_code_column(uint32_t(i));
    vx ^= m.vdc[col];
    vy ^= m.sobol[col];
  }
  shuffle_within_samples(n_per_sample, n_samples, rng, [&](int i) {
    shuffle_points(out + i * n_per_sample, n_per_sample, 1, rng);
  });
  shuffle_points(out, n_samples, n_per_sample, rng);
}

}  // namespace rt
