// pbrt-v3's PixelSampler bookkeeping, with per-pixel / per-sample seeding.
#include "runtime/sampler/pixel_sampler.h"

#include <algorithm>

#include "runtime/sampler/pixel_seed.h"
#include "runtime/sampler/sample_patterns.h"

namespace rt {

PixelSampler::PixelSampler(int64_t spp, int dimensions, uint64_t seed) : Sampler(spp), seed_(seed) {
  dims_1d_.assign(size_t(std::max(dimensions, 0)), std::vector<float>(size_t(spp)));
  dims_2d_.assign(size_t(std::max(dimensions, 0)), std::vector<Vec2>(size_t(spp)));
}

void PixelSampler::start_pixel(Point2i p) {
  Sampler::start_pixel(p);
  next_dim_1d_ = next_dim_2d_ = 0;
  sample_rng_ = sample_rng(seed_, p, first_);
}

bool PixelSampler::set_sample_number(int64_t n) {
  next_dim_1d_ = next_dim_2d_ = 0;
  sample_rng_ = sample_rng(seed_, pixel_, n);
  return Sampler::set_sample_number(n);
}

float PixelSampler::get_1d() {
  if (next_dim_1d_ < dims_1d_.size() && sample_index_ < spp_)
    return dims_1d_[next_dim_1d_++][size_t(sample_index_)];
  return sample_rng_.next_float();
}

int ZeroTwoArraysSampler::round_count(int n) const {
  return int(round_up_pow2(uint32_t(std::max(n, 1))));
}

void ZeroTwoArraysSampler::fill_1d_array(size_t i) {
  Rng rng = array_rng(seed_, pixel_, 1, i);
  van_der_corput_pattern(sizes_1d_[i], int(spp_), arrays_1d_[i].data(), rng);
}

void ZeroTwoArraysSampler::fill_2d_array(size_t i) {
  Rng rng = array_rng(seed_, pixel_, 2, i);
  sobol_2d_pattern(sizes_2d_[i], int(spp_), arrays_2d_[i].data(), rng);
}

Vec2 PixelSampler::get_2d() {
  if (next_dim_2d_ < dims_2d_.size() && sample_index_ < spp_)
    return dims_2d_[next_dim_2d_++][size_t(sample_index_)];
  float x = sample_rng_.next_float();
  return {x, sample_rng_.next_float()};
}

}  // namespace rt
