// pbrt-v3's SobolSampler (pbrt book 3rd ed., section 7.7): one Sobol'
// sequence over the image, its first two dimensions scaled to a square of
// 2^m x 2^m pixels (m from the larger side of the sample bounds) so each
// pixel's samples are the points that fall in it.
//
// Unlike pbrt-v3 (unscrambled), every dimension gets a seeded random xor
// scramble (a random digital shift: stratification is kept). For dims 0 and 1 the scramble's top m
// bits only relabel which pixel a point block lands in, so the pixel lookup searches for the
// scrambled pixel and the point stays inside its pixel.
#include <memory>
#include <vector>

#include "runtime/sampler/global_sampler.h"
#include "runtime/sampler/pixel_seed.h"
#include "runtime/sampler/sampler_kinds.h"
#include "runtime/sampler/sobol_matrices.h"

namespace rt {
namespace {

struct SobolTables {
  SobolPixelIndexer indexer;
  uint32_t scramble[kSobolDimensions];
  const uint32_t* nibbles = sobol_nibble_table(0);  // all dimensions, one after another
  SobolTables(int m, uint64_t seed) : indexer(m) {
    Rng rng(mix_seed(seed, SeedPurpose::kGlobalTable, 0x50b01));
    for (uint32_t& s : scramble) s = rng.next_u32();
  }
};

class SobolSampler final : public GlobalSampler {
 public:
  SobolSampler(int64_t spp, uint64_t seed, const Bounds2i& bounds)
      : GlobalSampler(spp), seed_(seed), bounds_(bounds) {
    uint32_t side = uint32_t(std::max(1, std::max(bounds.width(), bounds.height())));
    int m = log2_int(round_up_pow2(side));
    tables_ = std::make_shared<const SobolTables>(m, seed);
  }
  SobolSampler(const SobolSampler&) = default;

  std::unique_ptr<Sampler> clone() const override { return std::make_unique<SobolSampler>(*this); }

  void start_pixel(Point2i p) override {
    int m = tables_->indexer.log2_resolution();
    uint32_t mask = m == 0 ? 0 : uint32_t((1ull << m) - 1);
    uint32_t shift_x = m == 0 ? 0 : tables_->scramble[0] >> (32 - m);
    uint32_t shift_y = m == 0 ? 0 : tables_->scramble[1] >> (32 - m);
    pixel_x_ = (uint32_t(p.x - bounds_.min.x) & mask) ^ shift_x;
    pixel_y_ = (uint32_t(p.y - bounds_.min.y) & mask) ^ shift_y;
    GlobalSampler::start_pixel(p);
  }

 protected:
  int64_t index_for_sample(int64_t n) override {
    return int64_t(tables_->indexer.index(uint64_t(n), pixel_x_, pixel_y_));
  }

  float sample_dimension(int64_t index, int dim) const override {
    if (dim >= kSobolDimensions)
      return hashed_uniform(seed_, pixel_, uint64_t(index), uint64_t(dim));
    uint32_t bits =
        sobol_bits(uint64_t(index), tables_->nibbles + size_t(dim) * kSobolNibbleTable) ^
        tables_->scramble[dim];
    if (dim < 2) {
      // The top m bits name the pixel; the rest is the offset inside it
      // (exact, where pbrt-v3 scales a float by the resolution).
      int m = tables_->indexer.log2_resolution();
      bits = m == 0 ? bits : uint32_t(uint64_t(bits) << m);
    }
    return std::min(float(bits) * 0x1p-32f, kOneMinusEpsilon);
  }

 private:
  uint64_t seed_;
  Bounds2i bounds_;
  std::shared_ptr<const SobolTables> tables_;  // shared by clones
  uint32_t pixel_x_ = 0, pixel_y_ = 0;         // the pixel as the scrambled points see it
};

}  // namespace

std::unique_ptr<Sampler> make_sobol_sampler(int64_t spp, uint64_t seed, const Bounds2i& bounds) {
  return std::make_unique<SobolSampler>(spp, seed, bounds);
}

}  // namespace rt
