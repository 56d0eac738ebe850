// runtime/render/renderer.h — the tile-parallel render loop, in passes.
//
// The render visits every pixel in passes, each adding the next samples of the
// pixel's sequence (Sampler::set_sample_range): passes of 1, 1, 2, 4 and 8
// samples, then 8 at a time (kMaxPassSamples). Samplers whose patterns span the
// whole count (Sampler::whole_count_patterns: stratified, 02sequence, maxmindist)
// rebuild every pixel's pattern at each pass, so they keep doubling (1, 1, 2, 4,
// 8, 16, ...), and render in one pass when nothing may stop the render early or
// look at it between passes (no target error, time limit, checkpoints or on_pass;
// not resuming).
//
// The pass sizes depend only on the sample index, so a render stopped after N
// passes holds exactly the samples of a render whose count ends there, added in
// the same order: the same image, bit for bit, with any sampler whose values do
// not depend on the total count (halton, sobol, random). The pixel samplers
// stratify over the count they were built for, so theirs is only statistically
// the same. Ray differentials, and so texture filtering, follow the planned
// count (RenderOptions::differential_spp).
//
// Within a pass the tiles (tile_renderer.h) are rendered in parallel and merged
// into the film in tile order, so the image is bit-identical whatever the thread
// count (or the process count, tools/mpi). A tile is merged as soon as those before
// it are, so only a few are held at once (holding a pass's tiles until its end took
// more memory than the film: 80 bytes a pixel on the Cornell box); with
// whole_passes_only they are held until the pass ends. After each pass the
// film's sample count (Film::set_sample_count: what it held before plus the
// samples rendered) and splat scale (1 / that) are updated.
//
// Stopping: at the planned count (the sampler's), or at the end of a pass once
// the estimated error (error_estimate.h) is at most target_error, or before a
// pass that the last pass's speed says would end past time_limit (so a render
// overruns its limit by at most one pass, when a pass is slower than the last),
// or when *interrupt becomes true: the pass under way is abandoned (its splats and
// unmerged tiles dropped) and the film holds the passes done, plus the tiles of
// the abandoned pass merged so far unless whole_passes_only (a saved state must
// hold whole passes). checkpoint() runs at the
// end of a pass at most every checkpoint_every seconds. Progress (samples, time,
// ETA, and the error estimate with its target) goes to stderr unless quiet.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>

#include "runtime/film/film.h"
#include "runtime/render/camera.h"
#include "runtime/render/integrator.h"
#include "runtime/render/progress_bar.h"
#include "runtime/sampler/sampler.h"

namespace rt {

constexpr int64_t kMaxPassSamples = 8;

// The sample that ends the pass starting at `first` (see above).
int64_t pass_end(int64_t first, int64_t total, bool whole_count_patterns);

struct RenderOptions {
  bool quiet = false;
  // > 0: camera differentials scaled as for this many samples per pixel
  // (pbrt-v3 uses the sampler's count; see RenderJobOptions::differential_spp).
  int differential_spp = 0;
  // The first sample index to render: resuming (the film holds samples [0, first_sample)
  // already) or rendering a later range of the sequence alone.
  int64_t first_sample = 0;
  int64_t end_sample = 0;   // > 0: stop before this sample index (a shard's range)
  double target_error = 0;  // > 0: stop once the estimate is at most this (a fraction)
  double time_limit = 0;    // > 0: seconds, counted from time_origin
  double time_spent = 0;    // seconds already spent (loading, building) towards time_limit
  double checkpoint_every = 0;
  std::function<bool(std::string* error)> checkpoint;  // writes the image so far
  const std::atomic<bool>* interrupt = nullptr;
  bool whole_passes_only = false;  // an interrupted pass leaves nothing in the film
  // After every pass: the film, the sample index reached and the seconds since the loop
  // began (pbrt-converge measures its error ladder here; tests watch the estimate).
  std::function<void(const Film& film, int64_t samples, double seconds)> on_pass;
};

enum class StopReason : uint8_t { kSamples, kTargetError, kTimeLimit, kInterrupted, kError };

struct RenderStats {
  double seconds = 0;
  double first_tile_seconds = 0;  // time to the first finished tile (first pixels)
  uint64_t samples = 0, camera_rays = 0, rays = 0, shadow_rays = 0;
  uint64_t nonfinite_samples = 0;
  // bdpt and mlt: strategies joined, and those that carried no radiance (pbrt-v3's "zero
  // radiance paths"); mlt: mutations proposed and accepted; sppm: iterations and photons.
  uint64_t paths = 0, zero_radiance_paths = 0;
  uint64_t mutations = 0, accepted = 0;
  uint64_t iterations = 0, photons = 0;
  // Passes (the pass renderer only).
  int passes = 0, checkpoints = 0;
  int64_t samples_per_pixel = 0;  // the film holds (resumed ones included)
  StopReason stop = StopReason::kSamples;
  bool has_error_estimate = false;
  double error_estimate = 0;  // a fraction
  std::string error;          // kError: what failed (a checkpoint)
};

RenderStats render(const Camera& camera, const Sampler& sampler, const Integrator& integrator,
                   Film* film, const RenderOptions& options);

// The pass loop alone, for renders whose passes are rendered elsewhere (MPI): pass(first,
// last, progress) renders samples [first, last) of every pixel and merges its tiles into
// the film in tile order, leaving splats pending; false when it was interrupted (the film's
// sums untouched). total: the planned samples per pixel; whole: the sampler's
// whole_count_patterns(); pixels: pixels a pass renders (progress). Stats without ray
// counters (the caller's).
using RenderPass = std::function<bool(int64_t first, int64_t last, ProgressBar* progress)>;
RenderStats run_passes(Film* film, const Integrator& integrator, int64_t total, bool whole,
                       int64_t pixels, const RenderOptions& options, const RenderPass& pass);

}  // namespace rt
