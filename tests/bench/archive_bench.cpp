// archive_bench — archive size, compile time and load time against parsing. Never run in CI.
//
//   archive_bench [--repeat N] [--threads T] SCENE.pbrt...
//   archive_bench [--repeat N] [--threads T] --load ARCHIVE   (load only: for profiling, and
//   for side-by-side comparisons of two builds on their own archives)
//   ARCHIVE_BENCH_DRACO_IN_PROCESS=1 decodes Draco sections in this process instead of in
//   budgeted children (format/isolated_jobs.h), to measure what the isolation costs.
//
// For each scene: the bytes the compile read (scene text, meshes, images) and the archive's
// bytes with zstd and with --codec none; the time to parse the text into a SceneDesc (this
// project's parser, single-threaded); the time to compile and write each archive; and the time
// to load each archive ready for the renderer (SceneArchive::load: mapped, every checksum
// verified, every section decoded, every record validated) with T threads, warm page cache,
// not counting the archive's destruction. Best of N runs (default 5) for every time.
//
// Beside the uncompressed load, two references (see kBaselineLegend): floor0, the time merely
// to get the file's bytes and checksum them, which bounds parse/0 for any loader that verifies
// them; and the parse and the load each timed once in a new process, as one run pays them.

#include <fcntl.h>
#include <sys/mman.h>
#include <time.h>

#include <sys/stat.h>
#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "compiler/archive_builder.h"
#include "compiler/parser.h"
#include "format/archive_reader.h"
#include "format/checksum.h"
#include "format/isolated_jobs.h"
#include "format/scene_archive.h"
#include "tests/compiler/compiled_scene.h"

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

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

// One parse of scene, timed as every parse here is: best_of(n, parse_timed(scene, &input)),
// the SceneDesc freed inside the timing. *input gets the bytes the compile read.
auto parse_timed(const std::string& scene, uint64_t* input) {
  return [scene, input] {
    pbrtc::CompiledScene c;
    pbrtc::compile_scene(scene, &c);
    *input = 0;
    for (const std::string& f : c.scene.input_files) *input += file_size(f);
    return c.ok;
  };
}

// Process CPU time, to read next to wall time on a shared machine: a load whose wall time far
// exceeds its CPU time / T was waiting for a core.
double cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

constexpr const char* kBaselineLegend =
    "load z, load 0: the zstd and the --codec none archive's load (T threads), best of N;\n"
    "  cpu z: the zstd load's process CPU time (all threads), best of N.\n"
    "parse/0 = parse s / load 0.\n"
    "  floor0: one thread getting the --codec none file's bytes and checksumming them, nothing\n"
    "          else: open, fstat, as the loader gets them (pread into new[] for files up to\n"
    "          64 KiB, a plain mmap whose pages the checksum faults in for larger ones),\n"
    "          checksum64 of every byte, free or munmap, close. Best of N.\n"
    "  parse/f: parse s / floor0, the most parse/0 a checked one-thread load can reach.\n"
    "first in a new process (1: parse, load 0, parse/0): the same parse and --codec none load,\n"
    "  each the only one in a process of its own, best of N processes: what one run of pbrtc or\n"
    "  pbrtrun pays.\n";

// floor0 (see kBaselineLegend): the best of n times to get path's bytes into memory as the
// loader does, and checksum them; -1 if the file cannot be read.
double time_floor(const std::string& path, int n) {
  auto once = [&]() {
    const auto t = Clock::now();
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    struct stat st;
    if (fd < 0 || ::fstat(fd, &st) != 0 || st.st_size <= 0) {
      if (fd >= 0) ::close(fd);
      return -1.0;
    }
    const size_t size = size_t(st.st_size);
    // Small files are read into the heap, as in the loader; in a process that loads
    // repeatedly, new[] of a large block would reuse pages already faulted in, which a single
    // load never has.
    const bool small = size <= (size_t{64} << 10);
    std::unique_ptr<uint8_t[]> heap;
    void* p = MAP_FAILED;
    if (small) {
      heap.reset(new uint8_t[size]);
      p = heap.get();
    } else {
      p = mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0);
    }
    bool ok = p != MAP_FAILED;
    if (ok && small) ok = ::pread(fd, p, size, 0) == ssize_t(size);
    volatile uint64_t sum = ok ? pbrta::checksum64(p, size) : 0;
    (void)sum;
    if (!small && p != MAP_FAILED) munmap(p, size);
    ::close(fd);
    return ok ? since(t) : -1.0;
  };
  double best = 1e30;
  for (int i = 0; i < n; ++i) {
    const double s = once();
    if (s < 0) return -1;
    best = std::min(best, s);
  }
  return best;
}

// Best of n SceneArchive::load times (wall and process CPU), destruction not timed.
bool time_load(const std::string& path, int n, int threads, double* wall, double* cpu) {
  *wall = *cpu = 1e30;
  for (int i = 0; i < n; ++i) {
    auto a = std::make_unique<pbrta::SceneArchive>();
    std::string error;
    const double c = cpu_seconds();
    const auto t = Clock::now();
    const bool ok = a->load(path, threads, &error);
    *wall = std::min(*wall, since(t));
    *cpu = std::min(*cpu, cpu_seconds() - c);
    if (!ok) {
      std::fprintf(stderr, "%s\n", error.c_str());
      return false;
    }
  }
  return true;
}

