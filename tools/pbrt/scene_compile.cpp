#include "tools/pbrt/scene_compile.h"

#include <unistd.h>

#include <iostream>

#include "compiler/archive_builder.h"
#include "compiler/compile_progress.h"
#include "compiler/diagnostics.h"
#include "compiler/parser.h"
#include "compiler/scene_builder.h"
#include "format/archive.h"
#include "format/texel_format.h"

namespace pbrt_tool {

namespace {

pbrtc::ArchiveOptions archive_options(int threads) {
  pbrtc::ArchiveOptions opt;
  opt.threads = threads;
  return opt;
}

}  // namespace

std::string absolute_path(const std::string& path) {
  if (!path.empty() && path[0] == '/') return path;
  char buf[4096];
  std::string cwd = ::getcwd(buf, sizeof buf) ? buf : ".";
  std::string p = path;
  while (p.rfind("./", 0) == 0) p = p.substr(2);
  return cwd + "/" + p;
}

std::string compile_options_key() {
  pbrtc::ArchiveOptions o = archive_options(0);
  std::string key = "pbrtc 0.1.0; archive " + std::to_string(pbrta::kMajorVersion) + "." +
                    std::to_string(pbrta::kMinorVersion) + "; compress " +
                    std::to_string(o.compress) + " zstd " + std::to_string(o.zstd_level) +
                    " draco " + std::to_string(o.draco_bits) + " geometry_chunk " +
                    std::to_string(o.geometry_chunk_bytes) + " texel_chunk " +
                    std::to_string(o.texel_chunk_bytes) + " texels " +
                    pbrta::texel_format_name(uint32_t(o.texture_format));
  return key;
}

bool compile_scene(const SceneSource& source, const std::string& archive_path, int threads,
                   bool quiet, std::vector<std::string>* inputs) {
  pbrtc::SourceFiles files;
  pbrtc::Diagnostics diag(&files, quiet ? nullptr : &std::cerr);
  pbrtc::SceneDesc scene;
  pbrtc::TerminalProgress progress(source.display());
  bool ok =
      source.is_stdin()
          ? pbrtc::build_scene_from_string("<stdin>", source.text, "", &files, &diag, &scene)
          : pbrtc::build_scene(source.path, &files, &diag, &scene, quiet ? nullptr : &progress);
  progress.finish();
  if (quiet)  // pbrt-v3's --quiet keeps error messages
    for (const pbrtc::Diagnostic& d : diag.all())
      if (d.severity == pbrtc::Severity::kError) std::cerr << d.text << "\n";
  if (!ok) {
    std::cerr << source.display() << ": " << diag.error_count() << " error"
              << (diag.error_count() == 1 ? "" : "s") << "; not rendered\n";
    return false;
  }
  pbrtc::ArchiveStats stats;
  std::string error;
  std::string base = source.is_stdin() ? "" : pbrtc::directory_of(source.path);
  pbrtc::ArchiveOptions options = archive_options(threads);
  if (!quiet) options.progress = &progress;
  const bool written =
      pbrtc::write_archive(scene, files, base, archive_path, options, &stats, &error);
  progress.finish();
  if (!written) {
    std::cerr << "pbrt: error: " << error << "\n";
    return false;
  }
  inputs->clear();
  for (const std::string& f : scene.input_files) inputs->push_back(absolute_path(f));
  return true;
}

}  // namespace pbrt_tool
