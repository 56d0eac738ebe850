// runtime/render/renderer.cpp — see renderer.h.
#include "runtime/render/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <vector>

#include "runtime/core/clock.h"
#include "runtime/film/error_estimate.h"
#include "runtime/render/progress_bar.h"
#include "runtime/render/tile_renderer.h"

namespace rt {

namespace {

// "err 2.3% -> 1%, ETA 41 s": error falls as 1 / sqrt(samples), samples cost time.
std::string error_note(const ErrorEstimate& e, double target, double seconds, bool* has_eta) {
  *has_eta = false;
  if (!e.valid) return "err --";
  const std::string err = "err " + error_percent(e.rel_error);
  if (target <= 0) return err;
  const double ratio = e.rel_error / target;
  *has_eta = true;
  char eta[48];
  std::snprintf(eta, sizeof eta, ", ETA %.0f s", std::max(0.0, seconds * (ratio * ratio - 1)));
  return err + " -> " + error_percent(target) + eta;
}

}  // namespace

int64_t pass_end(int64_t first, int64_t total, bool whole_count_patterns) {
  const int64_t size = first == 0             ? 1
                       : whole_count_patterns ? first
                                              : std::min(first, kMaxPassSamples);
  return std::min(total, first + size);
}

RenderStats run_passes(Film* film, const Integrator& integrator, int64_t total, bool whole,
                       int64_t pixels, const RenderOptions& options, const RenderPass& pass) {
  auto t0 = std::chrono::steady_clock::now();
  RenderStats stats;
  const int64_t last = options.end_sample > 0 ? std::min(options.end_sample, total) : total;
  int64_t done = std::clamp<int64_t>(options.first_sample, 0, last);
  const int64_t film_samples = film->sample_count() - done;  // the film's count is this + done
  stats.samples_per_pixel = film->sample_count();
  if (pixels <= 0) return stats;
  ProgressBar progress((last - done) * pixels, options.quiet);
  // Those samplers rebuild every pixel's whole pattern at each pass (a fifth of a render's
  // time, measured on rs-procedural-textures/windy): one pass unless something may stop
  // the render or look at it between passes.
  // A resumed render continues in passes, as the render it resumes (which checkpointed) did.
  const bool one_pass = whole && options.target_error <= 0 && options.time_limit <= 0 &&
                        options.checkpoint_every <= 0 && !options.on_pass &&
                        (options.first_sample == 0 || options.end_sample > 0);
  // Passes that may end the render, be looked at or be dropped keep their splats apart.
  if (!one_pass) film->keep_pass_splats_apart();
  auto interrupted = [&] {
    return options.interrupt && options.interrupt->load(std::memory_order_relaxed);
  };
  double last_pass_seconds_per_sample = 0, last_checkpoint = 0, last_estimate = -1;

  while (done < last) {
    const int64_t end = one_pass ? last : std::min(last, pass_end(done, total, whole));
    const double elapsed = seconds_since(t0);
    if (options.time_limit > 0 && stats.passes > 0 &&
        options.time_spent + elapsed + last_pass_seconds_per_sample * double(end - done) >
            options.time_limit) {
      stats.stop = StopReason::kTimeLimit;
      break;
    }
    if (interrupted() || !pass(done, end, &progress)) {  // the film keeps the passes done
      film->discard_splats();
      integrator.end_pass(false, film_samples + done);
      stats.stop = StopReason::kInterrupted;
      break;
    }
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
    if (options.checkpoint && options.checkpoint_every > 0 && done < last &&
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
  stats.seconds = seconds_since(t0);
  return stats;
}

RenderStats render(const Camera& camera, const Sampler& sampler, const Integrator& integrator,
                   Film* film, const RenderOptions& options) {
  TileRenderer tiles(camera, sampler, integrator, film, options.differential_spp);
  // Finished tiles wait here until every tile before them is merged.
  std::vector<std::unique_ptr<FilmTile>> waiting;
  std::mutex merging;
  int next = 0;
  // Merged during the pass: every tile, or none (whole passes only: merged at its end).
  const int merge_early = options.whole_passes_only ? 0 : tiles.tile_count();
  auto done = [&](int t, std::unique_ptr<FilmTile> tile) {
    std::lock_guard<std::mutex> lock(merging);
    waiting[size_t(t)] = std::move(tile);
    for (; next < merge_early && waiting[size_t(next)]; ++next) {
      film->merge_tile(*waiting[size_t(next)]);
      waiting[size_t(next)].reset();
    }
  };
  RenderStats stats = run_passes(
      film, integrator, sampler.samples_per_pixel(), sampler.whole_count_patterns(),
      tiles.pixel_count(), options, [&](int64_t first, int64_t last, ProgressBar* progress) {
        waiting.clear();
        waiting.resize(size_t(tiles.tile_count()));
        next = 0;
        if (!tiles.render(first, last, 0, tiles.tile_count(), done, options.interrupt, progress))
          return false;
        for (; next < tiles.tile_count(); ++next) film->merge_tile(*waiting[size_t(next)]);
        return true;
      });
  tiles.add_counters(&stats);
  return stats;
}

}  // namespace rt
