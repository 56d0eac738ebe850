// runtime/render/tile_renderer.cpp — see tile_renderer.h.
#include "runtime/render/tile_renderer.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "runtime/core/clock.h"
#include "runtime/render/renderer.h"

namespace rt {

struct TileRenderer::ThreadState {
  RayCounters rays;
  uint64_t samples = 0, nonfinite = 0;
  std::unique_ptr<Sampler> sampler;  // cloned once, reused by every tile and pass
};

TileRenderer::TileRenderer(const Camera& camera, const Sampler& sampler,
                           const Integrator& integrator, Film* film, int differential_spp)
    : camera_(camera),
      prototype_(sampler),
      integrator_(integrator),
      film_(film),
      sample_use_(camera.sample_use(integrator.scene().effects)),
      diff_scale_(1 / std::sqrt(float(differential_spp > 0 ? differential_spp
                                                           : sampler.samples_per_pixel()))),
      threads_(std::make_unique<tbb::enumerable_thread_specific<ThreadState>>()) {
  bounds_ = film->sample_bounds();
  const IntegratorSettings& is = integrator.settings();
  if (is.has_pixel_bounds) bounds_ = intersect(bounds_, is.pixel_bounds);
  if (!bounds_.empty()) {
    nx_ = (bounds_.width() + kTileSize - 1) / kTileSize;
    ny_ = (bounds_.height() + kTileSize - 1) / kTileSize;
  }
}

TileRenderer::~TileRenderer() = default;

Bounds2i TileRenderer::tile_bounds(int t) const {
  const int tx = t % nx_, ty = t / nx_;
  return {{bounds_.min.x + tx * kTileSize, bounds_.min.y + ty * kTileSize},
          {std::min(bounds_.min.x + (tx + 1) * kTileSize, bounds_.max.x),
           std::min(bounds_.min.y + (ty + 1) * kTileSize, bounds_.max.y)}};
}

bool TileRenderer::render(int64_t first, int64_t last, int begin, int end, const TileDone& done,
                          const std::atomic<bool>* interrupt, ProgressBar* progress) {
  auto interrupted = [&] { return interrupt && interrupt->load(std::memory_order_relaxed); };
  // Each task renders the next tile in order (tbb::parallel_for alone would split the range
  // in halves, and a caller merging in tile order would hold half the tiles).
  std::atomic<int> next{begin};
  tbb::parallel_for(
      tbb::blocked_range<int>(begin, end, 1),
      [&](const tbb::blocked_range<int>& range) {
        ThreadState& ts = threads_->local();
        if (!ts.sampler) ts.sampler = prototype_.clone();
        Sampler& sampler = *ts.sampler;
        sampler.set_sample_range(first, last);
        for (int i = range.begin(); i != range.end(); ++i) {
          if (interrupted()) return;
          const int t = next++;
          const Bounds2i tb = tile_bounds(t);
          std::unique_ptr<FilmTile> tile = film_->make_tile(tb);
          for (int y = tb.min.y; y < tb.max.y; ++y)
            for (int x = tb.min.x; x < tb.max.x; ++x) {
              Point2i pixel{x, y};
              sampler.start_pixel(pixel);
              do {
                const CameraSample cs = pixel_camera_sample(sampler, pixel, sample_use_);
                RayDifferential ray;
                float w = camera_.generate_ray_differential(cs, diff_scale_, &ray);
                ++ts.rays.camera_rays;
                Rgb l;
                if (w > 0) l = integrator_.li(ray, sampler, &ts.rays);
                if (!l.is_finite()) {
                  ++ts.nonfinite;
                  l = Rgb();
                }
                tile->add_sample(cs.p_film, l, w,
                                 sample_half(pixel, sampler.current_sample_number()));
                ++ts.samples;
              } while (sampler.start_next_sample());
            }
          done(t, std::move(tile));
          if (progress) progress->add(tb.area() * (last - first));
          double none = -1;
          first_tile_seconds_.compare_exchange_strong(none, seconds_since(t0_));
        }
      },
      tbb::simple_partitioner());
  return !interrupted();
}

bool TileRenderer::render(int64_t first, int64_t last, int begin, int end,
                          std::vector<std::unique_ptr<FilmTile>>* out,
                          const std::atomic<bool>* interrupt, ProgressBar* progress) {
  out->clear();
  out->resize(size_t(std::max(0, end - begin)));
  return render(
      first, last, begin, end,
      [&](int t, std::unique_ptr<FilmTile> tile) { (*out)[size_t(t - begin)] = std::move(tile); },
      interrupt, progress);
}

void TileRenderer::add_counters(RenderStats* stats) const {
  for (const ThreadState& ts : *threads_) {
    stats->samples += ts.samples;
    stats->nonfinite_samples += ts.nonfinite;
    stats->camera_rays += ts.rays.camera_rays;
    stats->rays += ts.rays.rays;
    stats->shadow_rays += ts.rays.shadow_rays;
    stats->paths += ts.rays.paths;
    stats->zero_radiance_paths += ts.rays.zero_radiance_paths;
  }
  stats->first_tile_seconds = std::max(0.0, first_tile_seconds());
}

}  // namespace rt