// The first parse or load in a new process, which is what one run of pbrtc or pbrtrun pays:
// its heap and code pages are all new, where the best of N in one process reuses the memory
// earlier rounds faulted in (the parse's allocator recycles it; the loader's own huge-page
// mappings are new every time). The child (this program with --once) times only the one
// parse or load, not its own start. Best of n children; -1 on failure.
double time_in_new_process(const char* what, const std::string& path, int threads, int n) {
  double best = 1e30;
  for (int i = 0; i < n; ++i) {
    const std::string command = "'/proc/" + std::to_string(getpid()) + "/exe' --once " + what +
                                " '" + path + "' " + std::to_string(threads);
    FILE* child = popen(command.c_str(), "r");
    double s = -1;
    if (child == nullptr) return -1;
    const bool got = std::fscanf(child, "%lf", &s) == 1;
    if (pclose(child) != 0 || !got || s < 0) return -1;
    best = std::min(best, s);
  }
  return best;
}

// --once parse|load PATH T: one parse or one load, timed by the same code as in-process ones
// (so a load's destruction is left out, a parse's is not), its seconds on stdout.
int run_once(const std::string& what, const std::string& path, int threads) {
  double s = -1, cpu = 0;
  uint64_t input = 0;
  if (what == "parse")
    s = best_of(1, parse_timed(path, &input));
  else if (what == "load" && !time_load(path, 1, threads, &s, &cpu))
    s = -1;
  if (s < 0) return 1;
  std::printf("%.9f\n", s);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (std::getenv("ARCHIVE_BENCH_DRACO_IN_PROCESS") != nullptr) pbrta::set_isolation_enabled(false);
  if (argc == 5 && !std::strcmp(argv[1], "--once"))
    return run_once(argv[2], argv[3], std::atoi(argv[4]));
  int repeat = 5, threads = 2;
  std::vector<std::string> scenes;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--load") && i + 1 < argc) {
      scenes = {argv[i], argv[i + 1]};
      ++i;
    } else if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc)
      repeat = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc)
      threads = std::atoi(argv[++i]);
    else
      scenes.push_back(argv[i]);
  }
  // --load ARCHIVE: only load it, repeatedly.
  if (scenes.size() == 2 && scenes[0] == "--load") {
    double wall = 0, cpu = 0;
    if (!time_load(scenes[1], repeat, threads, &wall, &cpu)) return 1;
    std::printf("%s: load %.7f s (cpu %.7f s), %d threads, best of %d\n", scenes[1].c_str(), wall,
                cpu, threads, repeat);
    return 0;
  }
  if (scenes.empty()) {
    std::fprintf(stderr, "usage: archive_bench [--repeat N] [--threads T] SCENE.pbrt...\n");
    return 2;
  }
  std::printf("%s", kBaselineLegend);
  std::printf("%-44s %9s %9s %9s %6s | %8s %8s %8s | %8s %8s %6s %8s %7s | %8s %8s %7s | %8s\n",
              "scene", "input MB", "zstd MB", "raw MB", "z/raw", "parse s", "compile", "(raw)",
              "load z", "load 0", "parse/0", "floor0", "parse/f", "1: parse", "load 0", "parse/0",
              "cpu z");
  for (const std::string& scene : scenes) {
    // Per process: other runs of this benchmark may share /tmp.
    const std::string stem = "/tmp/archive_bench." + std::to_string(getpid());
    const std::string az = stem + ".z.pbrta", an = stem + ".n.pbrta";
    uint64_t input = 0;
    double parse = best_of(repeat, parse_timed(scene, &input));
    auto compile = [&](bool compress, const std::string& out) {
      return best_of(std::max(1, repeat / 2), [&] {
        pbrtc::CompiledScene c;
        pbrtc::compile_scene(scene, &c);
        if (!c.ok) return false;
        pbrtc::ArchiveOptions opt;
        opt.compress = compress;
        opt.threads = threads;
        std::string error;
        return pbrtc::write_archive(c.scene, c.files, pbrtc::directory_of(scene), out, opt, nullptr,
                                    &error);
      });
    };
    double compile_z = parse < 0 ? -1 : compile(true, az);
    double compile_n = compile_z < 0 ? -1 : compile(false, an);
    if (compile_n < 0) {  // a scene pbrtc refuses (the corpus lacks some files): not a failure
      std::printf("%-44s does not compile: skipped\n",
                  (scene.size() > 44 ? "..." + scene.substr(scene.size() - 41) : scene).c_str());
      std::remove(az.c_str());
      continue;
    }
    // Each load timed back to back, N loads in a row, as the parse it is compared with is.
    double load_z = 0, cpu_z = 0, load_n = 0, cpu_n = 0;
    if (!time_load(az, repeat, threads, &load_z, &cpu_z) ||
        !time_load(an, repeat, threads, &load_n, &cpu_n))
      return 1;
    const double floor0 = time_floor(an, repeat);
    const double parse1 = time_in_new_process("parse", scene, threads, repeat);
    const double load1 = time_in_new_process("load", an, threads, repeat);
    uint64_t zb = file_size(az), nb = file_size(an);
    std::string name = scene.size() > 44 ? "..." + scene.substr(scene.size() - 41) : scene;
    std::printf(
        "%-44s %9.2f %9.2f %9.2f %5.0f%% | %8.4f %8.4f %8.4f | %8.4f %8.5f %6.0fx %8.5f %6.0fx | "
        "%8.4f %8.5f %6.0fx | %8.4f\n",
        name.c_str(), input / 1e6, zb / 1e6, nb / 1e6, 100.0 * double(zb) / double(nb), parse,
        compile_z, compile_n, load_z, load_n, parse / load_n, floor0, parse / floor0, parse1, load1,
        parse1 / load1, cpu_z);
    std::fflush(stdout);
    std::remove(az.c_str());
    std::remove(an.c_str());
  }
  return 0;
}
