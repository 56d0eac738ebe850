// runtime/render/pbrtrun_main.cpp — pbrtrun: render a compiled scene archive.
//
//   pbrtrun scene.pbrta [--outfile x.exr] [--spp N] [--resdiv K]
//           [--cropwindow x0 x1 y0 y1] [--nthreads N] [--seed N] [--quiet] [--stats]
//           [--target-error P] [--time-limit T] [--checkpoint-every T] [--error-layer]
//           [--save-state FILE] [--resume FILE] [--shard K/N]
//
// Loads the archive (validated, no text parsing), builds Embree's scene and
// the integrator, renders with a progress bar and writes float32 OpenEXR (or
// an sRGB PNG preview for a .png name; --preview adds one beside the EXR).
// Anything the renderer cannot do yet stops before rendering with
// "not supported yet: <feature> (file:line)". Exit codes: 0 rendered,
// 1 bad archive or unsupported scene, 2 bad command line or output path,
// 128 + signal when SIGINT or SIGTERM stopped it (after writing the image so far).
#include <sys/resource.h>

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "format/scene_archive.h"
#include "runtime/core/clock.h"
#include "runtime/render/render_job.h"
#include "runtime/render/stop_flags.h"

namespace {

double peak_memory_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_maxrss) / 1024.0;
}

int fail(const std::string& message, int code = 1) {
  std::cerr << "pbrtrun: " << message << "\n";
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"pbrtrun: render a pbrtc scene archive (.pbrta) to OpenEXR"};
  std::string input, outfile, preview;
  int spp = 0, resdiv = 1, nthreads = 0;
  uint64_t seed = 0;
  std::vector<float> crop;
  bool quiet = false, show_stats = false;
  app.add_option("archive", input, "The scene archive written by pbrtc")->required();
  app.add_option("-o,--outfile", outfile,
                 "Write the image to this file (.exr: float32 OpenEXR; .png: sRGB preview); "
                 "default: the film's filename");
  app.add_option("--preview", preview, "Also write an sRGB PNG preview to this file");
  app.add_option("--spp", spp, "Samples per pixel (overrides the scene's sampler)")
      ->check(CLI::PositiveNumber);
  app.add_option("--resdiv", resdiv, "Divide the film resolution by this integer")
      ->check(CLI::PositiveNumber);
  app.add_option("--cropwindow", crop, "Render only this part of the image: x0 x1 y0 y1 in [0,1]")
      ->expected(4);
  app.add_option("--nthreads", nthreads, "Threads to render with (default: all cores)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--seed", seed, "Seed for every random choice (same seed, same image)");
  app.add_flag("-q,--quiet", quiet, "No progress bar or messages");
  bool watertight = false;
  app.add_flag("--watertight", watertight,
               "Close the cracks Embree leaves at shared mesh vertices (a box per vertex in the "
               "BVH: slower to build)");
  int differential_spp = 0;
  app.add_option("--differential-spp", differential_spp,
                 "Scale ray differentials (texture filtering) as for this many samples per pixel "
                 "instead of the rendered count (a render that is one of several averaged)")
      ->check(CLI::PositiveNumber);
  std::string target_error, time_limit, checkpoint_every, save_state, resume;
  bool error_layer = false;
  app.add_option("--target-error", target_error,
                 "Stop once the render's estimated error (relative RMS, percent) is this low, "
                 "e.g. 1 or 1%");
  app.add_option("--time-limit", time_limit,
                 "Stop before a pass that would end after this long (seconds, or 90s, 10m, 1h), "
                 "counted from the start");
  app.add_option("--checkpoint-every", checkpoint_every,
                 "Write the image so far (and the state, with --save-state) this often");
  app.add_flag("--error-layer", error_layer,
               "Add the per-pixel error estimate to the EXR as layer \"error\"");
  app.add_option("--save-state", save_state,
                 "Write the render's raw sums to this file (for pbrt-merge and --resume)");
  app.add_option("--resume", resume, "Continue the render a --save-state file holds");
  std::string shard;
  app.add_option("--shard", shard,
                 "Render only the K-th of N equal sample ranges (K/N, 1-based) to the "
                 "--save-state file; pbrt-merge joins the N states into the whole render");
  app.add_flag("--stats", show_stats,
               "Print the effects simulated, rays traced, load/build/render times and peak memory");
  CLI11_PARSE(app, argc, argv);

  if (!crop.empty() && (crop[0] < 0 || crop[1] > 1 || crop[2] < 0 || crop[3] > 1 ||
                        crop[0] >= crop[1] || crop[2] >= crop[3]))
    return fail("error: --cropwindow needs 0 <= x0 < x1 <= 1 and 0 <= y0 < y1 <= 1", 2);
  rt::RenderJobOptions job;
  if (!target_error.empty() && !rt::parse_percent(target_error, &job.target_error))
    return fail("error: --target-error needs a percentage above 0, such as 1 or 0.5%, not \"" +
                    target_error + "\"",
                2);
  if (!time_limit.empty() && !rt::parse_duration(time_limit, &job.time_limit))
    return fail("error: --time-limit needs a duration such as 90, 90s, 10m or 1h, not \"" +
                    time_limit + "\"",
                2);
  if (!checkpoint_every.empty() && !rt::parse_duration(checkpoint_every, &job.checkpoint_every))
    return fail("error: --checkpoint-every needs a duration such as 30s or 5m, not \"" +
                    checkpoint_every + "\"",
                2);
  if (!shard.empty()) {
    int k = 0, n = 0;
    char tail = 0;
    if (std::sscanf(shard.c_str(), "%d/%d%c", &k, &n, &tail) != 2 || k < 1 || n < 1 || k > n)
      return fail("error: --shard needs K/N with 1 <= K <= N, such as 3/8, not \"" + shard + "\"",
                  2);
    if (save_state.empty())
      return fail("error: --shard renders part of the samples: give --save-state for pbrt-merge",
                  2);
    job.shard = k - 1;
    job.shards = n;
  }
  int threads = nthreads > 0 ? nthreads : int(tbb::info::default_concurrency());
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
  auto t_start = std::chrono::steady_clock::now();
  job.time_origin = t_start;
  job.interrupt = rt::install_interrupt_handlers();

  pbrta::SceneArchive archive;
  std::string error;
  if (!archive.load(input, threads, &error)) return fail("error: " + error);
  double t_archive = rt::seconds_since(t_start);

  job.outfile = outfile;
  job.preview = preview;
  job.spp = spp;
  job.resdiv = resdiv;
  if (!crop.empty()) {
    job.has_crop = true;
    for (int i = 0; i < 4; ++i) job.crop[i] = crop[i];
  }
  job.seed = seed;
  job.quiet = quiet;
  job.watertight = watertight;
  job.differential_spp = differential_spp;
  job.error_layer = error_layer;
  job.save_state = save_state;
  job.resume = resume;
  rt::RenderJobResult result;
  if (!rt::render_archive(archive, job, &result, &error)) {
    if (result.interrupted) {
      if (!quiet) std::cerr << "pbrtrun: " << error << "\n";
      return 128 + rt::interrupt_signal();
    }
    return fail(error, result.bad_output ? 2 : 1);
  }
  if (show_stats)
    std::fputs(
        rt::format_render_stats(input, result, t_archive, threads, peak_memory_mib()).c_str(),
        stderr);
  return 0;
}
