// runtime/render/tile_renderer.h — the samples of one pass over some tiles.
//
// The film's sample bounds (within the integrator's pixel bounds) are cut into
// 16x16-pixel tiles numbered in raster order. render() renders tiles [begin, end)
// for samples [first, last) of every pixel in parallel with oneTBB, each with a
// per-thread clone of the sampler and its own FilmTile. What a tile holds depends
// only on (tile, samples, seed), never on the thread or the process that rendered
// it. Threads take tiles in order, so tiles finish nearly in order: a caller that
// merges them into the film in tile order (the renderer, renderer.h; the processes
// of an MPI render) holds only a few at a time. Non-finite radiance is counted and
// added as black, as pbrt-v3 does. Splats (bdpt) go to the film's pending buffer.
// Counters (rays, samples) accumulate per thread; counters() sums them.
#pragma once

#include <tbb/enumerable_thread_specific.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "runtime/film/film.h"
#include "runtime/render/camera.h"
#include "runtime/render/integrator.h"
#include "runtime/render/progress_bar.h"
#include "runtime/sampler/sampler.h"

namespace rt {

struct RenderStats;

class TileRenderer {
 public:
  static constexpr int kTileSize = 16;

  // differential_spp > 0: ray differentials scaled as for that count, else the sampler's.
  TileRenderer(const Camera& camera, const Sampler& sampler, const Integrator& integrator,
               Film* film, int differential_spp);
  ~TileRenderer();

  int tile_count() const { return nx_ * ny_; }
  Bounds2i tile_bounds(int t) const;
  int64_t pixel_count() const { return bounds_.empty() ? 0 : bounds_.area(); }

  // Tiles [begin, end) of the pass over samples [first, last), each handed to done(t, tile)
  // as it finishes, from the thread that rendered it (done must be thread-safe). False
  // when *interrupt became true (some tiles then never rendered). progress (optional)
  // counts pixel samples.
  using TileDone = std::function<void(int tile, std::unique_ptr<FilmTile> rendered)>;
  bool render(int64_t first, int64_t last, int begin, int end, const TileDone& done,
              const std::atomic<bool>* interrupt, ProgressBar* progress);
  // The same, collected: (*out)[t - begin].
  bool render(int64_t first, int64_t last, int begin, int end,
              std::vector<std::unique_ptr<FilmTile>>* out, const std::atomic<bool>* interrupt,
              ProgressBar* progress);

  // Rays, samples and the like so far, added to *stats; seconds from construction to the
  // first tile finished.
  void add_counters(RenderStats* stats) const;
  double first_tile_seconds() const { return first_tile_seconds_.load(); }

 private:
  struct ThreadState;
  const Camera& camera_;
  const Sampler& prototype_;
  const Integrator& integrator_;
  Film* film_;
  Bounds2i bounds_;
  int nx_ = 0, ny_ = 0;
  CameraSampleUse sample_use_;  // what of each camera sample is drawn
  float diff_scale_;
  std::chrono::steady_clock::time_point t0_ = std::chrono::steady_clock::now();
  std::atomic<double> first_tile_seconds_{-1};
  std::unique_ptr<tbb::enumerable_thread_specific<ThreadState>> threads_;
};

}  // namespace rt
