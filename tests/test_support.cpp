#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace testing_support {

std::string shared_dir() {
  const char* env = std::getenv("PBRTC_SHARED_DIR");
  std::string dir = env && *env ? env : PBRTC_SHARED_DIR_DEFAULT;
  if (!fs::is_directory(fs::path(dir) / "scenes")) {
    std::fprintf(stderr,
                 "FATAL: shared corpus not found at '%s' (expected ../shared beside the "
                 "repository, or set PBRTC_SHARED_DIR)\n",
                 dir.c_str());
    std::abort();
  }
  return dir;
}

std::string assimp_models_dir() {
  const char* env = std::getenv("PBRTC_ASSIMP_MODELS");
  std::string dir = env && *env ? env : "/usr/share/assimp/models";
  if (!fs::is_directory(fs::path(dir) / "OBJ")) {
    std::fprintf(stderr,
                 "FATAL: assimp's test models not found at '%s' (install Debian's "
                 "assimp-testmodels: bash tools/install-deps.sh, or set PBRTC_ASSIMP_MODELS)\n",
                 dir.c_str());
    std::abort();
  }
  return dir;
}

std::vector<std::string> shared_entry_scenes() {
  std::vector<std::string> out;
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(shared_dir() + "/scenes")) {
    if (!e.is_regular_file() || e.path().extension() != ".pbrt") continue;
    if (read_file(e.path().string()).find("WorldBegin") != std::string::npos)
      out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string scratch_dir(const std::string& test_name) {
  fs::path p = fs::path(PBRTC_BINARY_DIR) / "test-scratch" / test_name;
  // CTest runs each test case as its own process, in parallel: fixtures that
  // share a name must not empty each other's folders.
  if (const ::testing::TestInfo* t = ::testing::UnitTest::GetInstance()->current_test_info())
    p /= std::string(t->test_suite_name()) + "." + t->name();
  std::error_code ec;
  fs::remove_all(p, ec);
  fs::create_directories(p);
  return p.string();
}

std::string write_file(const std::string& path, const std::string& text) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream out(path, std::ios::binary);
  out << text;
  return path;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

}  // namespace testing_support
