// pbrt-v3's HaltonSampler (pbrt book 3rd ed., section 7.4): one Halton
// sequence over the image. The first two dimensions (bases 2 and 3) are
// scaled so that every pixel of a 128x128 tile owns one residue class of
// indices; the index of a pixel's sample i follows from the Chinese remainder
// theorem, and those dimensions' remaining digits give the point inside the
// pixel. Higher dimensions are digit-scrambled radical inverses.
//
// Seeds: the scrambles of the higher dimensions follow the seed; the pixel
// dimensions do not in pbrt-v3 (they name the pixel). With a seed other than
// 0, the in-pixel positions (dimensions 0 and 1, the digits past the ones
// naming the pixel) get a random digital shift from the seed (each of the
// first digits plus a random digit, mod the base): every stratum a pixel's
// samples fill stays filled, and renders with different seeds get independent
// positions, so two of them measure the noise positions cause (edges, texture
// detail), which the convergence test and the error sweeps rely on. Not the
// digit permutations of the higher dimensions: a permutation that moves digit
// 0 gives every value an infinite tail of nonzero digits, which puts points
// exactly on stratum boundaries. Seed 0 keeps pbrt-v3's positions exactly.
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
    Rng rng(mix_seed(seed, SeedPurpose::kGlobalTable, 0x4a170));
    shift2_ = rng.next_u32();
    for (uint8_t& d : shift3_) d = uint8_t(rng.next_u32() % 3);
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
      const uint64_t dim_offsets[2] = {
          inverse_radical_inverse<2>(uint64_t(positive_mod(p.x, kMaxResolution)),
                                     base_exponents_[0]),
          inverse_radical_inverse<3>(uint64_t(positive_mod(p.y, kMaxResolution)),
                                     base_exponents_[1])};
      for (int i = 0; i < 2; ++i) {
        pixel_offset_ += int64_t(dim_offsets[i] % uint64_t(base_scales_[i])) *
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
  float get_1d() override { return value(interval_index_, next_dimension_1d()); }
  Vec2 get_2d() override {
    const int d = next_dimension_2d();
    return {value(interval_index_, d), value(interval_index_, d + 1)};
  }

 private:
  float value(int64_t index, int dim) const {
    if (center_ && dim < 2) return 0.5f;
    double v;
    if (dim < 2) {
      const uint64_t digits = dim == 0 ? uint64_t(index) >> base_exponents_[0]
                                       : uint64_t(index) / uint64_t(base_scales_[1]);
      v = seed_ == 0 ? radical_inverse(dim == 0 ? 2 : 3, digits)
                     : (dim == 0 ? shifted_base2(digits) : shifted_base3(digits));
    } else if (dim < kHaltonDimensions)
      v = permutations_->scrambled(dim, uint64_t(index));
    else
      return hashed_uniform(seed_, pixel_, uint64_t(index), uint64_t(dim));
    return std::min(float(v), kOneMinusEpsilon);
  }

  // The radical inverse of q's digits, each of the first ones shifted by the
  // seed's digit (base 2: xor; base 3: added mod 3). Digits past those are
  // below float precision.
  double shifted_base2(uint64_t q) const {
    return double(reverse_bits(q) ^ (uint64_t(shift2_) << 32)) * 0x1p-64;
  }
  double shifted_base3(uint64_t q) const {
    double v = 0, scale = 1.0 / 3;
    for (int i = 0; i < kBase3Digits; ++i, scale /= 3) {
      const uint64_t next = q / 3;
      v += double((uint32_t(q - 3 * next) + shift3_[i]) % 3) * scale;
      q = next;
    }
    return v;
  }

 private:
  static constexpr int kBase3Digits = 21;  // 3^-21 < 2^-33
  uint32_t shift2_ = 0;
  uint8_t shift3_[kBase3Digits] = {};
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
