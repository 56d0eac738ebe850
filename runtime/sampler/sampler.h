// runtime/sampler/sampler.h — pbrt-v3's samplers: the sample values every
// pixel sample draws, dimension by dimension.
//
// Contract: what a sampler returns for (pixel p, sample i, dimension d) depends
// only on (settings, seed, p, i, d) — never on the thread, the tile or the
// pixels rendered before — so images are bit-identical for any thread count.
// (pbrt-v3 seeds its random generators per tile; these seed per pixel.)
//
// Use: request_*_array() first (as pbrt-v3's integrators do, after
// round_count()), then clone() one sampler per thread (clones copy the
// requests); per pixel start_pixel(), and per sample get_1d()/get_2d()/
// get_*_array() until start_next_sample() returns false. Every value lies in
// [0, 1).
//
// Passes: set_sample_range(first, end) makes start_pixel() begin at sample `first` and
// start_next_sample() stop before `end`, so a render can visit every pixel's samples in
// several passes and get the very values one pass would. Samplers whose values depend
// only on (pixel, sample index) compute arrays for that range alone; the pixel samplers
// (stratified, 02sequence, maxmindist) stratify over the whole count and rebuild the
// pixel's whole pattern at every start_pixel(): whole_count_patterns() says so, and the
// renderer gives them fewer, doubling passes.
//
// make_sampler() builds the scene's sampler entity: "halton", "sobol",
// "02sequence" (alias "lowdiscrepancy"), "maxmindist", "stratified",
// "random". spp_override > 0 replaces the scene's sample count as
// /work/shared/refs/README.md says (stratified: xsamples * ysamples = N,
// ysamples the largest divisor of N not above sqrt(N); sobol, 02sequence and
// maxmindist round up to a power of two, maxmindist to at most 2^16). seed
// changes every random choice (scrambles, permutations, jitter).
// sample_bounds is the film's sample bounds (Halton and Sobol map pixels to
// sample indices over it). Anything else fails with
// "not supported yet: ... (file:line)". type_override (non-empty) replaces the
// entity's type; its parameters (counts, dimensions) are still read from the entity.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "format/scene_archive.h"
#include "runtime/core/vec.h"

namespace rt {

class Sampler {
 public:
  virtual ~Sampler() = default;
  virtual std::unique_ptr<Sampler> clone() const = 0;  // same settings, independent state
  virtual void start_pixel(Point2i p);                 // sample 0 of that pixel, dimension 0
  bool start_next_sample();  // next sample of the pixel; false at the range's end
  void set_sample_range(int64_t first, int64_t end);  // within [0, spp]; default all
  virtual bool whole_count_patterns() const { return false; }
  virtual bool set_sample_number(int64_t n);
  virtual float get_1d() = 0;  // next dimension, in [0,1)
  virtual Vec2 get_2d() = 0;
  // The next dimension(s) passed over as get_1d()/get_2d() would take them, for a value nothing
  // reads (a pinhole camera's lens point, a still scene's time): the later values stay the
  // same, and samplers that compute values per dimension skip computing this one.
  virtual void skip_1d() { get_1d(); }
  virtual void skip_2d() { get_2d(); }
  // get_2d() where the value is read, skip_2d() (and zero) where it is not: a delta light's
  // sample, which pbrt-v3 draws and never reads.
  Vec2 get_2d_if(bool read) {
    if (read) return get_2d();
    skip_2d();
    return {0, 0};
  }
  void request_1d_array(int n);  // before rendering, as pbrt-v3's arrays
  void request_2d_array(int n);
  virtual int round_count(int n) const { return n; }
  const float* get_1d_array(int n);  // nullptr when not requested / exhausted
  const Vec2* get_2d_array(int n);
  int64_t samples_per_pixel() const { return spp_; }
  int64_t current_sample_number() const { return sample_index_; }
  Point2i current_pixel() const { return pixel_; }

 protected:
  explicit Sampler(int64_t spp) : spp_(spp), end_(spp) {}
  // Array i's values for the current pixel's samples [first_, end_), made when the array is
  // first handed out in the pixel rather than at start_pixel(): integrators request arrays
  // for every depth they might reach (pbrt-v3's directlighting: two per light per depth), and
  // most paths end long before.
  virtual void fill_1d_array(size_t /*i*/) {}
  virtual void fill_2d_array(size_t /*i*/) {}
  Sampler(const Sampler&) = default;
  Sampler& operator=(const Sampler&) = delete;

  int64_t spp_;
  Point2i pixel_;
  int64_t sample_index_ = 0;
  int64_t first_ = 0, end_;  // set_sample_range()
  // Requested array sizes, and per request n * spp values (sample s's array
  // starts at s * n), filled by the subclass's fill_*_array().
  std::vector<int> sizes_1d_, sizes_2d_;
  std::vector<std::vector<float>> arrays_1d_;
  std::vector<std::vector<Vec2>> arrays_2d_;
  size_t next_1d_array_ = 0, next_2d_array_ = 0;

 private:
  // True once per pixel for an array (whose filled_* entry it stamps): fill it then.
  bool first_read(uint64_t* filled_at) const;
  uint64_t pixel_serial_ = 0;                    // start_pixel() calls so far
  std::vector<uint64_t> filled_1d_, filled_2d_;  // the pixel_serial_ each array was filled at
};

std::unique_ptr<Sampler> make_sampler(const pbrta::SceneArchive& archive, int spp_override,
                                      uint64_t seed, const Bounds2i& sample_bounds,
                                      std::string* error, std::string_view type_override = {});

}  // namespace rt
