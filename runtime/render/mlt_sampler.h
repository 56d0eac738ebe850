// runtime/render/mlt_sampler.h — Kelemen et al.'s primary sample space, as pbrt-v3's
// MLTSampler (book 3rd ed., 16.4.1).
//
// A Sampler whose numbers are the coordinates of one point X of the unit hypercube, mutated
// between iterations: a large step redraws every coordinate uniformly, a small step moves each
// by a normal offset of standard deviation sigma (wrapped into [0, 1)). Coordinates are made
// lazily, when first read in an iteration, so a path that reads few numbers costs few; one that
// has not been read since an earlier iteration is brought up to date by the mutations it
// missed (small steps compound to a normal of sigma sqrt(n)). accept() keeps the proposal,
// reject() restores every coordinate the iteration changed. Numbers come in streams
// (camera, light, connection) interleaved in X, so each part of a path keeps its own
// coordinates whatever the other parts read.
#pragma once

#include <cstdint>
#include <vector>

#include "runtime/core/rng.h"
#include "runtime/sampler/sampler.h"

namespace rt {

class MltSampler : public Sampler {
 public:
  // rng_index picks the generator's stream; seed offsets it (independent images per seed).
  MltSampler(int64_t mutations_per_pixel, uint64_t rng_index, float sigma,
             float large_step_probability, int streams, uint64_t seed = 0);
  std::unique_ptr<Sampler> clone() const override;
  float get_1d() override;
  Vec2 get_2d() override;

  // The sampler as constructed with rng_index (same sigma, streams and seed), keeping its
  // storage: bootstrap paths each take a fresh sampler.
  void restart(uint64_t rng_index);
  void start_iteration();
  void accept();
  void reject();
  void start_stream(int index);

 private:
  struct PrimarySample {
    float value = 0, value_backup = 0;
    int64_t last_modified = 0, modify_backup = 0;
  };
  void ensure_ready(size_t index);

  Rng rng_;
  uint64_t seed_;
  float sigma_, large_step_probability_;
  int streams_;
  std::vector<PrimarySample> x_;
  int64_t iteration_ = 0, last_large_step_ = 0;
  bool large_step_ = true;
  int stream_ = 0;
  int64_t index_in_stream_ = 0;
};

}  // namespace rt
