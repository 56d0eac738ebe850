// tests/format/raw_codec_test.cpp — the raw codec: sections stored as they are, checksummed by
// 1 MiB chunks (ARCHIVE.md, section 5), with the checksum the spec defines (computed here from
// XXH3 directly, not with the reader's code); they load in place on 1 and 2 threads, from a
// mapped file and from memory. Damage in any chunk, chunks swapped, a whole-section XXH3 where
// the chunked one belongs, and a raw size that differs from the stored size are all refused
// with the section named; an empty or one-chunk section is valid.
#include <gtest/gtest.h>
#include <xxhash.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "archive_bytes.h"
#include "format/archive.h"
#include "format/archive_reader.h"
#include "format/archive_writer.h"
#include "fuzz/archive_reseal.h"
#include "test_support.h"

namespace pbrta {
namespace {

using test_bytes::entry_of;
using test_bytes::float_bytes;
using test_bytes::load_error;
using test_bytes::Raw;
using test_bytes::write_sections;

constexpr uint64_t kMiB = uint64_t{1} << 20;

const uint8_t* stored_of(const std::string& b, const SectionEntry& e) {
  return reinterpret_cast<const uint8_t*>(b.data()) + e.offset;
}

// Sets section i's table checksum to `checksum` and reseals the table and header only.
std::string with_checksum(std::string b, uint32_t i, uint64_t checksum) {
  SectionEntry e = entry_of(b, i);
  e.checksum = checksum;
  std::memcpy(&b[sizeof(Header) + i * sizeof(SectionEntry)], &e, sizeof e);
  test_bytes::reseal_table(&b);
  return b;
}

void expect_loads_in_place(const std::string& path, const std::string& bytes,
                           const std::vector<Raw>& sections) {
  for (int threads : {1, 2}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    std::string error;
    ArchiveReader from_file, from_memory;
    ASSERT_TRUE(from_file.open(path, &error) && from_file.load_sections(threads, &error)) << error;
    ASSERT_TRUE(from_memory.open_memory(bytes, "memory", &error) &&
                from_memory.load_sections(threads, &error))
        << error;
    for (const ArchiveReader* r : {&from_file, &from_memory}) {
      for (uint32_t i = 0; i < sections.size(); ++i) {
        SCOPED_TRACE("section " + std::to_string(i));
        const std::vector<uint8_t>& raw = sections[i].bytes;
        ASSERT_EQ(r->section_size(i), raw.size());
        const uint8_t* data = r->section_data(i);
        ASSERT_NE(data, nullptr);
        if (!raw.empty()) {
          EXPECT_EQ(std::memcmp(data, raw.data(), raw.size()), 0);
        }
        if (r->entry(i).codec != uint32_t(Codec::kRaw)) continue;
        EXPECT_TRUE(r->in_place(i));
        if (r == &from_memory) {
          EXPECT_EQ(data, stored_of(bytes, r->entry(i)));  // not a copy
        }
      }
    }
  }
}

// Whatever its size, a raw section's checksum is the spec's: XXH3 of its chunks' XXH3 values in
// order (never the whole section's XXH3). Each loads in place.
TEST(RawCodec, SectionsAreChecksummedByChunk) {
  const std::string dir = testing_support::scratch_dir("RawCodec.ByChunk");
  const std::vector<Raw> sections = {{Codec::kRaw, float_bytes(0, 1)},
                                     {Codec::kRaw, float_bytes(kMiB, 2)},
                                     {Codec::kRaw, float_bytes(kMiB + 1, 3)},
                                     {Codec::kZstd, float_bytes(5000, 4)},
                                     {Codec::kRaw, float_bytes(3 * kMiB + 5, 5)}};
  const std::string path = dir + "/a.pbrta";
  const std::string bytes = write_sections(path, sections);
  for (uint32_t i = 0; i < sections.size(); ++i) {
    SCOPED_TRACE("section " + std::to_string(i));
    const SectionEntry e = entry_of(bytes, i);
    ASSERT_EQ(e.codec, uint32_t(sections[i].codec));
    if (sections[i].codec == Codec::kZstd) continue;
    EXPECT_EQ(e.stored_size, e.raw_size);
    const uint8_t* stored = stored_of(bytes, e);
    EXPECT_EQ(e.checksum, fuzz_support::chunked_xxh3(stored, e.stored_size));
    if (e.stored_size > 0) {  // no chunks: XXH3 of nothing, either way
      EXPECT_NE(e.checksum, XXH3_64bits(stored, e.stored_size));
    }
  }
  expect_loads_in_place(path, bytes, sections);
}

// A flipped byte at the start of the first chunk, inside a middle one, or at the end of the
// short last one; two whole chunks swapped; the whole-section XXH3 codec 0 would store: each is
// a checksum mismatch in that section, on 2 threads from the file and on 1 from memory.
TEST(RawCodec, DamageInAnyChunkIsRefused) {
  const std::string dir = testing_support::scratch_dir("RawCodec.Damage");
  const std::string path = dir + "/bad.pbrta";
  const std::string good = write_sections(
      dir + "/good.pbrta",
      {{Codec::kZstd, float_bytes(3000, 1)}, {Codec::kRaw, float_bytes(3 * kMiB + 5, 2)}});
  const SectionEntry e = entry_of(good, 1);
  ASSERT_EQ(e.codec, uint32_t(Codec::kRaw));
  ASSERT_EQ(load_error(path, good), "");
  const std::string mismatch = path + ": section 'geometry' (#1): checksum mismatch";
  for (uint64_t at : {uint64_t{0}, kMiB + kMiB / 2, e.stored_size - 1}) {
    SCOPED_TRACE("byte " + std::to_string(at));
    std::string b = good;
    b[e.offset + at] ^= 0x10;
    EXPECT_EQ(load_error(path, b), mismatch);
  }
  std::string swapped = good;
  std::memcpy(&swapped[e.offset], good.data() + e.offset + kMiB, kMiB);
  std::memcpy(&swapped[e.offset + kMiB], good.data() + e.offset, kMiB);
  EXPECT_EQ(load_error(path, swapped), mismatch);
  EXPECT_EQ(
      load_error(path, with_checksum(good, 1, XXH3_64bits(stored_of(good, e), e.stored_size))),
      mismatch);
}

// A raw section stores the raw bytes: a table that says otherwise is refused before anything is
// read.
TEST(RawCodec, RawSizeMustEqualStoredSize) {
  const std::string dir = testing_support::scratch_dir("RawCodec.Sizes");
  const std::string path = dir + "/bad.pbrta";
  std::string b = write_sections(dir + "/good.pbrta", {{Codec::kRaw, float_bytes(2 * kMiB, 1)}});
  SectionEntry e = entry_of(b, 0);
  ASSERT_EQ(e.codec, uint32_t(Codec::kRaw));
  e.raw_size -= 16;
  std::memcpy(&b[sizeof(Header)], &e, sizeof e);
  test_bytes::reseal_table(&b);
  EXPECT_EQ(load_error(path, b), path + ": section 'geometry' (#0): raw size " +
                                     std::to_string(e.raw_size) + " differs from stored size " +
                                     std::to_string(e.stored_size) + " with codec 'raw'");
}

// An empty section (whose checksum is XXH3 of no bytes: there are no chunk checksums) and
// sections of less than a chunk and of exactly one are valid and load in place; a wrong checksum
// on the empty one is still a mismatch.
TEST(RawCodec, EmptyAndOneChunkSectionsAreValid) {
  const std::string dir = testing_support::scratch_dir("RawCodec.Small");
  const std::vector<Raw> sections = {{Codec::kRaw, float_bytes(0, 1)},
                                     {Codec::kRaw, float_bytes(100, 2)},
                                     {Codec::kRaw, float_bytes(kMiB, 3)}};
  const std::string path = dir + "/a.pbrta";
  const std::string bytes = write_sections(path, sections);
  for (uint32_t i = 0; i < sections.size(); ++i)
    ASSERT_EQ(entry_of(bytes, i).codec, uint32_t(Codec::kRaw));
  EXPECT_EQ(entry_of(bytes, 0).checksum, XXH3_64bits(nullptr, 0));
  const SectionEntry one = entry_of(bytes, 1);
  const uint64_t one_sum = XXH3_64bits(stored_of(bytes, one), one.stored_size);
  EXPECT_EQ(one.checksum, XXH3_64bits(&one_sum, sizeof one_sum));
  expect_loads_in_place(path, bytes, sections);
  EXPECT_EQ(load_error(dir + "/bad.pbrta", with_checksum(bytes, 0, XXH3_64bits(nullptr, 0) + 1)),
            dir + "/bad.pbrta: section 'geometry' (#0): checksum mismatch");
}

}  // namespace
}  // namespace pbrta
