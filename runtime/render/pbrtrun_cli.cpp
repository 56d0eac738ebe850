// runtime/render/pbrtrun_cli.cpp — see pbrtrun_cli.h.
#include "runtime/render/pbrtrun_cli.h"

#include <cstdio>

#include "runtime/render/stop_flags.h"

namespace rt {

void add_options(CLI::App* app, PbrtrunArgs* a) {
  app->add_option("archive", a->input, "The scene archive written by pbrtc")->required();
  app->add_option("-o,--outfile", a->outfile,
                  "Write the image to this file (.exr: float32 OpenEXR; .png: sRGB preview); "
                  "default: the film's filename");
  app->add_option("--preview", a->preview, "Also write an sRGB PNG a->preview to this file");
  app->add_option("--spp", a->spp, "Samples per pixel (overrides the scene's sampler)")
      ->check(CLI::PositiveNumber);
  app->add_option("--resdiv", a->resdiv, "Divide the film resolution by this integer")
      ->check(CLI::PositiveNumber);
  app->add_option("--cropwindow", a->crop,
                  "Render only this part of the image: x0 x1 y0 y1 in [0,1]")
      ->expected(4);
  app->add_option("--nthreads", a->nthreads, "Threads to render with (default: all cores)")
      ->check(CLI::NonNegativeNumber);
  app->add_option("--seed", a->seed, "Seed for every random choice (same seed, same image)");
  app->add_flag("-q,--quiet", a->quiet, "No progress bar or messages");
  app->add_flag("--watertight", a->watertight,
                "Close the cracks Embree leaves at shared mesh vertices (a box per vertex in the "
                "BVH: slower to build)");
  app->add_option("--differential-spp", a->differential_spp,
                  "Scale ray differentials (texture filtering) as for this many samples per pixel "
                  "instead of the rendered count (a render that is one of several averaged)")
      ->check(CLI::PositiveNumber);
  app->add_option("--target-error", a->target_error,
                  "Stop once the render's estimated error (relative RMS, percent) is this low, "
                  "e.g. 1 or 1%");
  app->add_option("--time-limit", a->time_limit,
                  "Stop before a pass that would end after this long (seconds, or 90s, 10m, 1h), "
                  "counted from the start");
  app->add_option("--checkpoint-every", a->checkpoint_every,
                  "Write the image so far (and the state, with --save-state) this often");
  app->add_flag("--error-layer", a->error_layer,
                "Add the per-pixel error estimate to the EXR as layer \"error\"");
  app->add_option("--save-state", a->save_state,
                  "Write the render's raw sums to this file (for pbrt-merge and --resume)");
  app->add_option("--resume", a->resume, "Continue the render a --save-state file holds");
  app->add_option("--shard", a->shard,
                  "Render only the K-th of N equal sample ranges (K/N, 1-based) to the "
                  "--save-state file; pbrt-merge joins the N states into the whole render");
  app->add_flag(
      "--stats", a->show_stats,
      "Print the effects simulated, rays traced, load/build/render times and peak memory");
}

bool to_job(const PbrtrunArgs& a, RenderJobOptions* job, std::string* error) {
  auto fail = [&](const std::string& message) {
    *error = message;
    return false;
  };
  if (!a.crop.empty() && (a.crop[0] < 0 || a.crop[1] > 1 || a.crop[2] < 0 || a.crop[3] > 1 ||
                          a.crop[0] >= a.crop[1] || a.crop[2] >= a.crop[3]))
    return fail("error: --cropwindow needs 0 <= x0 < x1 <= 1 and 0 <= y0 < y1 <= 1");
  const struct {
    const char* flag;
    const std::string& text;
    double* value;
  } stops[] = {{"target-error", a.target_error, &job->target_error},
               {"time-limit", a.time_limit, &job->time_limit},
               {"checkpoint-every", a.checkpoint_every, &job->checkpoint_every}};
  for (const auto& stop : stops)
    if (!stop.text.empty() && !rt::parse_stop_value(stop.flag, stop.text, stop.value, error)) {
      *error = "error: " + *error;
      return false;
    }
  if (!a.shard.empty()) {
    int k = 0, n = 0;
    char tail = 0;
    if (std::sscanf(a.shard.c_str(), "%d/%d%c", &k, &n, &tail) != 2 || k < 1 || n < 1 || k > n)
      return fail("error: --shard needs K/N with 1 <= K <= N, such as 3/8, not \"" + a.shard +
                  "\"");
    if (!a.resume.empty())
      return fail("error: --shard and --resume cannot be given together (a shard is a new render)");
    if (a.save_state.empty())
      return fail("error: --shard renders part of the samples: give --save-state for pbrt-merge");
    job->shard = k - 1;
    job->shards = n;
  }
  job->outfile = a.outfile;
  job->preview = a.preview;
  job->spp = a.spp;
  job->resdiv = a.resdiv;
  if (!a.crop.empty()) {
    job->has_crop = true;
    for (int i = 0; i < 4; ++i) job->crop[i] = a.crop[i];
  }
  job->seed = a.seed;
  job->quiet = a.quiet;
  job->watertight = a.watertight;
  job->differential_spp = a.differential_spp;
  job->error_layer = a.error_layer;
  job->save_state = a.save_state;
  job->resume = a.resume;
  return true;
}

}  // namespace rt
