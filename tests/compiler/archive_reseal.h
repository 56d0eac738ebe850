// tests/compiler/archive_reseal.h — load an archive whose records a test edited.
//
// Tests of SceneArchive's record validation edit bytes inside one section of a
// good archive; without new checksums the loader would stop at the checksum
// and never reach the check under test. reseal_and_load() recomputes the
// section's checksum, the table's and the header's, writes the bytes to
// `path` and returns load()'s error message (empty when the archive loaded) on
// `threads` threads.
// section_entry() finds the table entry of a section to edit.
#pragma once

#include <gtest/gtest.h>
#include <xxhash.h>

#include <cstddef>
#include <cstring>
#include <string>

#include "format/scene_archive.h"
#include "test_support.h"

namespace testing_support {

// The index of the first table entry of `kind`, or kNoIndex.
inline uint32_t section_entry(const pbrta::SceneArchive& archive, pbrta::SectionKind kind) {
  for (uint32_t i = 0; i < archive.reader().section_count(); ++i)
    if (archive.reader().entry(i).kind == uint32_t(kind)) return i;
  return pbrta::kNoIndex;
}

inline std::string reseal_and_load(std::string bytes, uint32_t section_entry,
                                   const std::string& path, int threads = 1) {
  const size_t entry_at = sizeof(pbrta::Header) + section_entry * sizeof(pbrta::SectionEntry);
  pbrta::SectionEntry e;
  std::memcpy(&e, &bytes[entry_at], sizeof e);
  e.checksum = XXH3_64bits(bytes.data() + e.offset, e.stored_size);
  std::memcpy(&bytes[entry_at], &e, sizeof e);
  pbrta::Header h;
  std::memcpy(&h, bytes.data(), sizeof h);
  h.table_checksum = XXH3_64bits(bytes.data() + sizeof h, h.section_count * sizeof e);
  h.header_checksum = XXH3_64bits(&h, offsetof(pbrta::Header, header_checksum));
  std::memcpy(&bytes[0], &h, sizeof h);
  write_file(path, bytes);
  pbrta::SceneArchive archive;
  std::string message;
  EXPECT_FALSE(archive.load(path, threads, &message));
  return message;
}

}  // namespace testing_support
