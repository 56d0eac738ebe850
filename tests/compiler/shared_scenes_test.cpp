// tests/compiler/shared_scenes_test.cpp — every entry scene of the shared corpus compiles.
//
// An entry file is a .pbrt file under shared/scenes that contains "WorldBegin" (the others are
// Included). Each must compile without errors, except that a file the corpus README lists after
// "Missing:" (it could not be obtained) may be reported as missing: for such scenes every error
// must be exactly that "cannot open file" error. A per-scene table is printed.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "compiler/diagnostics.h"
#include "compiler/scene_builder.h"
#include "test_support.h"

namespace pbrtc {
namespace {

namespace fs = std::filesystem;

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The paths the README lists after "Missing:" (up to the end of the table cell or line).
std::vector<std::string> missing_files(const std::string& readme) {
  std::vector<std::string> out;
  const std::string key = "Missing:";
  for (size_t at = readme.find(key); at != std::string::npos; at = readme.find(key, at + 1)) {
    size_t end = readme.find_first_of("|\n", at);
    std::istringstream words(readme.substr(at + key.size(), end - at - key.size()));
    for (std::string w; words >> w;) {
      while (!w.empty() && (w.back() == ',' || w.back() == '.' || w.back() == ';')) w.pop_back();
      if (!w.empty()) out.push_back(w);
    }
  }
  return out;
}

// True if d is the error for a missing corpus file: 'cannot open file "<path>" ...' where the
// path ends in one of the missing files.
bool is_missing_file_error(const Diagnostic& d, const std::vector<std::string>& missing) {
  const std::string prefix = "cannot open file \"";
  if (d.message.compare(0, prefix.size(), prefix) != 0) return false;
  size_t close = d.message.find('"', prefix.size());
  if (close == std::string::npos) return false;
  std::string path = d.message.substr(prefix.size(), close - prefix.size());
  for (const std::string& m : missing)
    if (ends_with(path, "/" + m) || path == m) return true;
  return false;
}

TEST(SharedScenes, EveryEntrySceneCompiles) {
  const std::string scenes = testing_support::shared_dir() + "/scenes";
  const std::vector<std::string> missing =
      missing_files(testing_support::read_file(scenes + "/README.md"));
  ASSERT_FALSE(missing.empty()) << "the corpus README lists no Missing: files";
  EXPECT_NE(std::find(missing.begin(), missing.end(),
                      "pbrt-v3-scenes/dragon/geometry/dragon_remeshed.ply"),
            missing.end());

  const std::vector<std::string> entries = testing_support::shared_entry_scenes();
  EXPECT_GE(entries.size(), 50u);

  std::printf("%-80s %7s %10s %6s %8s  %s\n", "scene", "shapes", "triangles", "warn", "ms",
              "status");
  int clean = 0, missing_only = 0;
  for (const std::string& path : entries) {
    SourceFiles files;
    Diagnostics diag(&files);
    SceneDesc scene;
    auto t0 = std::chrono::steady_clock::now();
    bool ok = build_scene(path, &files, &diag, &scene);
    double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::string rel = path.substr(scenes.size() + 1);
    std::string status = "ok";
    if (!ok) {
      bool all_missing = true;
      for (const Diagnostic& d : diag.all()) {
        if (d.severity != Severity::kError) continue;
        if (!is_missing_file_error(d, missing)) {
          all_missing = false;
          ADD_FAILURE() << rel << ": unexpected error:\n" << d.text;
        }
      }
      status = all_missing ? "missing corpus file" : "FAILED";
      if (all_missing) ++missing_only;
    } else {
      ++clean;
    }
    SceneCounts counts = count_scene(scene);
    std::printf("%-80s %7zu %10zu %6d %8.1f  %s\n", rel.c_str(), counts.shapes, counts.triangles,
                diag.warning_count(), ms, status.c_str());
  }
  std::printf("%zu entry scenes: %d compiled cleanly, %d failed only on missing corpus files\n",
              entries.size(), clean, missing_only);
  std::fflush(stdout);
}

}  // namespace
}  // namespace pbrtc
