// tools/accuracy/pbrt_converge_main.cpp — pbrt-converge: error against time.
//
//   pbrt-converge scene.pbrta --reference REF.exr --csv OUT.csv --plot OUT.png
//       (--converge REF.exr is the same as --reference REF.exr)
//       [--table OUT.md] [--min-spp N] [--max-spp N] [--max-seconds S]
//       [--samplers a,b,...] [--integrators a,b] [--strategies a,b,...]
//       [--resdiv K] [--seed N] [--nthreads N] [--name NAME] [--quiet]
//   pbrt-converge scene.pbrta --make-reference OUT.exr [--reference-spp N] [...]
//
// Renders the scene at spp min, 2 min, ... up to --max-spp (or while the next
// rung is predicted to fit in --max-seconds per configuration) for every
// configuration (sweep_config.h), measures each image against the reference
// (image_error.h), and writes the CSV (sweep_csv.h), the log-log plot
// (error_plot.h) and a Markdown table of the time to 5%/2%/1% relative error
// (time_to_error.h). --make-reference renders this project's reference at
// --reference-spp (default 16 x --max-spp) as two halves with seeds
// --reference-seed and the next one, writing OUT.exr (their mean) and
// OUT-a.exr / OUT-b.exr (the halves, for tools/compare's convergence check
// against pbrt-v3); without --reference the sweep then measures against it.
// Exit codes: 0 done, 1 a render or file failed, 2 bad command line.
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "format/scene_archive.h"
#include "runtime/core/clock.h"
#include "tools/accuracy/error_plot.h"
#include "tools/accuracy/sweep.h"
#include "tools/accuracy/sweep_config.h"
#include "tools/accuracy/sweep_csv.h"
#include "tools/accuracy/time_to_error.h"

