// tools/pbrt/scene_compile.h — compile one pbrt-v3 scene to an archive file, as pbrtc does.
//
// The scene is a file, or text already read from standard input (relative paths then
// resolve against the working directory, as pbrtc's "-" does). Diagnostics go to stderr
// in pbrtc's "path:line:col: error: message" form (with quiet, errors only). On success
// *inputs lists every file the compile read (scene files, Includes, meshes, images,
// spectra, lens files) as absolute paths, for the cache's manifest. Unless quiet, a long
// compile shows pbrtc's progress line on a terminal (compiler/compile_progress.h), erased
// before the render's own progress bar. The archive options
// are pbrtc's defaults (zstd level 6, no Draco, f32 texels); compile_options_key() names them for
// cache keys.
#pragma once

#include <string>
#include <vector>

namespace pbrt_tool {

struct SceneSource {
  std::string path;  // as given; "-" for standard input
  std::string text;  // standard input's text (path "-")
  bool is_stdin() const { return path == "-"; }
  std::string display() const { return is_stdin() ? "<stdin>" : path; }
};

bool compile_scene(const SceneSource& source, const std::string& archive_path, int threads,
                   bool quiet, std::vector<std::string>* inputs);

// The compiler's version and the compile options, as one string (part of every cache key).
std::string compile_options_key();

// path made absolute against the working directory (not resolving symbolic links).
std::string absolute_path(const std::string& path);

}  // namespace pbrt_tool
