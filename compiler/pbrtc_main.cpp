// pbrtc — the pbrt-v3 scene compiler's command line.
//
//   pbrtc scene.pbrt [-o scene.pbrta]   compile to an archive
//   pbrtc --check scene.pbrt...         parse and validate only, print a summary
//   pbrtc --info scene.pbrta            describe an archive
//   pbrtc --verify scene.pbrta          load and check an archive as pbrtrun does
//   pbrtc --dump scene.pbrta OUTDIR     write an archive back out as a pbrt-v3 scene
//   pbrtc --print-schema                the parameter schema as Markdown
//
// Diagnostics go to stderr as "path:line:col: error: message"; the exit code
// is 0 only if everything succeeded, and a failed compile writes nothing.
#include <CLI/CLI.hpp>

#include <tbb/global_control.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <optional>

#include "compiler/archive_builder.h"
#include "compiler/archive_dump.h"
#include "compiler/archive_info.h"
#include "compiler/compile_progress.h"
#include "compiler/diagnostics.h"
#include "compiler/parser.h"
#include "compiler/scene_builder.h"
#include "compiler/summary.h"
#include "format/scene_archive.h"

namespace {

std::string default_output(const std::string& input) {
  if (input == "-") return "stdin.pbrta";
  std::string base = input.substr(input.find_last_of('/') + 1);
  if (base.size() > 5 && base.compare(base.size() - 5, 5, ".pbrt") == 0)
    base.resize(base.size() - 5);
  return base + ".pbrta";
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// What Draco did: how many meshes it took, and the largest vertex displacement measured against
// the original vertices beside the bound the bits imply for that mesh (object space, per axis;
// Draco's float arithmetic may add a few ulps, the slack).
void print_draco_report(const std::string& path, int bits, const pbrtc::ArchiveStats& stats) {
  if (stats.draco_kept_lossless > 0)
    std::fprintf(stderr,
                 "pbrtc: %s: draco: %u meshes kept lossless (Draco failed or dropped degenerate "
                 "triangles)\n",
                 path.c_str(), stats.draco_kept_lossless);
  if (stats.draco.empty()) {
    std::fprintf(stderr, "pbrtc: %s: draco: no mesh qualified (64+ triangles, no tangents)\n",
                 path.c_str());
    return;
  }
  const pbrtc::DracoMeshStats* worst = &stats.draco[0];
  const pbrtc::DracoMeshStats* over = nullptr;
  uint64_t triangles = 0, stored = 0, raw = 0;
  for (const pbrtc::DracoMeshStats& d : stats.draco) {
    triangles += d.triangles;
    stored += d.stored_bytes;
    raw += d.raw_bytes;
    if (d.displacement > worst->displacement) worst = &d;
    if (!over && d.displacement > d.bound + d.slack) over = &d;
  }
  char verdict[160] = "every mesh within its bound";
  if (over)
    std::snprintf(verdict, sizeof verdict, "mesh %u EXCEEDS its bound (%.3g > %.3g + %.2g)",
                  over->mesh, over->displacement, over->bound, over->slack);
  std::fprintf(stderr,
               "pbrtc: %s: draco %d bits: %zu meshes (%llu triangles, %.2f MiB raw -> %.2f MiB); "
               "largest vertex displacement %.3g (mesh %u: bound %.3g + float rounding %.2g); "
               "%s\n",
               path.c_str(), bits, stats.draco.size(), (unsigned long long)triangles,
               double(raw) / (1 << 20), double(stored) / (1 << 20), worst->displacement,
               worst->mesh, worst->bound, worst->slack, verdict);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"pbrtc: compiles pbrt-v3 scenes into validated binary scene archives (.pbrta)"};
  std::vector<std::string> inputs;
  std::string outfile, codec = "zstd", texture_precision = "f32";
  bool check = false, info = false, verify = false, dump = false, print_schema = false;
  bool werror = false, quiet = false, draco_sequential = false;
  int max_errors = 20, zstd_level = 6, nthreads = 0, draco_bits = 0;
  app.add_option("files", inputs,
                 "pbrt-v3 scene files (\"-\" or none: standard input), or "
                 "archives with --info/--verify");
  app.add_option("-o,--outfile", outfile,
                 "archive to write (default: the scene's name with "
                 ".pbrta, in the current directory)");
  app.add_flag("--check", check, "parse and validate only; print a summary of each scene");
  app.add_flag("--info", info, "describe archives: version, effects, sections, counts");
  app.add_flag("--verify", verify, "load archives exactly as pbrtrun does; exit 0 only if sound");
  app.add_flag("--dump", dump,
               "write an archive back out as a pbrt-v3 scene: --dump A.pbrta "
               "OUTDIR (meshes as PLY, images as PFM beside it)");
  app.add_flag("--print-schema", print_schema, "print the parameter schema as Markdown");
  app.add_option("--codec", codec, "section compression: zstd (default) or none (usable in place)")
      ->check(CLI::IsMember({"zstd", "none"}));
  app.add_option("--zstd-level", zstd_level, "zstd level, 1-19 (default 6)")
      ->check(CLI::Range(1, 19));
  app.add_option("--draco-bits", draco_bits,
                 "lossy mesh compression: quantize positions of meshes of 64+ triangles to N "
                 "bits (8-30) with Draco; normals 10 bits, uv 12 (default 0: off)")
      ->check(CLI::Range(0, 0) | CLI::Range(8, 30));
  app.add_flag("--draco-sequential", draco_sequential,
               "with --draco-bits: keep vertex and triangle order (larger archives)");
  app.add_option("--texture-precision", texture_precision,
                 "texel storage of images (textures and light maps; environment-map sampling "
                 "distributions stay f32): f32 (default, lossless), f16 (half floats; values of "
                 "magnitude 65520+ refused) or unorm8 (linear bytes, value/255; values outside "
                 "[0, 1] refused)")
      ->check(CLI::IsMember({"f32", "f16", "unorm8"}));
  app.add_option("--nthreads", nthreads,
                 "threads for reading meshes, decoding images, compressing and loading "
                 "(default: all)")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--Werror", werror, "treat warnings as errors");
  app.add_flag("-q,--quiet", quiet, "print only errors and warnings");
  app.add_option("--max-errors", max_errors, "stop after this many errors (default 20)")
      ->check(CLI::PositiveNumber);
  app.set_version_flag("--version", "pbrtc 0.1.0 (archive format 1.0)");
  CLI11_PARSE(app, argc, argv);
  // Every parallel step (PLY reading and image decoding run in oneTBB's default arena) within
  // --nthreads; the archive's bytes do not depend on it.
  std::optional<tbb::global_control> limit;
  if (nthreads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, size_t(nthreads));

  if (print_schema) {
    pbrtc::print_schema_markdown(std::cout);
    return 0;
  }
  if (dump) {
    if (inputs.size() != 2) {
      std::cerr << "pbrtc: error: --dump takes an archive and an output directory\n";
      return 2;
    }
    pbrta::SceneArchive archive;
    std::string error;
    if (!archive.load(inputs[0], nthreads, &error)) {
      std::cerr << "pbrtc: error: " << error << "\n";
      return 1;
    }
    std::string base = inputs[0].substr(inputs[0].find_last_of('/') + 1);
    if (base.size() > 6 && base.compare(base.size() - 6, 6, ".pbrta") == 0)
      base.resize(base.size() - 6);
    if (!pbrtc::dump_archive(archive, inputs[1], base + ".pbrt", &error)) {
      std::cerr << "pbrtc: error: " << error << "\n";
      return 1;
    }
    if (!quiet) std::cerr << "pbrtc: wrote " << inputs[1] << "/" << base << ".pbrt\n";
    return 0;
  }
  if (info || verify) {
    if (inputs.empty()) {
      std::cerr << "pbrtc: error: --info and --verify need an archive\n";
      return 2;
    }
    bool ok = true;
    for (const std::string& path : inputs) {
      auto t0 = std::chrono::steady_clock::now();
      pbrta::SceneArchive archive;
      std::string error;
      if (!archive.load(path, nthreads, &error)) {
        std::cerr << "pbrtc: error: " << error << "\n";
        ok = false;
        continue;
      }
      if (info) pbrtc::print_archive_info(std::cout, path, archive);
      if (verify && !quiet)
        std::cout << path << ": ok (" << archive.reader().section_count()
                  << " sections verified in " << seconds_since(t0) << " s)\n";
    }
    return ok ? 0 : 1;
  }

  if (draco_bits > 0 && codec == "none") {
    std::cerr << "pbrtc: error: --draco-bits compresses meshes; it cannot go with --codec none\n";
    return 2;
  }
  if (draco_sequential && draco_bits == 0) {
    std::cerr << "pbrtc: error: --draco-sequential needs --draco-bits\n";
    return 2;
  }
  if (inputs.empty()) inputs.push_back("-");
  if (!outfile.empty() && inputs.size() > 1) {
    std::cerr << "pbrtc: error: -o names one archive but " << inputs.size()
              << " scenes were given\n";
    return 2;
  }
  bool all_ok = true;
  for (const std::string& path : inputs) {
    auto t0 = std::chrono::steady_clock::now();
    pbrtc::SourceFiles files;
    pbrtc::Diagnostics diag(&files, &std::cerr);
    diag.werror = werror;
    diag.max_errors = max_errors;
    pbrtc::SceneDesc scene;
    pbrtc::TerminalProgress progress(path);
    bool ok = pbrtc::build_scene(path, &files, &diag, &scene, quiet ? nullptr : &progress);
    progress.finish();
    if (diag.should_stop())
      std::cerr << path << ": too many errors (" << diag.error_count() << "), stopping\n";
    if (!ok) {
      all_ok = false;
      std::cerr << path << ": " << diag.error_count() << " error"
                << (diag.error_count() == 1 ? "" : "s") << ", " << diag.warning_count()
                << " warning" << (diag.warning_count() == 1 ? "" : "s")
                << (check ? "" : "; no archive written") << "\n";
      continue;
    }
    if (check) {
      if (!quiet) pbrtc::print_summary(std::cout, path, scene);
      continue;
    }
    double parse_s = seconds_since(t0);
    std::string out = outfile.empty() ? default_output(path) : outfile;
    pbrtc::ArchiveOptions opt;
    opt.compress = codec != "none";
    opt.zstd_level = zstd_level;
    opt.threads = nthreads;
    opt.draco_bits = draco_bits;
    opt.draco_sequential = draco_sequential;
    opt.texture_format = texture_precision == "f16"      ? pbrta::PixelFormat::kHalf16
                         : texture_precision == "unorm8" ? pbrta::PixelFormat::kUnorm8
                                                         : pbrta::PixelFormat::kFloat32;
    if (!quiet) opt.progress = &progress;
    pbrtc::ArchiveStats stats;
    std::string error;
    const bool written = pbrtc::write_archive(
        scene, files, path == "-" ? "" : pbrtc::directory_of(path), out, opt, &stats, &error);
    progress.finish();
    if (!written) {
      std::cerr << "pbrtc: error: " << error << "\n";
      all_ok = false;
      continue;
    }
    if (!quiet) {
      pbrtc::SceneCounts c = pbrtc::count_scene(scene);
      std::fprintf(stderr,
                   "pbrtc: %s: %zu shapes (%zu triangles), %zu lights, %zu materials -> %s "
                   "(%.2f MiB of %.2f MiB raw, %u sections); parse %.3f s, total %.3f s\n",
                   path.c_str(), c.shapes, c.triangles, c.lights + c.area_lights, c.materials,
                   out.c_str(), double(stats.file_size) / (1 << 20),
                   double(stats.raw_size) / (1 << 20), stats.sections, parse_s, seconds_since(t0));
      if (draco_bits > 0) print_draco_report(path, draco_bits, stats);
    }
  }
  return all_ok ? 0 : 1;
}
