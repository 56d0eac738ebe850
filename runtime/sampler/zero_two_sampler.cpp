// pbrt-v3's ZeroTwoSequenceSampler (pbrt book 3rd ed., section 7.5): each of
// the first `dimensions` 1-D and 2-D dimensions of a pixel's samples is a
// freshly scrambled (0,2)-sequence (van der Corput for 1-D), shuffled across
// the pixel's samples so dimensions do not correlate. Counts are powers of
// two, so each pixel's set is a full (0,2)-net.
#include <memory>

#include "runtime/sampler/pixel_sampler.h"
#include "runtime/sampler/pixel_seed.h"
#include "runtime/sampler/sample_patterns.h"
#include "runtime/sampler/sampler_kinds.h"

namespace rt {
namespace {

class ZeroTwoSampler final : public ZeroTwoArraysSampler {
 public:
  ZeroTwoSampler(int64_t spp, int dimensions, uint64_t seed)
      : ZeroTwoArraysSampler(spp, dimensions, seed) {}
  ZeroTwoSampler(const ZeroTwoSampler&) = default;

  std::unique_ptr<Sampler> clone() const override {
    return std::make_unique<ZeroTwoSampler>(*this);
  }

  void start_pixel(Point2i p) override {
    pixel_rng_ = pixel_rng(seed_, p);
    int spp = int(spp_);
    for (auto& d : dims_1d_) van_der_corput_pattern(1, spp, d.data(), pixel_rng_);
    for (auto& d : dims_2d_) sobol_2d_pattern(1, spp, d.data(), pixel_rng_);
    PixelSampler::start_pixel(p);
  }
};

}  // namespace

std::unique_ptr<Sampler> make_zero_two_sampler(int64_t spp, int dimensions, uint64_t seed) {
  return std::make_unique<ZeroTwoSampler>(spp, dimensions, seed);
}

}  // namespace rt
