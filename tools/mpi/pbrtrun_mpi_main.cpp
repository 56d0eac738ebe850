// tools/mpi/pbrtrun_mpi_main.cpp — pbrtrun-mpi: one image rendered by the ranks of an MPI job.
//
//   mpirun -np N pbrtrun-mpi scene.pbrta [every pbrtrun option] [--broadcast-archive]
//
// Every rank loads the archive: from the path given (where "{rank}" becomes the rank, for
// nodes with their own copies), or, with --broadcast-archive, rank 0 reads it and sends the
// bytes to the others (nodes without a shared file system), which load them from a temporary
// file. A rank that cannot load it says so ("rank R: error: ...") and the job exits 1. Then
// every rank builds the scene and rank 0 leads the render (mpi_render.h): the same progress
// line, stopping rules, checkpoints, states and files as pbrtrun, the image of one process
// for the same seed. sppm and mlt are refused (they do not render in passes of tiles), and
// bdpt's strategy images (each rank's would hold only its own paths).
// If a rank dies the job ends (MPI's default error handler); --checkpoint-every with
// --save-state leaves a state that a rerun with --resume continues, losing at most one
// checkpoint interval. Test hooks: --slow-rank R --slow-tile-seconds S.
#include <mpi.h>
#include <unistd.h>

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>

#include "format/scene_archive.h"
#include "runtime/core/clock.h"
#include "runtime/render/integrator.h"
#include "runtime/render/pbrtrun_cli.h"
#include "runtime/render/render_job.h"
#include "runtime/render/stop_flags.h"
#include "tools/mpi/mpi_render.h"

namespace {

int g_rank = 0;

// Ends the job with `code` on every rank (all ranks call it, after agreeing).
int finish(int code) {
  MPI_Finalize();
  return code;
}

// True on every rank when `ok` is true on every rank.
bool all_ok(bool ok) {
  int mine = ok ? 1 : 0, all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  return all == 1;
}

std::string rank_path(std::string path, int rank) {
  const std::string key = "{rank}";
  for (size_t at; (at = path.find(key)) != std::string::npos;)
    path.replace(at, key.size(), std::to_string(rank));
  return path;
}

// Rank 0's file bytes to every rank, each then loading them from a temporary file.
bool load_broadcast(const std::string& path, int threads, pbrta::SceneArchive* archive,
                    std::string* error) {
  std::string bytes;
  int64_t size = -1;
  if (g_rank == 0) {
    std::ifstream f(path, std::ios::binary);
    if (f) {
      bytes.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
      size = int64_t(bytes.size());
    }
  }
  MPI_Bcast(&size, 1, MPI_INT64_T, 0, MPI_COMM_WORLD);
  if (size < 0) {
    *error = path + ": rank 0 cannot read the archive to broadcast it";
    return false;
  }
  bytes.resize(size_t(size));
  for (int64_t at = 0; at < size;) {  // MPI counts are ints: 1 GiB at a time
    const int n = int(std::min<int64_t>(size - at, int64_t(1) << 30));
    MPI_Bcast(bytes.data() + at, n, MPI_BYTE, 0, MPI_COMM_WORLD);
    at += n;
  }
  if (g_rank == 0) return archive->load(path, threads, error);
  const char* tmpdir = std::getenv("TMPDIR");
  std::string name = std::string(tmpdir && *tmpdir ? tmpdir : "/tmp") + "/pbrtrun-mpi-XXXXXX";
  const int fd = mkstemp(name.data());
  if (fd < 0) {
    *error = "cannot create a temporary file for the broadcast archive in " + name;
    return false;
  }
  const bool written = ::write(fd, bytes.data(), bytes.size()) == ssize_t(bytes.size());
  ::close(fd);
  const bool ok = written && archive->load(name, threads, error);
  if (!written) *error = name + ": cannot write the broadcast archive";
  ::unlink(name.c_str());  // a mapping of it stays valid
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  int provided = 0, size = 1;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  auto say = [](const std::string& m) { std::cerr << "pbrtrun-mpi: " << m << "\n"; };

  CLI::App app{"pbrtrun-mpi: render a pbrtc scene archive with the ranks of an MPI job"};
  rt::PbrtrunArgs args;
  rt::add_options(&app, &args);
  bool broadcast = false;
  mpi_render::Slowdown slow;
  app.add_flag("--broadcast-archive", broadcast,
               "Rank 0 reads the archive and sends it to the other ranks");
  app.add_option("--slow-rank", slow.rank, "Test hook: this rank sleeps after each tile");
  app.add_option("--slow-tile-seconds", slow.seconds_per_tile,
                 "Test hook: how long --slow-rank sleeps per tile");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = g_rank == 0 ? app.exit(e) : (e.get_exit_code() == 0 ? 0 : 2);
    return finish(code == 0 ? 0 : 2);
  }
  rt::RenderJobOptions job;
  std::string error;
  if (!rt::to_job(args, &job, &error)) {
    if (g_rank == 0) say(error);
    return finish(2);
  }
  const int threads = args.nthreads > 0 ? args.nthreads : int(tbb::info::default_concurrency());
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
  auto t_start = std::chrono::steady_clock::now();

