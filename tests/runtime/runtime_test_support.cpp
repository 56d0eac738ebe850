// tests/runtime/runtime_test_support.cpp — see runtime_test_support.h.
#include "runtime/runtime_test_support.h"

#include <gtest/gtest.h>

#include <sstream>

#include "compiler/archive_builder.h"
#include "compiler/diagnostics.h"
#include "compiler/parser.h"
#include "compiler/scene_builder.h"
#include "compiler/source_files.h"
#include "test_support.h"

namespace testing_support {

bool compile_file(const std::string& scene_path, const std::string& out_path,
                  pbrta::SceneArchive* archive) {
  std::ostringstream messages;
  pbrtc::SourceFiles files;
  pbrtc::Diagnostics diag(&files, &messages);
  pbrtc::SceneDesc scene;
  if (!pbrtc::build_scene(scene_path, &files, &diag, &scene, nullptr)) {
    ADD_FAILURE() << "compile failed:\n" << messages.str();
    return false;
  }
  pbrtc::ArchiveOptions opt;
  opt.threads = 1;
  pbrtc::ArchiveStats stats;
  std::string error;
  if (!pbrtc::write_archive(scene, files, pbrtc::directory_of(scene_path), out_path, opt, &stats,
                            &error)) {
    ADD_FAILURE() << "archive not written: " << error;
    return false;
  }
  if (!archive->load(out_path, 1, &error)) {
    ADD_FAILURE() << "archive not loaded: " << error;
    return false;
  }
  return true;
}

bool compile_text(const std::string& dir, const std::string& scene_text,
                  pbrta::SceneArchive* archive) {
  std::string path = write_file(dir + "/scene.pbrt", scene_text);
  return compile_file(path, dir + "/scene.pbrta", archive);
}

}  // namespace testing_support
