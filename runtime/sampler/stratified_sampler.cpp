// pbrt-v3's StratifiedSampler (pbrt book 3rd ed., section 7.3): each of the
// first `dimensions` dimensions is a jittered stratification over the
// pixel's xsamples * ysamples samples, shuffled per dimension so dimensions do
// not correlate; the 2-D arrays are Latin hypercubes (any count works).
#include <memory>

#include "runtime/sampler/pixel_sampler.h"
#include "runtime/sampler/pixel_seed.h"
#include "runtime/sampler/sample_patterns.h"
#include "runtime/sampler/sampler_kinds.h"

namespace rt {
namespace {

class StratifiedSampler final : public PixelSampler {
 public:
  StratifiedSampler(int xsamples, int ysamples, bool jitter, int dimensions, uint64_t seed)
      : PixelSampler(int64_t(xsamples) * ysamples, dimensions, seed),
        xsamples_(xsamples),
        ysamples_(ysamples),
        jitter_(jitter) {}
  StratifiedSampler(const StratifiedSampler&) = default;

  std::unique_ptr<Sampler> clone() const override {
    return std::make_unique<StratifiedSampler>(*this);
  }

  void start_pixel(Point2i p) override {
    pixel_rng_ = pixel_rng(seed_, p);
    int spp = int(spp_);
    for (auto& d : dims_1d_) {
      stratified_1d(d.data(), spp, pixel_rng_, jitter_);
      shuffle_blocks(d.data(), spp, 1, pixel_rng_);
    }
    for (auto& d : dims_2d_) {
      stratified_2d(d.data(), xsamples_, ysamples_, pixel_rng_, jitter_);
      shuffle_points(d.data(), spp, 1, pixel_rng_);
    }
    PixelSampler::start_pixel(p);
  }

 protected:
  void fill_1d_array(size_t i) override {
    Rng rng = array_rng(seed_, pixel_, 1, i);
    const int n = sizes_1d_[i];
    for (int64_t s = 0; s < spp_; ++s) {
      float* a = &arrays_1d_[i][size_t(s) * size_t(n)];
      stratified_1d(a, n, rng, jitter_);
      shuffle_blocks(a, n, 1, rng);
    }
  }
  void fill_2d_array(size_t i) override {
    Rng rng = array_rng(seed_, pixel_, 2, i);
    const int n = sizes_2d_[i];
    for (int64_t s = 0; s < spp_; ++s)
      latin_hypercube(&arrays_2d_[i][size_t(s) * size_t(n)].x, n, 2, rng);
  }

 private:
  int xsamples_, ysamples_;
  bool jitter_;
};

}  // namespace

std::unique_ptr<Sampler> make_stratified_sampler(int xsamples, int ysamples, bool jitter,
                                                 int dimensions, uint64_t seed) {
  return std::make_unique<StratifiedSampler>(xsamples, ysamples, jitter, dimensions, seed);
}

}  // namespace rt
