// runtime/sampler/pixel_sampler.h — pbrt-v3's PixelSampler: the first
// `dimensions` 1-D and 2-D dimensions of every sample of a pixel are generated
// together at start_pixel() (so they can be stratified across the pixel's
// samples); later dimensions are independent uniform values.
//
// Subclasses fill dims_1d_/dims_2d_ (spp values each) in start_pixel(), drawing
// from pixel_rng (seeded from (seed, pixel) only), and each requested array when
// it is first handed out in the pixel (fill_*_array), from its own array_rng.
// Past the precomputed dimensions, values come from a generator reseeded from
// (seed, pixel, sample) at every sample start, so they never depend on what
// earlier samples consumed.
#pragma once

#include "runtime/core/rng.h"
#include "runtime/sampler/sampler.h"

namespace rt {

class PixelSampler : public Sampler {
 public:
  void start_pixel(Point2i p) override;
  bool set_sample_number(int64_t n) override;
  float get_1d() override;
  Vec2 get_2d() override;
  bool whole_count_patterns() const override { return true; }

 protected:
  PixelSampler(int64_t spp, int dimensions, uint64_t seed);
  PixelSampler(const PixelSampler&) = default;

  uint64_t seed_;
  std::vector<std::vector<float>> dims_1d_;
  std::vector<std::vector<Vec2>> dims_2d_;
  size_t next_dim_1d_ = 0, next_dim_2d_ = 0;
  Rng pixel_rng_;   // for the subclass's start_pixel() patterns
  Rng sample_rng_;  // values past the precomputed dimensions
};

// A pixel sampler whose counts are powers of two and whose requested arrays are scrambled,
// shuffled (0,2)-sequence patterns (pbrt-v3's ZeroTwoSequenceSampler and MaxMinDistSampler).
class ZeroTwoArraysSampler : public PixelSampler {
 public:
  int round_count(int n) const override;

 protected:
  using PixelSampler::PixelSampler;
  void fill_1d_array(size_t i) override;
  void fill_2d_array(size_t i) override;
};

}  // namespace rt
