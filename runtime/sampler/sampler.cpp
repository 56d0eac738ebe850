// The bookkeeping all samplers share: the current pixel and sample, and the
// requested sample arrays handed out in request order (pbrt-v3's Sampler).
#include "runtime/sampler/sampler.h"

#include <algorithm>

namespace rt {

void Sampler::start_pixel(Point2i p) {
  pixel_ = p;
  ++pixel_serial_;
  sample_index_ = first_;
  next_1d_array_ = next_2d_array_ = 0;
}

bool Sampler::start_next_sample() {
  return set_sample_number(sample_index_ + 1) && sample_index_ < end_;
}

void Sampler::set_sample_range(int64_t first, int64_t end) {
  first_ = std::clamp<int64_t>(first, 0, spp_);
  end_ = std::clamp<int64_t>(end, first_, spp_);
}

bool Sampler::set_sample_number(int64_t n) {
  next_1d_array_ = next_2d_array_ = 0;
  sample_index_ = n;
  return sample_index_ < spp_;
}

bool Sampler::first_read(uint64_t* filled_at) const {
  if (*filled_at == pixel_serial_) return false;
  *filled_at = pixel_serial_;
  return true;
}

void Sampler::request_1d_array(int n) {
  sizes_1d_.push_back(n);
  arrays_1d_.emplace_back(size_t(n) * size_t(spp_));
  filled_1d_.push_back(0);
}

void Sampler::request_2d_array(int n) {
  sizes_2d_.push_back(n);
  arrays_2d_.emplace_back(size_t(n) * size_t(spp_));
  filled_2d_.push_back(0);
}

const float* Sampler::get_1d_array(int n) {
  if (next_1d_array_ == arrays_1d_.size() || sample_index_ >= spp_) return nullptr;
  if (sizes_1d_[next_1d_array_] != n) return nullptr;  // asked out of request order
  if (first_read(&filled_1d_[next_1d_array_])) fill_1d_array(next_1d_array_);
  return &arrays_1d_[next_1d_array_++][size_t(sample_index_) * size_t(n)];
}

const Vec2* Sampler::get_2d_array(int n) {
  if (next_2d_array_ == arrays_2d_.size() || sample_index_ >= spp_) return nullptr;
  if (sizes_2d_[next_2d_array_] != n) return nullptr;
  if (first_read(&filled_2d_[next_2d_array_])) fill_2d_array(next_2d_array_);
  return &arrays_2d_[next_2d_array_++][size_t(sample_index_) * size_t(n)];
}

}  // namespace rt
