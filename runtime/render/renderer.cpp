// runtime/render/renderer.cpp — see renderer.h.
#include "runtime/render/renderer.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <vector>

#include "runtime/core/clock.h"
#include "runtime/render/progress_bar.h"

namespace rt {

namespace {

constexpr int kTileSize = 16;

struct ThreadCounters {
  RayCounters rays;
  uint64_t samples = 0, nonfinite = 0;
};

}  // namespace

RenderStats render(const Camera& camera, const Sampler& prototype, const Integrator& integrator,
                   Film* film, const RenderOptions& options) {
  auto t0 = std::chrono::steady_clock::now();
  Bounds2i sb = film->sample_bounds();
  const IntegratorSettings& is = integrator.settings();
  if (is.has_pixel_bounds) sb = intersect(sb, is.pixel_bounds);
  RenderStats stats;
  if (sb.empty()) return stats;
  const int nx = (sb.width() + kTileSize - 1) / kTileSize;
  const int ny = (sb.height() + kTileSize - 1) / kTileSize;
  const int ntiles = nx * ny;
  std::vector<std::unique_ptr<FilmTile>> tiles(ntiles);
  tbb::enumerable_thread_specific<ThreadCounters> counters;
  ProgressBar progress(ntiles, options.quiet);
  std::atomic<bool> first_done{false};
  double first_tile = 0;
  std::mutex first_mutex;
  const float diff_scale =
      1 / std::sqrt(float(options.differential_spp > 0 ? options.differential_spp
                                                       : prototype.samples_per_pixel()));

  tbb::parallel_for(
      tbb::blocked_range<int>(0, ntiles, 1),
      [&](const tbb::blocked_range<int>& range) {
        ThreadCounters& tc = counters.local();
        for (int t = range.begin(); t != range.end(); ++t) {
          int tx = t % nx, ty = t / nx;
          Bounds2i tb{{sb.min.x + tx * kTileSize, sb.min.y + ty * kTileSize},
                      {std::min(sb.min.x + (tx + 1) * kTileSize, sb.max.x),
                       std::min(sb.min.y + (ty + 1) * kTileSize, sb.max.y)}};
          std::unique_ptr<Sampler> sampler = prototype.clone();
          std::unique_ptr<FilmTile> tile = film->make_tile(tb);
          for (int y = tb.min.y; y < tb.max.y; ++y)
            for (int x = tb.min.x; x < tb.max.x; ++x) {
              Point2i pixel{x, y};
              sampler->start_pixel(pixel);
              do {
                CameraSample cs;
                Vec2 u = sampler->get_2d();
                cs.p_film = {float(x) + u.x, float(y) + u.y};
                cs.time = sampler->get_1d();
                cs.p_lens = sampler->get_2d();
                RayDifferential ray;
                float w = camera.generate_ray_differential(cs, &ray);
                ray.scale_differentials(diff_scale);
                ++tc.rays.camera_rays;
                Rgb l;
                if (w > 0) l = integrator.li(ray, *sampler, &tc.rays);
                if (!l.is_finite()) {
                  ++tc.nonfinite;
                  l = Rgb();
                }
                tile->add_sample(cs.p_film, l, w);
                ++tc.samples;
              } while (sampler->start_next_sample());
            }
          tiles[t] = std::move(tile);
          progress.add(1);
          if (!first_done.exchange(true)) {
            std::lock_guard<std::mutex> lock(first_mutex);
            first_tile = seconds_since(t0);
          }
        }
      },
      tbb::simple_partitioner());
  progress.finish();
  for (int t = 0; t < ntiles; ++t) film->merge_tile(*tiles[t]);
  for (const ThreadCounters& tc : counters) {
    stats.samples += tc.samples;
    stats.nonfinite_samples += tc.nonfinite;
    stats.camera_rays += tc.rays.camera_rays;
    stats.rays += tc.rays.rays;
    stats.shadow_rays += tc.rays.shadow_rays;
    stats.paths += tc.rays.paths;
    stats.zero_radiance_paths += tc.rays.zero_radiance_paths;
  }
  stats.first_tile_seconds = first_tile;
  stats.seconds = seconds_since(t0);
  return stats;
}

}  // namespace rt
