// libFuzzer target for the pbrtc front end: lexer, parser and scene builder.
// Input is scene text; Include and file names resolve against an empty
// directory so the fuzzer cannot wander the file system. Diagnostics are
// collected, not printed. Any crash, leak or sanitizer report is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "compiler/scene_builder.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  pbrtc::SourceFiles files;
  pbrtc::Diagnostics diag(&files, nullptr);
  pbrtc::SceneDesc scene;
  pbrtc::build_scene_from_string("fuzz.pbrt",
                                 std::string(reinterpret_cast<const char*>(data), size),
                                 "/nonexistent-fuzz-dir", &files, &diag, &scene);
  return 0;
}
