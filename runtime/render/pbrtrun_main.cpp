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
#include "runtime/render/pbrtrun_cli.h"
#include "runtime/render/render_job.h"
#include "runtime/render/stop_flags.h"

namespace {

int fail(const std::string& message, int code = 1) {
  std::cerr << "pbrtrun: " << message << "\n";
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"pbrtrun: render a pbrtc scene archive (.pbrta) to OpenEXR"};
  rt::PbrtrunArgs args;
  rt::add_options(&app, &args);
  CLI11_PARSE(app, argc, argv);
  rt::RenderJobOptions job;
  std::string error;
  if (!rt::to_job(args, &job, &error)) return fail(error, 2);
  const int threads = args.nthreads > 0 ? args.nthreads : int(tbb::info::default_concurrency());
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
  auto t_start = std::chrono::steady_clock::now();
  job.time_origin = t_start;
  job.interrupt = rt::install_interrupt_handlers();

  pbrta::SceneArchive archive;
  archive.skip_source_texels();
  if (!archive.load(args.input, threads, &error)) return fail("error: " + error);
  double t_archive = rt::seconds_since(t_start);

  rt::RenderJobResult result;
  if (!rt::render_archive(archive, job, &result, &error)) {
    bool print = true;
    const int status = rt::failed_render_status(result, args.quiet, &print);
    if (print) std::cerr << "pbrtrun: " << error << "\n";
    return status;
  }
  if (args.show_stats)
    std::fputs(
        rt::format_render_stats(args.input, result, t_archive, threads, rt::peak_memory_mib())
            .c_str(),
        stderr);
  return 0;
}
