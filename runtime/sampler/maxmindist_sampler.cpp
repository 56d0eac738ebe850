// pbrt-v3's MaxMinDistSampler (pbrt book 3rd ed., section 7.6): the camera
// dimensions of a pixel's 2^k samples are the points (i / 2^k, C_k i), with
// generator matrices C_k chosen by Grünschloß and Keller to maximise the
// minimum distance between points; the other dimensions are as in the
// (0,2)-sequence sampler.
#include <memory>

#include "runtime/sampler/pixel_sampler.h"
#include "runtime/sampler/pixel_seed.h"
#include "runtime/sampler/sample_patterns.h"
#include "runtime/sampler/sampler_kinds.h"

namespace rt {
namespace {

// The generator matrices C_0..C_16 (columns, bits already reversed so the
// product is the fraction's bits; only the first k columns of C_k are used and
// the rest are 0). Source: L. Grünschloß and A. Keller, "(t, m, s)-Nets and
// Maximized Minimum Distance", Monte Carlo and Quasi-Monte Carlo Methods 2006
// (2008), in the form pbrt-v3 tabulates them (CMaxMinDist, core/lowdiscrepancy.cpp).
// One change: pbrt-v3's C_1 has its only bit in column 31, which no index
// below 2 reaches (both points of a 2-sample pixel get y = 0); here it is in
// column 0, the 1-bit van der Corput matrix.
const uint32_t kMaxMinDist[17][16] = {
    {},
    {0x80000000},
    {0xc0000000, 0x80000000},
    {0xa0000000, 0x40000000, 0x80000000},
    {0xc0000000, 0x50000000, 0x20000000, 0x30000000},
    {0x88000000, 0x58000000, 0x20000000, 0x40000000, 0x80000000},
    {0xe0000000, 0x60000000, 0x28000000, 0x10000000, 0x18000000, 0x04000000},
    {0x82000000, 0x44000000, 0x2c000000, 0x10000000, 0x20000000, 0x40000000, 0x80000000},
    {0x80000000, 0x70000000, 0x30000000, 0x14000000, 0x08000000, 0x0c000000, 0x02000000,
     0x01000000},
    {0xc0000000, 0x41000000, 0x22000000, 0x16000000, 0x08000000, 0x10000000, 0x20000000, 0x40800000,
     0x80000000},
    {0x80000000, 0x40000000, 0x20000000, 0x18000000, 0x08000000, 0x1c000000, 0x1e000000, 0x03000000,
     0x00800000, 0x00400000},
    {0x80000000, 0x60400000, 0x20800000, 0x11000000, 0x0b000000, 0x04000000, 0x08000000, 0x10000000,
     0x20000000, 0x40000000, 0x00200000},
    {0x80000000, 0x40000000, 0x20000000, 0x1c000000, 0x0c000000, 0x05000000, 0x02000000, 0x03000000,
     0x00800000, 0x00400000, 0x00200000, 0x00100000},
    {0x80000000, 0x40000000, 0x30200000, 0x10400000, 0x08800000, 0x05800000, 0x02000000, 0x04000000,
     0x08000000, 0x10000000, 0x20000000, 0x00100000, 0x00080000},
    {0x80000000, 0x40000000, 0x20000000, 0x10000000, 0x0e000000, 0x06000000, 0x02800000, 0x01000000,
     0x01800000, 0x00400000, 0x00200000, 0x00100000, 0x00080000, 0x00040000},
    {0x80000000, 0x40000000, 0x20000000, 0x18100000, 0x08200000, 0x04400000, 0x02c00000, 0x01000000,
     0x02000000, 0x04000000, 0x08000000, 0x10000000, 0x00080000, 0x00040000, 0x00020000},
    {0x80000000, 0x40000000, 0x20000000, 0x10000000, 0x08000000, 0x07000000, 0x03000000, 0x01400000,
     0x00800000, 0x00c00000, 0x00200000, 0x00100000, 0x00080000, 0x00040000, 0x00020000,
     0x00010000},
};

class MaxMinDistSampler final : public ZeroTwoArraysSampler {
 public:
  MaxMinDistSampler(int64_t spp, int dimensions, uint64_t seed)
      : ZeroTwoArraysSampler(spp, dimensions, seed),
        columns_(kMaxMinDist[log2_int(uint32_t(spp))]) {}
  MaxMinDistSampler(const MaxMinDistSampler&) = default;

  std::unique_ptr<Sampler> clone() const override {
    return std::make_unique<MaxMinDistSampler>(*this);
  }

  void start_pixel(Point2i p) override {
    pixel_rng_ = pixel_rng(seed_, p);
    int spp = int(spp_);
    if (!dims_2d_.empty()) {
      float inv = 1.f / float(spp);
      for (int i = 0; i < spp; ++i) {
        uint32_t bits = 0;
        for (uint32_t a = uint32_t(i), k = 0; a; a >>= 1, ++k)
          if (a & 1) bits ^= columns_[k];
        dims_2d_[0][size_t(i)] = {float(i) * inv,
                                  std::min(float(bits) * 0x1p-32f, kOneMinusEpsilon)};
      }
      shuffle_points(dims_2d_[0].data(), spp, 1, pixel_rng_);
    }
    for (auto& d : dims_1d_) van_der_corput_pattern(1, spp, d.data(), pixel_rng_);
    for (size_t i = 1; i < dims_2d_.size(); ++i)
      sobol_2d_pattern(1, spp, dims_2d_[i].data(), pixel_rng_);
    PixelSampler::start_pixel(p);
  }

 private:
  const uint32_t* columns_;
};

}  // namespace

std::unique_ptr<Sampler> make_maxmindist_sampler(int64_t spp, int dimensions, uint64_t seed) {
  return std::make_unique<MaxMinDistSampler>(spp, dimensions, seed);
}

}  // namespace rt
