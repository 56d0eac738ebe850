// runtime/render/mlt_sampler.cpp — see mlt_sampler.h.
#include "runtime/render/mlt_sampler.h"

#include <algorithm>
#include <cmath>

#include "runtime/core/normal_sample.h"

namespace rt {

MltSampler::MltSampler(int64_t mutations_per_pixel, uint64_t rng_index, float sigma,
                       float large_step_probability, int streams, uint64_t seed)
    : Sampler(mutations_per_pixel),
      rng_(seed, rng_index),
      seed_(seed),
      sigma_(sigma),
      large_step_probability_(large_step_probability),
      streams_(streams) {}

void MltSampler::restart(uint64_t rng_index) {
  rng_ = Rng(seed_, rng_index);
  x_.clear();
  iteration_ = last_large_step_ = 0;
  large_step_ = true;
  stream_ = 0;
  index_in_stream_ = 0;
}

std::unique_ptr<Sampler> MltSampler::clone() const {
  return std::make_unique<MltSampler>(*this);
}

void MltSampler::start_iteration() {
  ++iteration_;
  large_step_ = rng_.next_float() < large_step_probability_;
}

void MltSampler::accept() {
  if (large_step_) last_large_step_ = iteration_;
}

void MltSampler::reject() {
  for (PrimarySample& x : x_)
    if (x.last_modified == iteration_) {
      x.value = x.value_backup;
      x.last_modified = x.modify_backup;
    }
  --iteration_;
}

void MltSampler::start_stream(int index) {
  stream_ = index;
  index_in_stream_ = 0;
}

void MltSampler::ensure_ready(size_t index) {
  if (index >= x_.size()) x_.resize(index + 1);
  PrimarySample& x = x_[index];
  // A coordinate untouched since before the last accepted large step takes that step's value.
  if (x.last_modified < last_large_step_) {
    x.value = rng_.next_float();
    x.last_modified = last_large_step_;
  }
  x.value_backup = x.value;
  x.modify_backup = x.last_modified;
  if (large_step_) {
    x.value = rng_.next_float();
  } else {
    // The small steps it missed, as one: their normal offsets add up in variance.
    const int64_t steps = iteration_ - x.last_modified;
    const float normal = normal_sample(rng_);
    x.value += normal * sigma_ * std::sqrt(float(steps));
    x.value -= std::floor(x.value);
    x.value = std::min(x.value, kOneMinusEpsilon);  // -1e-9 wraps to 1 in float
  }
  x.last_modified = iteration_;
}

float MltSampler::get_1d() {
  const size_t index = size_t(stream_ + streams_ * index_in_stream_++);
  ensure_ready(index);
  return x_[index].value;
}

Vec2 MltSampler::get_2d() {
  float a = get_1d();
  return {a, get_1d()};
}

}  // namespace rt
