// pbrt-v3's GlobalSampler bookkeeping (pbrt book 3rd ed., section 7.2.5).
#include "runtime/sampler/global_sampler.h"

namespace rt {

void GlobalSampler::start_pixel(Point2i p) {
  Sampler::start_pixel(p);
  dimension_ = 0;
  interval_index_ = index_for_sample(first_);
  array_end_dim_ = kArrayStartDim + int(sizes_1d_.size()) + 2 * int(sizes_2d_.size());
}

void GlobalSampler::fill_1d_array(size_t i) {
  const int64_t n = sizes_1d_[i];
  for (int64_t j = first_ * n; j < end_ * n; ++j)
    arrays_1d_[i][size_t(j)] = sample_dimension(index_for_sample(j), kArrayStartDim + int(i));
}

void GlobalSampler::fill_2d_array(size_t i) {
  const int64_t n = sizes_2d_[i];
  const int dim = kArrayStartDim + int(sizes_1d_.size()) + 2 * int(i);
  for (int64_t j = first_ * n; j < end_ * n; ++j) {
    const int64_t index = index_for_sample(j);
    arrays_2d_[i][size_t(j)] = {sample_dimension(index, dim), sample_dimension(index, dim + 1)};
  }
}

bool GlobalSampler::set_sample_number(int64_t n) {
  dimension_ = 0;
  interval_index_ = index_for_sample(n);
  return Sampler::set_sample_number(n);
}

float GlobalSampler::get_1d() {
  return sample_dimension(interval_index_, next_dimension_1d());
}

Vec2 GlobalSampler::get_2d() {
  const int d = next_dimension_2d();
  return {sample_dimension(interval_index_, d), sample_dimension(interval_index_, d + 1)};
}

}  // namespace rt
