// tests/test_support.h — helpers shared by the unit tests.
//
// shared_dir() finds the read-only corpus (../shared beside the repository, or
// $PBRTC_SHARED_DIR) and fails the test loudly when it is missing, so a test
// that needs real scenes can never pass by skipping them.
#pragma once

#include <string>
#include <vector>

namespace testing_support {

// The shared corpus directory; aborts the process with a message if absent.
std::string shared_dir();

// Debian's assimp-testmodels (/usr/share/assimp/models, or $PBRTC_ASSIMP_MODELS): real OBJ, MTL,
// PLY files nobody here wrote, installed by tools/install-deps.sh. Aborts with a message if absent.
std::string assimp_models_dir();

// Every entry scene of the shared corpus: the .pbrt files under
// shared_dir()/scenes that contain "WorldBegin" (the others are Included), sorted.
std::vector<std::string> shared_entry_scenes();

// A fresh empty directory under the build tree for one test's files.
std::string scratch_dir(const std::string& test_name);

// Writes text to path (creating parent directories); returns path.
std::string write_file(const std::string& path, const std::string& text);

// Reads a whole file; empty string if it cannot be read.
std::string read_file(const std::string& path);

// text cut at its newlines (a program's output, say), without them.
std::vector<std::string> lines_of(const std::string& text);

}  // namespace testing_support
