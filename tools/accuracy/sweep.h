// tools/accuracy/sweep.h — error against time: render a scene at a ladder of
// sample counts per configuration and measure each image against a reference.
//
// Every render goes through rt::render_archive (so it is what pbrtrun would
// give for the same overrides), writing no file. A configuration's rungs are
// the passes of one render at the top rung (renderer.h: a pass that ends at a
// rung holds exactly that rung's samples), measured as the render goes, and the
// ladder's time budget is that render's --time-limit. Samplers that stratify over
// the whole count (stratified, 02sequence, maxmindist) render each rung on its
// own instead, since a pass of a longer render is not their render of that
// count. `seconds` is what a user waits for a render to that count after the
// archive is loaded (scene build, sampler and integrator setup, the render loop
// to that pass); `render_seconds` is the render loop alone. Rungs of one
// configuration use the same seed.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "format/scene_archive.h"
#include "runtime/film/image_io.h"
#include "tools/accuracy/image_error.h"
#include "tools/accuracy/spp_ladder.h"
#include "tools/accuracy/sweep_config.h"

namespace accuracy {

struct SweepOptions {
  LadderBudget budget;
  int resdiv = 1;
  uint64_t seed = 1;
};

struct SweepRow {
  std::string scene, config;
  int spp = 0;
  double seconds = 0, render_seconds = 0;
  ImageErrors errors;
  double estimated_error = -1;  // the render's own estimate (error_estimate.h); -1: none
};

// One render to memory with a configuration's overrides.
bool render_image(const pbrta::SceneArchive& archive, const SweepConfig& config, int spp,
                  int resdiv, uint64_t seed, rt::ImageRgb* image, double* seconds,
                  double* render_seconds, std::string* error);

// Appends one row per rung of every configuration to *rows (calling
// on_row after each, e.g. for progress). Fails on the first render or
// comparison that fails, with the configuration named in *error.
bool run_sweep(const pbrta::SceneArchive& archive, const std::string& scene_name,
               const rt::ImageRgb& reference, const std::vector<SweepConfig>& configs,
               const SweepOptions& options, std::vector<SweepRow>* rows, std::string* error,
               const std::function<void(const SweepRow&)>& on_row = {});

// This project's reference: two renders of the scene's own configuration at
// spp/2 each with seeds seed and seed + 1, and their average (*mean), which
// has spp samples. The halves are what the noise-aware convergence test
// (tools/compare/convergence.h) takes to check the reference against pbrt-v3's.
bool render_reference(const pbrta::SceneArchive& archive, int spp, int resdiv, uint64_t seed,
                      rt::ImageRgb* half_a, rt::ImageRgb* half_b, rt::ImageRgb* mean,
                      std::string* error);

}  // namespace accuracy
