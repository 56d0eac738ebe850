// tests/compiler/compiled_scene.h — a scene file through the front end, for archive tests.
//
// compile_scene() parses and resolves `path` as pbrtc does (build_scene),
// keeping the source files (the archive writer needs them), the path (its
// directory resolves relative file names) and the error messages.
#pragma once

#include <string>
#include <vector>

#include "compiler/diagnostics.h"
#include "compiler/scene_builder.h"
#include "compiler/source_files.h"

namespace pbrtc {

struct CompiledScene {
  SourceFiles files;
  SceneDesc scene;
  std::string path;
  std::vector<std::string> errors;
  bool ok = false;
};

inline void compile_scene(const std::string& path, CompiledScene* c) {
  Diagnostics diag(&c->files, nullptr);
  c->path = path;
  c->ok = build_scene(path, &c->files, &diag, &c->scene);
  for (const auto& d : diag.all()) c->errors.push_back(d.message);
}

}  // namespace pbrtc
