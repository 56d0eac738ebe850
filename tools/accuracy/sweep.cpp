#include "tools/accuracy/sweep.h"

#include <algorithm>
#include <chrono>
#include <memory>

#include "runtime/core/clock.h"
#include "runtime/film/error_estimate.h"
#include "runtime/render/render_job.h"
#include "runtime/sampler/sampler.h"

namespace accuracy {

namespace {

rt::RenderJobOptions render_options(const SweepConfig& config, int spp, int resdiv, uint64_t seed) {
  rt::RenderJobOptions o;
  o.spp = spp;
  o.resdiv = resdiv;
  o.seed = seed;
  o.quiet = true;
  o.write_files = false;
  o.sampler = config.sampler;
  o.integrator = config.integrator;
  o.light_strategy = config.strategy;
  o.program = "pbrt-converge";
  return o;
}

}  // namespace

bool render_image(const pbrta::SceneArchive& archive, const SweepConfig& config, int spp,
                  int resdiv, uint64_t seed, rt::ImageRgb* image, double* seconds,
                  double* render_seconds, std::string* error) {
  rt::RenderJobOptions o = render_options(config, spp, resdiv, seed);
  o.keep_image = true;
  rt::RenderJobResult result;
  auto t0 = std::chrono::steady_clock::now();
  if (!rt::render_archive(archive, o, &result, error)) return false;
  *seconds = rt::seconds_since(t0);
  *render_seconds = result.render.seconds;
  *image = std::move(result.image);
  return true;
}

namespace {

// Does this configuration's sampler build its patterns for the whole sample count?
bool whole_count_sampler(const pbrta::SceneArchive& archive, const SweepConfig& config) {
  std::string error;
  std::unique_ptr<rt::Sampler> s =
      rt::make_sampler(archive, 1, 0, rt::Bounds2i{{0, 0}, {1, 1}}, &error, config.sampler);
  return s && s->whole_count_patterns();
}

// Every rung of one configuration from the passes of one render at the top rung.
bool sweep_by_passes(const pbrta::SceneArchive& archive, const std::string& scene_name,
                     const rt::ImageRgb& reference, const SweepConfig& config,
                     const SweepOptions& options, const std::vector<int>& ladder,
                     std::vector<SweepRow>* rows, std::string* error,
                     const std::function<void(const SweepRow&)>& on_row) {
  rt::RenderJobOptions o = render_options(config, ladder.back(), options.resdiv, options.seed);
  o.time_limit = options.budget.max_seconds;
  std::vector<SweepRow> found;
  std::string why;
  o.on_pass = [&](const rt::Film& film, int64_t samples, double seconds) {
    if (!why.empty() || std::find(ladder.begin(), ladder.end(), samples) == ladder.end()) return;
    SweepRow row;
    row.scene = scene_name;
    row.config = config.name();
    row.spp = int(samples);
    row.render_seconds = seconds;
    const rt::ErrorEstimate e = rt::estimate_error(film);
    if (e.valid) row.estimated_error = e.rel_error;
    if (!image_errors(film.image(), reference, &row.errors, &why))
      why = config.name() + " at " + std::to_string(samples) + " spp: " + why;
    found.push_back(row);
  };
  rt::RenderJobResult result;
  o.time_origin = std::chrono::steady_clock::now();
  if (!rt::render_archive(archive, o, &result, error)) {
    *error = config.name() + ": " + *error;
    return false;
  }
  if (!why.empty()) {
    *error = why;
    return false;
  }
  for (SweepRow& row : found) {
    row.seconds = result.setup_seconds + row.render_seconds;  // what a render to row.spp costs
    rows->push_back(row);
    if (on_row) on_row(row);
  }
  return true;
}

}  // namespace

bool run_sweep(const pbrta::SceneArchive& archive, const std::string& scene_name,
               const rt::ImageRgb& reference, const std::vector<SweepConfig>& configs,
               const SweepOptions& options, std::vector<SweepRow>* rows, std::string* error,
               const std::function<void(const SweepRow&)>& on_row) {
  const LadderBudget& budget = options.budget;
  for (const SweepConfig& config : configs) {
    const std::vector<int> ladder = spp_ladder(budget);
    if (ladder.empty()) continue;
    if (!whole_count_sampler(archive, config)) {
      if (!sweep_by_passes(archive, scene_name, reference, config, options, ladder, rows, error,
                           on_row))
        return false;
      continue;
    }
    // Stratified, 02sequence and maxmindist stratify over the count they are built for: a
    // pass of a longer render is not what a render of that count gives, so one per rung.
    double spent = 0;
    for (int spp = ladder.front(); spp > 0;) {
      SweepRow row;
      row.scene = scene_name;
      row.config = config.name();
      row.spp = spp;
      rt::ImageRgb image;
      std::string why;
      if (!render_image(archive, config, spp, options.resdiv, options.seed, &image, &row.seconds,
                        &row.render_seconds, &why) ||
          !image_errors(image, reference, &row.errors, &why)) {
        *error = config.name() + " at " + std::to_string(spp) + " spp: " + why;
        return false;
      }
      spent += row.seconds;
      rows->push_back(row);
      if (on_row) on_row(row);
      spp = next_rung(budget, spp, row.seconds, spent);
    }
  }
  return true;
}

bool render_reference(const pbrta::SceneArchive& archive, int spp, int resdiv, uint64_t seed,
                      rt::ImageRgb* half_a, rt::ImageRgb* half_b, rt::ImageRgb* mean,
                      std::string* error) {
  if (spp < 2) {
    *error = "a reference needs at least 2 spp (two halves)";
    return false;
  }
  double seconds = 0, render_seconds = 0;
  SweepConfig scene_own;
  if (!render_image(archive, scene_own, spp / 2, resdiv, seed, half_a, &seconds, &render_seconds,
                    error) ||
      !render_image(archive, scene_own, spp / 2, resdiv, seed + 1, half_b, &seconds,
                    &render_seconds, error))
    return false;
  *mean = *half_a;
  for (size_t i = 0; i < mean->rgb.size(); ++i)
    mean->rgb[i] = 0.5f * (half_a->rgb[i] + half_b->rgb[i]);
  return true;
}

}  // namespace accuracy
