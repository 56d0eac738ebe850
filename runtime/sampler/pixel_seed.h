// runtime/sampler/pixel_seed.h — seeds and hashed values derived only from
// (scene seed, pixel, sample, dimension).
//
// Every random choice a sampler makes goes through these, which is what makes
// a pixel's samples independent of the thread and tile that render it.
#pragma once

#include <cstdint>

#include "runtime/core/math.h"
#include "runtime/core/rng.h"
#include "runtime/core/vec.h"

namespace rt {

// Distinct purposes keep the streams of one pixel apart.
enum class SeedPurpose : uint64_t {
  kPixelPattern = 1,  // a pixel's precomputed dimensions and arrays
  kPerSample = 2,     // values past the precomputed dimensions
  kGlobalTable = 3,   // sampler-wide scrambles and permutations
  kHashedDim = 4,     // global samplers past their tables
  kArrayPattern = 6,  // a pixel sampler's requested arrays, one stream per array
};

inline uint64_t pixel_key(Point2i p) {
  return (uint64_t(uint32_t(p.x)) << 32) | uint64_t(uint32_t(p.y));
}

inline uint64_t mix_seed(uint64_t seed, SeedPurpose purpose, uint64_t a = 0, uint64_t b = 0) {
  uint64_t h = mix_bits(seed + 0x9e3779b97f4a7c15ull * (uint64_t(purpose) + 1));
  h = mix_bits(h ^ a);
  return mix_bits(h ^ mix_bits(b + 0x632be59bd9b4e019ull));
}

inline Rng pixel_rng(uint64_t seed, Point2i p) {
  return Rng(mix_seed(seed, SeedPurpose::kPixelPattern, pixel_key(p)));
}

// The generator of a requested array's values in pixel p (dims 1 or 2, its index among the
// arrays of that kind, and for the random sampler the sample): one stream per array, so the
// arrays can be made in any order, or not at all.
inline Rng array_rng(uint64_t seed, Point2i p, int dims, size_t array, int64_t sample = 0) {
  return Rng(mix_seed(seed, SeedPurpose::kArrayPattern, pixel_key(p),
                      (uint64_t(array) << 2 | uint64_t(dims)) ^ (uint64_t(sample) << 32)));
}

inline Rng sample_rng(uint64_t seed, Point2i p, int64_t sample) {
  return Rng(mix_seed(seed, SeedPurpose::kPerSample, pixel_key(p), uint64_t(sample)));
}

// A uniform value in [0,1) for one (pixel, global index, dimension): the
// fallback of the global samplers past their tables (unbiased, not stratified).
inline float hashed_uniform(uint64_t seed, Point2i p, uint64_t index, uint64_t dim) {
  uint64_t h = mix_seed(seed, SeedPurpose::kHashedDim, pixel_key(p) ^ mix_bits(dim + 1), index);
  return std::min(kOneMinusEpsilon, float(uint32_t(h >> 32)) * 0x1p-32f);
}

}  // namespace rt
