#include "tools/accuracy/sweep.h"

#include <chrono>

#include "runtime/core/clock.h"
#include "runtime/render/render_job.h"

namespace accuracy {

bool render_image(const pbrta::SceneArchive& archive, const SweepConfig& config, int spp,
                  int resdiv, uint64_t seed, rt::ImageRgb* image, double* seconds,
                  double* render_seconds, std::string* error) {
  rt::RenderJobOptions o;
  o.spp = spp;
  o.resdiv = resdiv;
  o.seed = seed;
  o.quiet = true;
  o.write_files = false;
  o.keep_image = true;
  o.sampler = config.sampler;
  o.integrator = config.integrator;
  o.light_strategy = config.strategy;
  o.program = "pbrt-converge";
  rt::RenderJobResult result;
  auto t0 = std::chrono::steady_clock::now();
  if (!rt::render_archive(archive, o, &result, error)) return false;
  *seconds = rt::seconds_since(t0);
  *render_seconds = result.render.seconds;
  *image = std::move(result.image);
  return true;
}

bool run_sweep(const pbrta::SceneArchive& archive, const std::string& scene_name,
               const rt::ImageRgb& reference, const std::vector<SweepConfig>& configs,
               const SweepOptions& options, std::vector<SweepRow>* rows, std::string* error,
               const std::function<void(const SweepRow&)>& on_row) {
  const LadderBudget& budget = options.budget;
  for (const SweepConfig& config : configs) {
    double spent = 0;
    for (int spp = budget.min_spp < 1 ? 1 : budget.min_spp; spp > 0;) {
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
