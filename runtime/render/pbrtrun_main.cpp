// runtime/render/pbrtrun_main.cpp — pbrtrun: render a compiled scene archive.
//
//   pbrtrun scene.pbrta [--outfile x.exr] [--spp N] [--resdiv K]
//           [--cropwindow x0 x1 y0 y1] [--nthreads N] [--seed N] [--quiet] [--stats]
//
// Loads the archive (validated, no text parsing), builds Embree's scene and
// the integrator, renders with a progress bar and writes float32 OpenEXR (or
// an sRGB PNG preview for a .png name; --preview adds one beside the EXR).
// Anything the renderer cannot do yet stops before rendering with
// "not supported yet: <feature> (file:line)". Exit codes: 0 rendered,
// 1 bad archive or unsupported scene, 2 bad command line or output path.
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
  app.add_flag("--stats", show_stats,
               "Print the effects simulated, rays traced, load/build/render times and peak memory");
  CLI11_PARSE(app, argc, argv);

  if (!crop.empty() && (crop[0] < 0 || crop[1] > 1 || crop[2] < 0 || crop[3] > 1 ||
                        crop[0] >= crop[1] || crop[2] >= crop[3]))
    return fail("error: --cropwindow needs 0 <= x0 < x1 <= 1 and 0 <= y0 < y1 <= 1", 2);
  int threads = nthreads > 0 ? nthreads : int(tbb::info::default_concurrency());
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
  auto t_start = std::chrono::steady_clock::now();

  pbrta::SceneArchive archive;
  std::string error;
  if (!archive.load(input, threads, &error)) return fail("error: " + error);
  double t_archive = rt::seconds_since(t_start);

  rt::RenderJobOptions job;
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
  rt::RenderJobResult result;
  if (!rt::render_archive(archive, job, &result, &error))
    return fail(error, result.bad_output ? 2 : 1);
  if (show_stats)
    std::fputs(
        rt::format_render_stats(input, result, t_archive, threads, peak_memory_mib()).c_str(),
        stderr);
  return 0;
}
