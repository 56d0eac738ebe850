// tools/pbrt/pbrt_main.cpp — pbrt: pbrt-v3's command line, compiling (cached) then rendering.
//
//   pbrt [--nthreads num] [--outfile filename] [--quick] [--quiet]
//        [--cropwindow x0 x1 y0 y1] [--cat | --toply] [--spp N] [--seed N] [--stats]
//        [--preview file.png] [--cache-size size] [--no-cache]
//        [--target-error P] [--time-limit T] [--checkpoint-every T] [--error-layer]
//        [--save-state FILE] [--resume FILE] [scene.pbrt...]
//
// Each scene in turn (standard input when none is named) is compiled to an archive, or
// found in the cache of compiled archives (tools/pbrt/cache.h), then rendered by the same
// function pbrtrun uses (runtime/render/render_job.h), so the pixels are pbrtrun's.
// --cat and --toply print the compiled scene back as pbrt-v3 text instead of rendering.
// --quick is pbrt-v3's: resolution / 4, 1 sample per pixel, light nsamples / 4; being a
// render option, it never changes the cache key. Exit codes: 0 all rendered, 1 a scene
// failed (compile errors as "file:line:col: error: ...", "not supported yet: ..."),
// 2 bad command line or output path.

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <iterator>
#include <memory>
#include <string>

#include "compiler/archive_dump.h"
#include "runtime/render/render_job.h"
#include "runtime/render/stop_flags.h"
#include "tools/pbrt/cache.h"
#include "tools/pbrt/cached_compile.h"
#include "tools/pbrt/options.h"
#include "tools/pbrt/scene_compile.h"

namespace {

using pbrt_tool::Options;

// --cat: the scene with every mesh inline; --toply: every triangle mesh as a PLY file in
// the working directory. Images and lens files keep the names the scene gave them.
bool print_scene(const pbrta::SceneArchive& archive, const Options& o) {
  pbrtc::DumpOptions d;
  d.meshes = o.toply ? pbrtc::DumpMeshes::kAllPly : pbrtc::DumpMeshes::kInline;
  d.mesh_prefix = "mesh_";
  d.original_files = true;
  std::string text, error;
  if (!pbrtc::dump_archive_text(archive, ".", d, &text, &error)) {
    std::cerr << "pbrt: error: " << error << "\n";
    return false;
  }
  std::cout << text;
  std::cout.flush();
  return true;
}

// 0, 1 or 2 as the exit codes above.
int run_scene(const std::string& file, const Options& o, pbrt_tool::SceneCache* cache,
              int threads) {
  const auto start = std::chrono::steady_clock::now();  // --time-limit counts compiling too
  pbrt_tool::SceneSource source;
  source.path = file;
  if (source.is_stdin())
    source.text.assign(std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>());
  pbrt_tool::ObtainStats got;
  std::unique_ptr<pbrta::SceneArchive> archive =
      pbrt_tool::obtain_archive(source, cache, threads, o.quiet, &got);
  if (!archive) return 1;
  if (o.cat || o.toply) return print_scene(*archive, o) ? 0 : 1;

  rt::RenderJobOptions job;
  job.program = "pbrt";
  job.outfile = o.outfile;
  job.preview = o.preview;
  job.spp = o.spp;
  job.quick = o.quick;
  job.resdiv = o.quick ? 4 : 1;
  job.light_nsamples_divisor = o.quick ? 4 : 1;
  job.has_crop = o.has_crop;
  for (int i = 0; i < 4; ++i) job.crop[i] = o.crop[i];
  job.seed = o.seed;
  job.quiet = o.quiet;
  job.target_error = o.target_error;
  job.time_limit = o.time_limit;
  job.checkpoint_every = o.checkpoint_every;
  job.time_origin = start;
  job.error_layer = o.error_layer;
  job.save_state = o.save_state;
  job.resume = o.resume;
  job.interrupt = rt::install_interrupt_handlers();
  rt::RenderJobResult result;
  std::string error;
  if (!rt::render_archive(*archive, job, &result, &error)) {
    bool print = true;
    const int status = rt::failed_render_status(result, o.quiet, &print);
    if (print) std::cerr << "pbrt: " << error << "\n";
    return status;
  }
  if (o.stats) {
    std::fprintf(stderr, "pbrt: %s: cache: %s (lookup %.3f s, compile %.3f s, load %.3f s)%s%s\n",
                 source.display().c_str(), pbrt_tool::outcome_name(got.outcome), got.lookup_seconds,
                 got.compile_seconds, got.load_seconds, got.archive_path.empty() ? "" : " ",
                 got.archive_path.c_str());
    std::fputs(rt::format_render_stats(source.display(), result, got.load_seconds, threads,
                                       rt::peak_memory_mib())
                   .c_str(),
               stderr);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  std::string error;
  if (!pbrt_tool::parse_options(argc, argv, &o, &error)) {
    std::cerr << "pbrt: error: " << error << "\n" << pbrt_tool::usage_text();
    return 2;
  }
  if (o.help) {
    std::cout << pbrt_tool::usage_text();
    return 0;
  }
  if (o.files.empty()) o.files.push_back("-");
  const int threads = o.nthreads > 0 ? o.nthreads : int(tbb::info::default_concurrency());
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));

  std::unique_ptr<pbrt_tool::SceneCache> cache;
  if (!o.no_cache) {
    cache = std::make_unique<pbrt_tool::SceneCache>(pbrt_tool::SceneCache::default_dir(),
                                                    o.cache_bytes);
    if (!cache->open(&error)) {
      std::cerr << "pbrt: warning: " << error << "; compiling without the cache\n";
      cache.reset();
    }
  }
  int status = 0;
  for (const std::string& file : o.files) {
    int s = run_scene(file, o, cache.get(), threads);
    if (s > status) status = s;
  }
  return status;
}
