// tests/runtime/runtime_test_support.h — compile scene text to an archive and load it.
//
// Renderer tests start from real pbrt-v3 text, compiled by pbrtc's own front
// end (never from hand-made records), so what they check is what a user gets.
#pragma once

#include <string>

#include "format/scene_archive.h"

namespace testing_support {

// Writes `scene_text` to <dir>/scene.pbrt, compiles it to <dir>/scene.pbrta
// and loads that into *archive. Fails the calling test (and returns false)
// with the compiler's or loader's messages when anything goes wrong.
bool compile_text(const std::string& dir, const std::string& scene_text,
                  pbrta::SceneArchive* archive);

// Compiles an existing scene file to out_path and loads it.
bool compile_file(const std::string& scene_path, const std::string& out_path,
                  pbrta::SceneArchive* archive);

}  // namespace testing_support
