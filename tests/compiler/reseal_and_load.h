// tests/compiler/reseal_and_load.h — load an archive whose records a test edited.
//
// Tests of SceneArchive's record validation edit bytes inside a good archive; without new
// checksums the loader would stop at a checksum and never reach the check under test.
// reseal_and_load() recomputes every checksum (the fuzzers' reseal, tests/fuzz/archive_reseal.h),
// writes the bytes to `path` and returns load()'s error message on `threads` threads; the load
// must fail. section_entry() finds the table entry of a section to edit.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "format/scene_archive.h"
#include "fuzz/archive_reseal.h"
#include "test_support.h"

namespace testing_support {

// The index of the first table entry of `kind`, or kNoIndex.
inline uint32_t section_entry(const pbrta::SceneArchive& archive, pbrta::SectionKind kind) {
  for (uint32_t i = 0; i < archive.reader().section_count(); ++i)
    if (archive.reader().entry(i).kind == uint32_t(kind)) return i;
  return pbrta::kNoIndex;
}

inline std::string reseal_and_load(const std::string& bytes, const std::string& path,
                                   int threads = 1) {
  std::vector<uint8_t> sealed(bytes.begin(), bytes.end());
  fuzz_support::reseal(&sealed);
  write_file(path, std::string(sealed.begin(), sealed.end()));
  pbrta::SceneArchive archive;
  std::string message;
  EXPECT_FALSE(archive.load(path, threads, &message));
  return message;
}

}  // namespace testing_support
