// runtime/render/renderer.cpp — see renderer.h.
#include "runtime/render/renderer.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <vector>

#include "runtime/core/clock.h"
#include "runtime/film/error_estimate.h"
#include "runtime/render/progress_bar.h"

namespace rt {

namespace {

constexpr int kTileSize = 16;

struct ThreadState {
  RayCounters rays;
  uint64_t samples = 0, nonfinite = 0;
  std::unique_ptr<Sampler> sampler;  // cloned once, reused by every tile and pass
};

// "err 2.3% -> 1%, ETA 41 s": error falls as 1 / sqrt(samples), samples cost time.
std::string error_note(const ErrorEstimate& e, double target, double seconds, bool* has_eta) {
  *has_eta = false;
  if (!e.valid) return "err --";
  char buf[128];
  if (target <= 0) {
    std::snprintf(buf, sizeof buf, "err %.3g%%", 100 * e.rel_error);
    return buf;
  }
  const double ratio = e.rel_error / target;
  *has_eta = true;
  std::snprintf(buf, sizeof buf, "err %.3g%% -> %.3g%%, ETA %.0f s", 100 * e.rel_error,
                100 * target, std::max(0.0, seconds * (ratio * ratio - 1)));
  return buf;
}

}  // namespace

int64_t pass_end(int64_t first, int64_t total, bool whole_count_patterns) {
  const int64_t size = first == 0             ? 1
                       : whole_count_patterns ? first
                                              : std::min(first, kMaxPassSamples);
  return std::min(total, first + size);
}

RenderStats render(const Camera& camera, const Sampler& prototype, const Integrator& integrator,
                   Film* film, const RenderOptions& options) {
  auto t0 = std::chrono::steady_clock::now();
  Bounds2i sb = film->sample_bounds();
  const IntegratorSettings& is = integrator.settings();
  if (is.has_pixel_bounds) sb = intersect(sb, is.pixel_bounds);
  RenderStats stats;
  const int64_t total = prototype.samples_per_pixel();
  int64_t done = std::clamp<int64_t>(options.first_sample, 0, total);
  const int64_t film_samples = film->sample_count() - done;  // the film's count is this + done
  stats.samples_per_pixel = film->sample_count();
  if (sb.empty()) return stats;
  const int nx = (sb.width() + kTileSize - 1) / kTileSize;
  const int ny = (sb.height() + kTileSize - 1) / kTileSize;
  const int ntiles = nx * ny;
  tbb::enumerable_thread_specific<ThreadState> threads;
  ProgressBar progress((total - done) * sb.area(), options.quiet);
  std::atomic<bool> first_done{false};
  std::mutex first_mutex;
  const float diff_scale =
      1 / std::sqrt(float(options.differential_spp > 0 ? options.differential_spp : total));
  const bool whole = prototype.whole_count_patterns();
  // Those samplers rebuild every pixel's whole pattern at each pass (a fifth of a render's
  // time, measured on rs-procedural-textures/windy): one pass unless something may stop
  // the render or look at it between passes.
  const bool one_pass = whole && options.target_error <= 0 && options.time_limit <= 0 &&
                        options.checkpoint_every <= 0 && !options.on_pass;
  auto interrupted = [&] {
    return options.interrupt && options.interrupt->load(std::memory_order_relaxed);
  };
  double last_pass_seconds_per_sample = 0, last_checkpoint = 0, last_estimate = -1;

  while (done < total) {
    const int64_t end = one_pass ? total : pass_end(done, total, whole);
    const double elapsed = seconds_since(t0);
    if (options.time_limit > 0 && stats.passes > 0 &&
        options.time_spent + elapsed + last_pass_seconds_per_sample * double(end - done) >
            options.time_limit) {
      stats.stop = StopReason::kTimeLimit;
      break;
    }
    if (interrupted()) {
      stats.stop = StopReason::kInterrupted;
      break;
    }
    std::vector<std::unique_ptr<FilmTile>> tiles{size_t(ntiles)};
    tbb::parallel_for(
        tbb::blocked_range<int>(0, ntiles, 1),
        [&](const tbb::blocked_range<int>& range) {
          ThreadState& ts = threads.local();
          if (!ts.sampler) ts.sampler = prototype.clone();
          Sampler& sampler = *ts.sampler;
          sampler.set_sample_range(done, end);
          for (int t = range.begin(); t != range.end(); ++t) {
            if (interrupted()) return;
            int tx = t % nx, ty = t / nx;
            Bounds2i tb{{sb.min.x + tx * kTileSize, sb.min.y + ty * kTileSize},
                        {std::min(sb.min.x + (tx + 1) * kTileSize, sb.max.x),
                         std::min(sb.min.y + (ty + 1) * kTileSize, sb.max.y)}};
            std::unique_ptr<FilmTile> tile = film->make_tile(tb);
            for (int y = tb.min.y; y < tb.max.y; ++y)
              for (int x = tb.min.x; x < tb.max.x; ++x) {
                Point2i pixel{x, y};
                sampler.start_pixel(pixel);
                do {
                  CameraSample cs;
                  Vec2 u = sampler.get_2d();
                  cs.p_film = {float(x) + u.x, float(y) + u.y};
                  cs.time = sampler.get_1d();
                  cs.p_lens = sampler.get_2d();
                  RayDifferential ray;
                  float w = camera.generate_ray_differential(cs, &ray);
                  ray.scale_differentials(diff_scale);
                  ++ts.rays.camera_rays;
                  Rgb l;
                  if (w > 0) l = integrator.li(ray, sampler, &ts.rays);
                  if (!l.is_finite()) {
                    ++ts.nonfinite;
                    l = Rgb();
                  }
                  tile->add_sample(cs.p_film, l, w,
                                   sample_half(pixel, sampler.current_sample_number()));
                  ++ts.samples;
                } while (sampler.start_next_sample());
              }
            tiles[size_t(t)] = std::move(tile);
            progress.add(tb.area() * (end - done));
            if (!first_done.exchange(true)) {
              std::lock_guard<std::mutex> lock(first_mutex);
              stats.first_tile_seconds = seconds_since(t0);
            }
          }
        },
        tbb::simple_partitioner());
    if (interrupted()) {  // the pass is incomplete: the film keeps the passes done
      film->discard_splats();
      integrator.end_pass(false, film_samples + done);
      stats.stop = StopReason::kInterrupted;
      break;
    }
    for (const auto& tile : tiles) film->merge_tile(*tile);
    film->commit_splats();
    last_pass_seconds_per_sample = (seconds_since(t0) - elapsed) / double(end - done);
    done = end;
    ++stats.passes;
    film->set_sample_count(film_samples + done);
    film->set_splat_scale(1.f / float(film_samples + done));
    integrator.end_pass(true, film_samples + done);
    if (options.on_pass) options.on_pass(*film, done, seconds_since(t0));

    // The estimate costs a pass over the image: only when a target needs it, or
    // twice a second for the progress line.
    const double now = seconds_since(t0);
    if (options.target_error > 0 || (!options.quiet && now - last_estimate >= 0.5)) {
      last_estimate = now;
      const ErrorEstimate e = estimate_error(*film);
      bool has_eta = false;
      const std::string note = error_note(e, options.target_error, now, &has_eta);
      // Towards a target, error falls as 1 / sqrt(samples): (target / err)^2 of the way.
      const double toward = options.target_error > 0 && e.valid && e.rel_error > 0
                                ? std::pow(options.target_error / e.rel_error, 2)
                                : 0;
      progress.set_note(note, has_eta, toward);
      if (options.target_error > 0 && e.valid && e.rel_error <= options.target_error) {
        stats.stop = StopReason::kTargetError;
        break;
      }
    }
    if (options.checkpoint && options.checkpoint_every > 0 && done < total &&
        now - last_checkpoint >= options.checkpoint_every) {
      last_checkpoint = now;
      ++stats.checkpoints;
      if (!options.checkpoint(&stats.error)) {
        stats.stop = StopReason::kError;
        break;
      }
    }
  }
  const ErrorEstimate e = estimate_error(*film);
  stats.has_error_estimate = e.valid;
  stats.error_estimate = e.rel_error;
  bool has_eta = false;
  const std::string note = error_note(e, 0, 0, &has_eta);
  progress.set_note(note, false, stats.stop == StopReason::kTargetError ? 1 : 0);
  progress.finish();
  stats.samples_per_pixel = film_samples + done;
  for (const ThreadState& ts : threads) {
    stats.samples += ts.samples;
    stats.nonfinite_samples += ts.nonfinite;
    stats.camera_rays += ts.rays.camera_rays;
    stats.rays += ts.rays.rays;
    stats.shadow_rays += ts.rays.shadow_rays;
    stats.paths += ts.rays.paths;
    stats.zero_radiance_paths += ts.rays.zero_radiance_paths;
  }
  stats.seconds = seconds_since(t0);
  return stats;
}

}  // namespace rt
