// runtime/sampler/global_sampler.h — pbrt-v3's GlobalSampler: one
// low-discrepancy sequence over the whole image; each (pixel, sample) maps to
// a global sequence index and each dimension reads that point's coordinate.
//
// Dimensions kArrayStartDim.. are reserved for the requested arrays (as in
// pbrt-v3): get_1d()/get_2d() skip over them. Sample s of an n-value array
// uses the pixel's sequence points s*n .. s*n+n-1.
#pragma once

#include "runtime/sampler/sampler.h"

namespace rt {

class GlobalSampler : public Sampler {
 public:
  void start_pixel(Point2i p) override;
  bool set_sample_number(int64_t n) override;
  float get_1d() override;
  Vec2 get_2d() override;
  void skip_1d() override { next_dimension_1d(); }
  void skip_2d() override { next_dimension_2d(); }

 protected:
  void fill_1d_array(size_t i) override;
  void fill_2d_array(size_t i) override;
  explicit GlobalSampler(int64_t spp) : Sampler(spp) {}
  GlobalSampler(const GlobalSampler&) = default;

  // The global index of the current pixel's sample n.
  virtual int64_t index_for_sample(int64_t n) = 0;
  // Coordinate `dim` of sequence point `index`; dims 0 and 1 are relative to
  // the current pixel (the offset inside it).
  virtual float sample_dimension(int64_t index, int dim) const = 0;

  // The dimension the next get_1d() reads, or the first of get_2d()'s two (both past the
  // arrays' reserved dimensions), and the count moved past it.
  int next_dimension_1d() {
    if (dimension_ >= kArrayStartDim && dimension_ < array_end_dim_) dimension_ = array_end_dim_;
    return dimension_++;
  }
  int next_dimension_2d() {
    if (dimension_ + 1 >= kArrayStartDim && dimension_ < array_end_dim_)
      dimension_ = array_end_dim_;
    dimension_ += 2;
    return dimension_ - 2;
  }

  static constexpr int kArrayStartDim = 5;
  int dimension_ = 0;
  int array_end_dim_ = kArrayStartDim;
  int64_t interval_index_ = 0;
};

}  // namespace rt
