// archive_bench — archive size, compile time and load time against parsing. Never run in CI.
//
//   archive_bench [--repeat N] [--threads T] SCENE.pbrt...
//
// For each scene: the bytes the compile read (scene text, meshes, images) and the archive's
// bytes with zstd and with --codec none; the time to parse the text into a SceneDesc (this
// project's parser, single-threaded); the time to compile and write each archive; and the time
// to load each archive ready for the renderer (SceneArchive::load: mapped, every checksum
// verified, every section decoded, every record validated) with T threads, warm page cache. The
// zstd baseline is the sum of single-threaded ZSTD_decompress times of its compressed sections,
// divided by T. Best of N runs (default 5).
#include <zstd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <sys/stat.h>
#include <vector>

#include "compiler/archive_builder.h"
#include "compiler/parser.h"
#include "compiler/scene_builder.h"
#include "format/archive_reader.h"
#include "format/scene_archive.h"

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

uint64_t file_size(const std::string& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0 ? uint64_t(st.st_size) : 0;
}

template <class F>
double best_of(int n, F&& f) {
  double best = 1e30;
  for (int i = 0; i < n; ++i) {
    auto t = Clock::now();
    if (!f()) return -1;
    best = std::min(best, since(t));
  }
  return best;
}

// Sum of single-threaded ZSTD_decompress times over the archive's zstd sections (the raw bytes
// of shuffled sections are decompressed too; unshuffling is not counted). With warm set, into an
// output buffer already written (no page faults); otherwise into fresh memory, as a real load
// must.
double zstd_baseline(const std::string& path, int repeat, bool warm) {
  pbrta::ArchiveReader r;
  std::string error;
  if (!r.open(path, &error)) return -1;
  FILE* f = std::fopen(path.c_str(), "rb");
  std::vector<uint8_t> file(file_size(path));
  if (!f || std::fread(file.data(), 1, file.size(), f) != file.size()) return -1;
  std::fclose(f);
  double total = 0;
  ZSTD_DCtx* ctx = ZSTD_createDCtx();
  for (uint32_t i = 0; i < r.section_count(); ++i) {
    const pbrta::SectionEntry& e = r.entry(i);
    if (e.codec != uint32_t(pbrta::Codec::kZstd) && e.codec != uint32_t(pbrta::Codec::kZstdShuffle4))
      continue;
    std::vector<uint8_t> out(warm ? e.raw_size + 16 : 0);
    if (warm) std::memset(out.data(), 0, out.size());  // touched: no page faults in the timing
    total += best_of(repeat, [&] {
      if (warm)
        return !ZSTD_isError(ZSTD_decompressDCtx(ctx, out.data(), out.size(),
                                                 file.data() + e.offset, e.stored_size));
      std::unique_ptr<uint8_t[]> fresh(new uint8_t[e.raw_size + 16]);
      return !ZSTD_isError(ZSTD_decompressDCtx(ctx, fresh.get(), e.raw_size + 16,
                                               file.data() + e.offset, e.stored_size));
    });
  }
  ZSTD_freeDCtx(ctx);
  return total;
}

}  // namespace

int main(int argc, char** argv) {
  int repeat = 5, threads = 2;
  std::vector<std::string> scenes;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--load") && i + 1 < argc)
      scenes = {"--load", argv[++i]};
    else if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc)
      repeat = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc)
      threads = std::atoi(argv[++i]);
    else
      scenes.push_back(argv[i]);
  }
  // --load ARCHIVE: only load it, repeatedly (for profiling the loader).
  if (scenes.size() == 2 && scenes[0] == "--load") {
    double t = best_of(repeat, [&] {
      pbrta::SceneArchive a;
      std::string error;
      return a.load(scenes[1], threads, &error);
    });
    std::printf("%s: best load %.5f s\n", scenes[1].c_str(), t);
    return 0;
  }
  if (scenes.empty()) {
    std::fprintf(stderr, "usage: archive_bench [--repeat N] [--threads T] SCENE.pbrt...\n");
    return 2;
  }
  std::printf("%-44s %9s %9s %9s %6s | %8s %8s %8s | %8s %8s %6s | %8s %8s %5s %5s\n", "scene",
              "input MB", "zstd MB", "none MB", "z/none", "parse s", "compile", "(none)",
              "load z", "load 0", "parse/0", "zstd/T", "fresh/T", "ratio", "fresh");
  for (const std::string& scene : scenes) {
    std::string az = "/tmp/archive_bench.z.pbrta", an = "/tmp/archive_bench.n.pbrta";
    uint64_t input = 0;
    double parse = best_of(repeat, [&] {
      pbrtc::SourceFiles files;
      pbrtc::Diagnostics diag(&files, nullptr);
      pbrtc::SceneDesc s;
      bool ok = pbrtc::build_scene(scene, &files, &diag, &s);
      input = 0;
      for (const std::string& f : s.input_files) input += file_size(f);
      return ok;
    });
    auto compile = [&](bool compress, const std::string& out) {
      return best_of(std::max(1, repeat / 2), [&] {
        pbrtc::SourceFiles files;
        pbrtc::Diagnostics diag(&files, nullptr);
        pbrtc::SceneDesc s;
        if (!pbrtc::build_scene(scene, &files, &diag, &s)) return false;
        pbrtc::ArchiveOptions opt;
        opt.compress = compress;
        opt.threads = threads;
        std::string error;
        return pbrtc::write_archive(s, files, pbrtc::directory_of(scene), out, opt, nullptr,
                                    &error);
      });
    };
    double compile_z = compile(true, az), compile_n = compile(false, an);
    auto load = [&](const std::string& path) {
      return best_of(repeat, [&] {
        pbrta::SceneArchive a;
        std::string error;
        bool ok = a.load(path, threads, &error);
        if (!ok) std::fprintf(stderr, "%s\n", error.c_str());
        return ok;
      });
    };
    double load_z = load(az), load_n = load(an);
    double base = zstd_baseline(az, repeat, true) / threads;
    double fresh = zstd_baseline(az, repeat, false) / threads;
    uint64_t zb = file_size(az), nb = file_size(an);
    std::string name = scene.size() > 44 ? "..." + scene.substr(scene.size() - 41) : scene;
    std::printf("%-44s %9.2f %9.2f %9.2f %5.0f%% | %8.4f %8.4f %8.4f | %8.4f %8.5f %6.0fx | %8.4f "
                "%8.4f %5.2f %5.2f\n",
                name.c_str(), input / 1e6, zb / 1e6, nb / 1e6, 100.0 * double(zb) / double(nb),
                parse, compile_z, compile_n, load_z, load_n, parse / load_n, base, fresh,
                base > 0 ? load_z / base : 0, fresh > 0 ? load_z / fresh : 0);
    std::fflush(stdout);
  }
  return 0;
}