namespace {

int fail(const std::string& message, int code = 1) {
  std::cerr << "pbrt-converge: " << message << "\n";
  return code;
}

std::string stem_of(const std::string& path) {
  size_t slash = path.find_last_of('/');
  std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  size_t dot = name.find_last_of('.');
  return dot == std::string::npos ? name : name.substr(0, dot);
}

// OUT.exr -> OUT<suffix>.exr
std::string beside(const std::string& path, const std::string& suffix) {
  size_t dot = path.find_last_of('.');
  size_t slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return path + suffix;
  return path.substr(0, dot) + suffix + path.substr(dot);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"pbrt-converge: error against time for a pbrtc scene archive"};
  std::string input, reference_path, csv_path, plot_path, table_path, make_reference, name;
  std::string samplers, integrators, strategies;
  accuracy::SweepOptions sweep;
  int reference_spp = 0, nthreads = 0;
  uint64_t reference_seed = 1000;
  bool quiet = false;
  app.add_option("archive", input, "The scene archive written by pbrtc")->required();
  // --converge: the spelling issue 9 gives for pbrtrun's option of the same meaning.
  app.add_option("--reference,--converge", reference_path,
                 "Reference image (EXR) the renders are measured against");
  app.add_option("--csv", csv_path, "Write the sweep as CSV here");
  app.add_option("--plot", plot_path, "Write the log-log plot (PNG) here");
  app.add_option("--table", table_path, "Write the time-to-error Markdown table here");
  app.add_option("--min-spp", sweep.budget.min_spp, "First rung of the ladder (default 1)")
      ->check(CLI::PositiveNumber);
  app.add_option("--max-spp", sweep.budget.max_spp, "Largest rung (default 64)")
      ->check(CLI::PositiveNumber);
  app.add_option("--max-seconds", sweep.budget.max_seconds,
                 "Per configuration: stop before a rung predicted to exceed this total")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--samplers", samplers,
                 "Comma list: random,stratified,halton,sobol,02sequence,maxmindist");
  app.add_option("--integrators", integrators, "Comma list: path,directlighting (,whitted)");
  app.add_option("--strategies", strategies,
                 "Comma list of path light strategies: uniform,power,spatial");
  app.add_option("--resdiv", sweep.resdiv, "Divide the film resolution (match the reference's)")
      ->check(CLI::PositiveNumber);
  app.add_option("--seed", sweep.seed, "Seed of the sweep's renders (default 1)");
  app.add_option("--make-reference", make_reference,
                 "Render this project's reference to this EXR (and its halves beside it)");
  app.add_option("--reference-spp", reference_spp, "Reference spp (default 16 x --max-spp)")
      ->check(CLI::PositiveNumber);
  app.add_option("--reference-seed", reference_seed,
                 "Seed of the reference's first half (default 1000)");
  app.add_option("--nthreads", nthreads, "Threads (default: all cores)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--name", name, "Scene name in the CSV and plot (default: the archive's stem)");
  app.add_flag("-q,--quiet", quiet, "No per-render progress lines");
  bool plot_estimate = false;
  app.add_flag("--plot-estimate", plot_estimate,
               "Also plot each configuration's own error estimate (\"<config> estimated\")");
  CLI11_PARSE(app, argc, argv);

  if (sweep.budget.min_spp > sweep.budget.max_spp)
    return fail("error: --min-spp is above --max-spp", 2);
  bool sweeping = !csv_path.empty() || !plot_path.empty() || !table_path.empty();
  if (!sweeping && make_reference.empty())
    return fail("error: nothing to do: give --csv/--plot/--table and/or --make-reference", 2);
  if (sweeping && reference_path.empty() && make_reference.empty())
    return fail("error: a sweep needs --reference (or --make-reference)", 2);
  std::vector<accuracy::SweepConfig> configs;
  std::string error;
  if (!accuracy::make_configs(accuracy::split_list(samplers), accuracy::split_list(integrators),
                              accuracy::split_list(strategies), &configs, &error))
    return fail("error: " + error, 2);
  if (name.empty()) name = stem_of(input);

  int threads = nthreads > 0 ? nthreads : int(tbb::info::default_concurrency());
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
  auto t0 = std::chrono::steady_clock::now();
  pbrta::SceneArchive archive;
  archive.skip_source_texels();
  if (!archive.load(input, threads, &error)) return fail("error: " + error);
  double load_seconds = rt::seconds_since(t0);
  std::printf("pbrt-converge: %s: archive loaded in %.4f s\n", name.c_str(), load_seconds);

  rt::ImageRgb reference;
  if (!make_reference.empty()) {
    int spp = reference_spp > 0 ? reference_spp : 16 * sweep.budget.max_spp;
    rt::ImageRgb a, b;
    auto tr = std::chrono::steady_clock::now();
    if (!accuracy::render_reference(archive, spp, sweep.resdiv, reference_seed, &a, &b, &reference,
                                    &error))
      return fail("reference: " + error);
    if (!rt::write_exr(make_reference, reference, &error) ||
        !rt::write_exr(beside(make_reference, "-a"), a, &error) ||
        !rt::write_exr(beside(make_reference, "-b"), b, &error))
      return fail("error: " + error);
    std::printf("pbrt-converge: %s: reference at %d spp in %.2f s: %s\n", name.c_str(), spp,
                rt::seconds_since(tr), make_reference.c_str());
  }
  if (!sweeping) return 0;
  if (!reference_path.empty() && !rt::read_exr(reference_path, &reference, &error))
    return fail("error: " + error);

  std::vector<accuracy::SweepRow> rows;
  auto progress = [&](const accuracy::SweepRow& r) {
    if (quiet) return;
    std::printf(
        "  %-28s %6d spp %9.3f s  sqrt(relmse) %.4f  rmse %.4g  mare %.4f  estimated %.4f\n",
        r.config.c_str(), r.spp, r.seconds, std::sqrt(r.errors.relmse), r.errors.rmse,
        r.errors.mare, r.estimated_error);
    std::fflush(stdout);
  };
  if (!accuracy::run_sweep(archive, name, reference, configs, sweep, &rows, &error, progress))
    return fail(error);

  if (!csv_path.empty() && !accuracy::write_sweep_csv(csv_path, rows, &error))
    return fail("error: " + error);
  std::vector<accuracy::SweepRow> plotted = rows;
  if (plot_estimate)
    for (const accuracy::SweepRow& r : rows)
      if (r.estimated_error > 0) {
        accuracy::SweepRow e = r;
        e.config += " estimated";
        e.errors.relmse = r.estimated_error * r.estimated_error;
        plotted.push_back(e);
      }
  if (!plot_path.empty() &&
      !rt::write_png(plot_path, accuracy::plot_error_curves(plotted, name + ": error against time"),
                     &error))
    return fail("error: " + error);
  if (!table_path.empty()) {
    std::ofstream f(table_path, std::ios::binary);
    f << accuracy::time_to_error_table(name, rows, {0.05, 0.02, 0.01});
    if (!f) return fail("error: cannot write " + table_path);
  }
  return 0;
}