  pbrta::SceneArchive archive;
  archive.skip_source_texels();
  const std::string path = rank_path(args.input, g_rank);
  const bool loaded = broadcast ? load_broadcast(path, threads, &archive, &error)
                                : archive.load(path, threads, &error);
  if (!loaded) say("rank " + std::to_string(g_rank) + ": error: " + error);
  if (!all_ok(loaded)) {
    if (g_rank == 0 && loaded) say("error: another rank could not load the archive");
    return finish(1);
  }
  const double t_archive = rt::seconds_since(t_start);
  rt::IntegratorSettings settings;
  if (!rt::read_integrator(archive, &settings, &error) ||
      settings.type == rt::IntegratorType::kMlt || settings.type == rt::IntegratorType::kSppm ||
      settings.bdpt_visualize_strategies || settings.bdpt_visualize_weights) {
    const std::string type(archive.type_name(archive.scene().integrator));
    if (g_rank == 0)
      say(!error.empty() ? error
          : settings.type == rt::IntegratorType::kBdpt
              ? "not supported yet: bdpt's visualizestrategies/visualizeweights under MPI (the "
                "strategy images would hold rank 0's paths only)"
              : "not supported yet: the " + type +
                    " integrator under MPI (it does not render in passes of tiles)");
    return finish(1);
  }

  job.time_origin = t_start;
  bool led = false;
  if (g_rank == 0) {
    job.interrupt = rt::install_interrupt_handlers();
    job.render_loop = [&](const rt::Camera& c, const rt::Sampler& s, const rt::Integrator& i,
                          rt::Film* f, const rt::RenderOptions& o) {
      led = true;
      return mpi_render::lead(c, s, i, f, o, size, threads, slow);
    };
  } else {
    job.quiet = true;
    job.write_files = false;
    job.save_state.clear();
    job.resume.clear();
    job.render_loop = [&](const rt::Camera& c, const rt::Sampler& s, const rt::Integrator& i,
                          rt::Film* f, const rt::RenderOptions& o) {
      return mpi_render::follow(c, s, i, f, o, g_rank, threads, slow);
    };
  }
  rt::RenderJobResult result;
  const bool ok = rt::render_archive(archive, job, &result, &error);
  if (g_rank == 0 && !led) {  // failed before the render: release the others
    const char nothing = 0;
    for (int r = 1; r < size; ++r)
      MPI_Send(&nothing, 1, MPI_BYTE, r, mpi_render::kStop, MPI_COMM_WORLD);
    uint64_t zero[7] = {}, sum[7];
    MPI_Reduce(zero, sum, 7, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
  }
  int code = 0;
  if (g_rank == 0) {
    if (!ok) {
      bool print = true;
      code = rt::failed_render_status(result, args.quiet, &print);
      if (print) say(error);
    } else if (args.show_stats) {
      std::string text =
          rt::format_render_stats(args.input, result, t_archive, threads, rt::peak_memory_mib());
      text += "  MPI ranks              " + std::to_string(size) + " x " + std::to_string(threads) +
              " threads\n";
      std::fputs(text.c_str(), stderr);
    }
  } else if (!ok) {
    say("rank " + std::to_string(g_rank) + ": " + error);
    code = 1;
  }
  MPI_Bcast(&code, 1, MPI_INT, 0, MPI_COMM_WORLD);
  return finish(code);
}
