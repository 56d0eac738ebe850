// pbrt-v3's HaltonSampler (pbrt book 3rd ed., section 7.4): one Halton
// sequence over the image. The first two dimensions (bases 2 and 3) are
// scaled so that every pixel of a 128x128 tile owns one residue class of
// indices; the index of a pixel's sample i follows from the Chinese remainder
// theorem, and those dimensions' remaining digits give the point inside the
// pixel. Higher dimensions are digit-scrambled radical inverses.
#include <memory>

#include "runtime/sampler/global_sampler.h"
#include "runtime/sampler/pixel_seed.h"
#include "runtime/sampler/radical_inverse.h"
#include "runtime/sampler/sampler_kinds.h"

namespace rt {
namespace {

constexpr int kMaxResolution = 128;  // the pixel pattern repeats past this, as in pbrt-v3

// x with a * x = 1 (mod n), by the extended Euclidean algorithm.
int64_t multiplicative_inverse(int64_t a, int64_t n) {
  int64_t r0 = n, r1 = a % n, s0 = 0, s1 = 1;
  while (r1 != 0) {
    int64_t q = r0 / r1;
    int64_t r = r0 - q * r1;
    r0 = r1;
    r1 = r;
    int64_t s = s0 - q * s1;
    s0 = s1;
    s1 = s;
  }
  int64_t x = s0 % n;
  return x < 0 ? x + n : x;
}

int positive_mod(int a, int b) {
  int r = a % b;
  return r < 0 ? r + b : r;
}

class HaltonSampler final : public GlobalSampler {
 public:
  HaltonSampler(int64_t spp, uint64_t seed, const Bounds2i& bounds, bool center)
      : GlobalSampler(spp),
        seed_(seed),
        center_(center),
        permutations_(std::make_shared<const DigitPermutations>(seed)) {
    int extent[2] = {bounds.width(), bounds.height()};
    for (int i = 0; i < 2; ++i) {
      int base = i == 0 ? 2 : 3, scale = 1, exponent = 0;
      while (scale < std::min(extent[i], kMaxResolution)) {
        scale *= base;
        ++exponent;
      }
      base_scales_[i] = scale;
      base_exponents_[i] = exponent;
    }
    stride_ = int64_t(base_scales_[0]) * base_scales_[1];
    mult_inverse_[0] = multiplicative_inverse(base_scales_[1], base_scales_[0]);
    mult_inverse_[1] = multiplicative_inverse(base_scales_[0], base_scales_[1]);
  }
  HaltonSampler(const HaltonSampler&) = default;

  std::unique_ptr<Sampler> clone() const override { return std::make_unique<HaltonSampler>(*this); }

  void start_pixel(Point2i p) override {
    // The first digits of dims 0 and 1 must name p (mod the tile): the index
    // is found digit-inverted per base and combined by CRT.
    pixel_offset_ = 0;
    if (stride_ > 1) {
      int pm[2] = {positive_mod(p.x, kMaxResolution), positive_mod(p.y, kMaxResolution)};
      for (int i = 0; i < 2; ++i) {
        uint64_t dim_offset =
            inverse_radical_inverse(i == 0 ? 2 : 3, uint64_t(pm[i]), base_exponents_[i]);
        pixel_offset_ += int64_t(dim_offset % uint64_t(base_scales_[i])) *
                         (stride_ / base_scales_[i]) % stride_ * mult_inverse_[i];
        pixel_offset_ %= stride_;
      }
    }
    GlobalSampler::start_pixel(p);
  }

 protected:
  int64_t index_for_sample(int64_t n) override { return pixel_offset_ + n * stride_; }

  float sample_dimension(int64_t index, int dim) const override { return value(index, dim); }

 public:
  // GlobalSampler's bookkeeping, with the sequence values computed without a
  // virtual call (these run for every dimension of every sample).
  float get_1d() override {
    if (dimension_ >= kArrayStartDim && dimension_ < array_end_dim_) dimension_ = array_end_dim_;
    return value(interval_index_, dimension_++);
  }
  Vec2 get_2d() override {
    if (dimension_ + 1 >= kArrayStartDim && dimension_ < array_end_dim_)
      dimension_ = array_end_dim_;
    Vec2 p{value(interval_index_, dimension_), value(interval_index_, dimension_ + 1)};
    dimension_ += 2;
    return p;
  }

 private:
  float value(int64_t index, int dim) const {
    if (center_ && dim < 2) return 0.5f;
    double v;
    if (dim == 0)
      v = radical_inverse(2, uint64_t(index) >> base_exponents_[0]);
    else if (dim == 1)
      v = radical_inverse(3, uint64_t(index) / uint64_t(base_scales_[1]));
    else if (dim < kHaltonDimensions)
      v = permutations_->scrambled(dim, uint64_t(index));
    else
      return hashed_uniform(seed_, pixel_, uint64_t(index), uint64_t(dim));
    return std::min(float(v), kOneMinusEpsilon);
  }

 private:
  uint64_t seed_;
  bool center_;
  std::shared_ptr<const DigitPermutations> permutations_;  // shared by clones
  int base_scales_[2], base_exponents_[2];
  int64_t stride_, mult_inverse_[2];
  int64_t pixel_offset_ = 0;
};

}  // namespace

std::unique_ptr<Sampler> make_halton_sampler(int64_t spp, uint64_t seed, const Bounds2i& bounds,
                                             bool sample_pixel_center) {
  return std::make_unique<HaltonSampler>(spp, seed, bounds, sample_pixel_center);
}

}  // namespace rt
