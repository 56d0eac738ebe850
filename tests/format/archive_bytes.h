// tests/format/archive_bytes.h — helpers the reader's load tests share: smooth float data (what
// meshes hold), writing sections to a file, reading and resealing a section entry in an archive's
// bytes, and the error a damaged archive gives when loaded from a file and from memory.
#pragma once

#include <gtest/gtest.h>
#include <xxhash.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "format/archive.h"
#include "format/archive_reader.h"
#include "format/archive_writer.h"
#include "fuzz/archive_reseal.h"
#include "test_support.h"

namespace pbrta::test_bytes {

// Smooth floats with noise: they compress well shuffled. Ragged tail bytes are random.
inline std::vector<uint8_t> float_bytes(size_t bytes, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.f, 0.01f);
  std::vector<uint8_t> v(bytes);
  for (size_t i = 0; i + 4 <= bytes; i += 4) {
    const float f = std::sin(0.001f * static_cast<float>(i)) + noise(rng);
    std::memcpy(&v[i], &f, 4);
  }
  for (size_t i = bytes / 4 * 4; i < bytes; ++i) v[i] = static_cast<uint8_t>(rng());
  return v;
}

// A section to write: the codec asked for, its raw bytes, and whether to shuffle them.
struct Raw {
  Codec codec;
  std::vector<uint8_t> bytes;
  bool shuffle = false;
};

// Writes the sections (all geometry) to path and returns the file's bytes.
inline std::string write_sections(const std::string& path, const std::vector<Raw>& sections) {
  ArchiveWriter w;
  for (const Raw& s : sections)
    w.add_section(SectionKind::kGeometry, s.bytes, 1, s.codec, s.shuffle);
  std::string error;
  EXPECT_TRUE(w.write(path, 0, 3, 2, &error)) << error;
  return testing_support::read_file(path);
}

inline SectionEntry entry_of(const std::string& b, uint32_t i) {
  SectionEntry e;
  std::memcpy(&e, b.data() + sizeof(Header) + i * sizeof(SectionEntry), sizeof e);
  return e;
}

// The table's and the header's checksums recomputed, after an edit of the table.
inline void reseal_table(std::string* b) {
  Header h;
  std::memcpy(&h, b->data(), sizeof h);
  h.table_checksum =
      XXH3_64bits(b->data() + sizeof(Header), uint64_t{h.section_count} * sizeof(SectionEntry));
  h.header_checksum = XXH3_64bits(&h, offsetof(Header, header_checksum));
  std::memcpy(&(*b)[0], &h, sizeof h);
}

// Section i's checksum set to XXH3 of its first `covered` stored bytes (by 1 MiB chunks for raw;
// for zstd, covered is its frame index), then the table's and the header's checksums.
inline void reseal(std::string* b, uint32_t i, uint64_t covered) {
  SectionEntry e = entry_of(*b, i);
  const auto* at = reinterpret_cast<const uint8_t*>(b->data()) + e.offset;
  e.checksum = e.codec == uint32_t(Codec::kRaw) ? fuzz_support::chunked_xxh3(at, covered)
                                                : XXH3_64bits(at, covered);
  std::memcpy(&(*b)[sizeof(Header) + i * sizeof(SectionEntry)], &e, sizeof e);
  reseal_table(b);
}

// The load's error from the file (2 threads) and from memory (1 thread), which must agree; ""
// if either loads.
inline std::string load_error(const std::string& path, const std::string& bytes) {
  testing_support::write_file(path, bytes);
  std::string file_error, memory_error;
  ArchiveReader from_file, from_memory;
  const bool file_ok = from_file.open(path, &file_error) && from_file.load_sections(2, &file_error);
  const bool memory_ok = from_memory.open_memory(bytes, path, &memory_error) &&
                         from_memory.load_sections(1, &memory_error);
  if (file_ok || memory_ok) return "";
  EXPECT_EQ(file_error, memory_error);
  return file_error;
}

}  // namespace pbrta::test_bytes
