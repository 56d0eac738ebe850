// pbrt-v3's RandomSampler: independent uniform values in every dimension and
// array (the baseline the other samplers improve on).
#include <memory>

#include "runtime/core/rng.h"
#include "runtime/sampler/pixel_seed.h"
#include "runtime/sampler/sampler_kinds.h"

namespace rt {
namespace {

class RandomSampler final : public Sampler {
 public:
  RandomSampler(int64_t spp, uint64_t seed) : Sampler(spp), seed_(seed) {}
  RandomSampler(const RandomSampler&) = default;

  std::unique_ptr<Sampler> clone() const override { return std::make_unique<RandomSampler>(*this); }

  void start_pixel(Point2i p) override {
    Sampler::start_pixel(p);
    rng_ = sample_rng(seed_, p, first_);
  }

  bool set_sample_number(int64_t n) override {
    rng_ = sample_rng(seed_, pixel_, n);
    return Sampler::set_sample_number(n);
  }

  float get_1d() override { return rng_.next_float(); }
  Vec2 get_2d() override {
    float x = rng_.next_float();
    return {x, rng_.next_float()};
  }

 protected:
  // Each sample's array from its own generator, so a pass fills only its samples.
  void fill_1d_array(size_t i) override {
    const size_t n = size_t(sizes_1d_[i]);
    for (int64_t s = first_; s < end_; ++s) {
      Rng rng = array_rng(seed_, pixel_, 1, i, s);
      for (size_t j = 0; j < n; ++j) arrays_1d_[i][size_t(s) * n + j] = rng.next_float();
    }
  }
  void fill_2d_array(size_t i) override {
    const size_t n = size_t(sizes_2d_[i]);
    for (int64_t s = first_; s < end_; ++s) {
      Rng rng = array_rng(seed_, pixel_, 2, i, s);
      for (size_t j = 0; j < n; ++j) {
        Vec2& v = arrays_2d_[i][size_t(s) * n + j];
        v.x = rng.next_float();
        v.y = rng.next_float();
      }
    }
  }

 private:
  uint64_t seed_;
  Rng rng_;
};

}  // namespace

std::unique_ptr<Sampler> make_random_sampler(int64_t spp, uint64_t seed) {
  return std::make_unique<RandomSampler>(spp, seed);
}

}  // namespace rt
