// tests/format/archive_load_test.cpp — ArchiveReader::load_sections: raw sections checksummed by
// chunk and used in place, zstd sections decoded frame by frame (shuffled ones through a scratch
// block) into one shared decode buffer, every section read through the mapping. Sections of every
// size around the frame sizes decode to their exact bytes on 1 and 2 threads, from a file and from
// memory; damage in the middle of a large section is still caught (checksum, or zstd itself when
// the checksum is forged); a file that shrinks between open and load gives an error, not SIGBUS,
// whether its sections are compressed or used in place. The loading threads' zstd contexts and
// scratch blocks are kept across loads: readers on several threads at once, loading archives
// whose frames need larger and smaller blocks in turn, still decode exactly. A small file is read
// whole at open instead of mapped. A decode buffer's pages past the bytes a load used go back.
#include <sys/mman.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <xxhash.h>

#include <cstddef>
#include <cstring>
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "archive_bytes.h"
#include "format/archive.h"
#include "format/archive_reader.h"
#include "format/archive_writer.h"
#include "test_support.h"

namespace pbrta {
namespace {

using test_bytes::entry_of;
using test_bytes::float_bytes;
using test_bytes::load_error;
using test_bytes::Raw;
using test_bytes::write_sections;

void expect_decodes(const ArchiveReader& r, const std::vector<Raw>& sections) {
  ASSERT_EQ(r.section_count(), sections.size());
  for (uint32_t i = 0; i < r.section_count(); ++i) {
    SCOPED_TRACE("section " + std::to_string(i) + " of " +
                 std::to_string(sections[i].bytes.size()) + " bytes");
    ASSERT_EQ(r.entry(i).codec, static_cast<uint32_t>(sections[i].codec));
    const uint8_t* data = r.section_data(i);
    ASSERT_NE(data, nullptr);
    EXPECT_EQ(reinterpret_cast<uintptr_t>(data) % 16, 0u);
    ASSERT_EQ(r.section_size(i), sections[i].bytes.size());
    if (!sections[i].bytes.empty()) {
      EXPECT_EQ(std::memcmp(data, sections[i].bytes.data(), sections[i].bytes.size()), 0);
    }
    for (uint64_t k = 0; k < kSectionPadding; ++k)
      ASSERT_EQ(data[r.section_size(i) + k], 0) << "padding byte " << k;
  }
}

// Every size around the frame sizes (empty, shorter than a word, ragged tails, exactly one 1 MiB
// frame, one byte more, several 4 MiB frames), shuffled and plain, and raw around the 1 MiB chunk,
// in one archive: each decodes to its bytes, in its own slot of the shared buffer, whatever the
// thread count and source.
TEST(ArchiveLoad, EverySizeAroundTheFramesDecodesExactly) {
  const std::string dir = testing_support::scratch_dir("ArchiveLoad.EverySize");
  const uint64_t m = uint64_t{1} << 20;
  std::vector<Raw> sections;
  uint32_t seed = 1;
  for (uint64_t size : {uint64_t{0}, uint64_t{1}, uint64_t{3}, uint64_t{4}, uint64_t{7}, m - 1, m,
                        m + 1, m + 4, 4 * m + 7, 9 * m})
    sections.push_back({Codec::kZstd, float_bytes(size, seed++), true});
  sections.push_back({Codec::kZstd, float_bytes(2 * m + 5, seed++)});
  for (uint64_t size : {uint64_t{0}, uint64_t{5}, m, m + 3, 3 * m})
    sections.push_back({Codec::kRaw, float_bytes(size, seed++)});
  const std::string path = dir + "/sizes.pbrta";
  const std::string bytes = write_sections(path, sections);
  for (int threads : {1, 2}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    std::string error;
    ArchiveReader from_file;
    ASSERT_TRUE(from_file.open(path, &error) && from_file.load_sections(threads, &error)) << error;
    expect_decodes(from_file, sections);
    ArchiveReader from_memory;
    ASSERT_TRUE(from_memory.open_memory(bytes, "sizes", &error) &&
                from_memory.load_sections(threads, &error))
        << error;
    expect_decodes(from_memory, sections);
  }
}

// Two archives, the first with frames larger than the second's, each loaded in turn by three
// readers on their own threads, each of which loads with two threads: every load must decode
// exactly, whatever buffers the threads kept from the loads before.
TEST(ArchiveLoad, ConcurrentReadersShareTheKeptDecodersSafely) {
  const std::string dir = testing_support::scratch_dir("ArchiveLoad.ConcurrentReaders");
  const std::vector<Raw> big = {{Codec::kZstd, float_bytes(9 * (1u << 20) + 12, 1), true},
                                {Codec::kZstd, float_bytes(300 * 1024, 2)}};
  const std::vector<Raw> small = {{Codec::kZstd, float_bytes(700 * 1024, 3), true},
                                  {Codec::kZstd, float_bytes(2 * (1u << 20), 4), true}};
  const std::string paths[2] = {dir + "/big.pbrta", dir + "/small.pbrta"};
  write_sections(paths[0], big);
  write_sections(paths[1], small);
  std::vector<std::thread> readers;
  for (int t = 0; t < 3; ++t)
    readers.emplace_back([&, t] {
      for (int round = 0; round < 4; ++round) {
        const int which = (round + t) % 2;
        ArchiveReader r;
        std::string error;
        ASSERT_TRUE(r.open(paths[which], &error) && r.load_sections(2, &error)) << error;
        expect_decodes(r, which == 0 ? big : small);
      }
    });
  for (std::thread& t : readers) t.join();
}

// A file of 64 KiB or less is read whole when opened, not mapped: what happens to the file
// afterwards does not reach the sections, which load from the copy (uncompressed ones in place).
TEST(ArchiveLoad, SmallFileIsReadWholeAtOpen) {
  const std::string dir = testing_support::scratch_dir("ArchiveLoad.SmallFile");
  const std::vector<Raw> sections = {{Codec::kRaw, float_bytes(3000, 1)},
                                     {Codec::kZstd, float_bytes(2000, 2)},
                                     {Codec::kZstd, float_bytes(1000, 3), true}};
  const std::string path = dir + "/small.pbrta";
  const std::string bytes = write_sections(path, sections);
  ASSERT_LE(bytes.size(), 64u << 10);
  ArchiveReader r;
  std::string error;
  ASSERT_TRUE(r.open(path, &error)) << error;
  ASSERT_EQ(::truncate(path.c_str(), 0), 0);
  ASSERT_TRUE(r.load_sections(2, &error)) << error;
  expect_decodes(r, sections);
  EXPECT_FALSE(r.open(path, &error));  // and the file itself is now too short to open
}

// Two sets of sections that make files between 64 KiB and 2 MiB: mostly uncompressed (800 KiB
// plain, 600 KiB zstd) and mostly compressed (400 KiB plain, the same 600 KiB zstd). The zstd
// section is random bytes, which do not compress: stored as large as they are raw.
std::pair<std::vector<Raw>, std::vector<Raw>> mid_sized_sections() {
  std::mt19937 rng(5);
  std::vector<uint8_t> noise(600u << 10);
  for (uint8_t& b : noise) b = static_cast<uint8_t>(rng());
  return {{{Codec::kRaw, float_bytes(800u << 10, 1)}, {Codec::kZstd, noise}},
          {{Codec::kRaw, float_bytes(400u << 10, 2)}, {Codec::kZstd, noise}}};
}

// A file over 64 KiB is mapped, whatever its codecs, and a mapped file can see itself shrink: cut
// inside either section between open and load, the load is refused before it reads the mapping,
// naming the first section cut (the uncompressed one used in place, or the compressed one
// decoded from the mapping). Uncut, the same file loads.
TEST(ArchiveLoad, MidSizedFileThatShrinksBeforeTheLoadIsRefused) {
  const std::string dir = testing_support::scratch_dir("ArchiveLoad.MidSized");
  const auto [mostly_none, mostly_zstd] = mid_sized_sections();
  for (const auto& [name, sections] :
       {std::pair{"mostly-none", mostly_none}, std::pair{"mostly-zstd", mostly_zstd}}) {
    for (uint32_t cut_in : {0u, 1u}) {
      SCOPED_TRACE(std::string(name) + ", cut in section " + std::to_string(cut_in));
      const std::string path = dir + "/" + name + ".pbrta";
      const std::string bytes = write_sections(path, sections);
      ASSERT_GT(bytes.size(), 64u << 10);
      ASSERT_LT(bytes.size(), 2u << 20);
      ArchiveReader r;
      std::string error;
      ASSERT_TRUE(r.open(path, &error)) << error;
      ASSERT_EQ(::truncate(path.c_str(), static_cast<off_t>(entry_of(bytes, cut_in).offset + 100)),
                0);
      EXPECT_FALSE(r.load_sections(2, &error));
      EXPECT_EQ(error, path + ": section 'geometry' (#" + std::to_string(cut_in) +
                           "): truncated while loading: the file shrank after it was opened");
      EXPECT_EQ(r.section_data(0), nullptr);  // all or nothing
      testing_support::write_file(path, bytes);
      ASSERT_TRUE(r.open(path, &error) && r.load_sections(2, &error)) << error;
      expect_decodes(r, sections);
    }
  }
}

// Damage to the header or table of a mapped file is refused with the message the same bytes get
// from memory (load_error compares the two), whichever codecs the table claims.
TEST(ArchiveLoad, MidSizedFileWithADamagedTableIsRefused) {
  const std::string dir = testing_support::scratch_dir("ArchiveLoad.MidSizedDamage");
  const std::string path = dir + "/t.pbrta";
  const auto [none_sections, zstd_sections] = mid_sized_sections();
  const std::string mostly_none = write_sections(dir + "/none.pbrta", none_sections);
  const std::string mostly_zstd = write_sections(dir + "/zstd.pbrta", zstd_sections);
  auto with_codec = [](std::string b, uint32_t i, Codec codec) {
    SectionEntry e = entry_of(b, i);
    e.codec = static_cast<uint32_t>(codec);
    std::memcpy(&b[sizeof(Header) + i * sizeof(SectionEntry)], &e, sizeof e);
    return b;
  };
  EXPECT_EQ(load_error(path, with_codec(mostly_none, 0, Codec::kZstd)),
            path + ": section table checksum mismatch");
  EXPECT_EQ(load_error(path, with_codec(mostly_zstd, 1, Codec::kRaw)),
            path + ": section table checksum mismatch");
  // A section count far beyond the file: refused by the header's checksum.
  std::string b = mostly_none;
  const uint32_t count = 0xFFFFFFFFu;
  std::memcpy(&b[offsetof(Header, section_count)], &count, sizeof count);
  EXPECT_EQ(load_error(path, b), path + ": header checksum mismatch");
  // Resealed, so the table agrees with its checksum: refused by the layout checks.
  b = with_codec(mostly_zstd, 1, Codec::kRaw);
  test_bytes::reseal(&b, 1, entry_of(b, 1).stored_size);
  const SectionEntry e = entry_of(b, 1);
  EXPECT_EQ(load_error(path, b), path + ": section 'geometry' (#1): raw size " +
                                     std::to_string(e.raw_size) + " differs from stored size " +
                                     std::to_string(e.stored_size) + " with codec 'raw'");
}

// The padding of a mapped file is checked through the mapping after an uncompressed section and
// with pread after a compressed one: a nonzero byte is refused either way, with the message the
// same bytes get from memory.
TEST(ArchiveLoad, MidSizedFileWithNonzeroPaddingIsRefused) {
  const std::string dir = testing_support::scratch_dir("ArchiveLoad.MidSizedPadding");
  const std::string path = dir + "/t.pbrta";
  const std::string good = write_sections(dir + "/none.pbrta", mid_sized_sections().first);
  ASSERT_GT(good.size(), 64u << 10);
  for (uint32_t i : {0u, 1u}) {
    const SectionEntry e = entry_of(good, i);
    for (uint64_t at : {e.offset + e.stored_size, e.offset + e.stored_size + kSectionPadding - 1}) {
      std::string b = good;
      b[at] = 7;
      EXPECT_EQ(load_error(path, b), path + ": section 'geometry' (#" + std::to_string(i) +
                                         "): nonzero byte at offset " + std::to_string(at) +
                                         " in the padding after the section");
    }
  }
}

class ArchiveLoadDamage : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing_support::scratch_dir(
        std::string("ArchiveLoad.") +
        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    sections_ = {{Codec::kZstd, float_bytes(1000, 7)},
                 {Codec::kZstd, float_bytes((6u << 20) + 10, 8), true}};
    good_ = write_sections(dir_ + "/good.pbrta", sections_);
  }
  std::string dir_;
  std::vector<Raw> sections_;
  std::string good_;
};

// The frame of a zstd section whose stored bytes hold byte `at` (ARCHIVE.md section 5: a 16-byte
// header, one 16-byte entry per frame, then the frames in order).
uint32_t frame_holding(const std::string& b, const SectionEntry& e, uint64_t at) {
  FrameIndexHeader h;
  std::memcpy(&h, b.data() + e.offset, sizeof h);
  const uint64_t n = (e.raw_size + h.frame_size - 1) / h.frame_size;
  uint64_t end = sizeof h + n * sizeof(FrameEntry);
  for (uint32_t k = 0; k < n; ++k) {
    FrameEntry f;
    std::memcpy(&f, b.data() + e.offset + sizeof h + k * sizeof f, sizeof f);
    end += f.stored_size;
    if (at < end) return k;
  }
  return uint32_t(n);
}

// One flipped bit halfway through a section of several frames: that frame's checksum.
TEST_F(ArchiveLoadDamage, FlippedByteInTheMiddleFailsItsFramesChecksum) {
  const SectionEntry e = entry_of(good_, 1);
  ASSERT_GT(e.stored_size, 1000u);
  std::string b = good_;
  b[e.offset + e.stored_size / 2] ^= 0x04;
  const uint32_t frame = frame_holding(good_, e, e.stored_size / 2);
  EXPECT_GT(frame, 0u);
  EXPECT_EQ(load_error(dir_ + "/t.pbrta", b), dir_ + "/t.pbrta: section 'geometry' (#1): frame " +
                                                  std::to_string(frame) + ": checksum mismatch");
}

// Damage whose checksum was forged, from the start of a frame in the middle of the section (its
// frame and block headers): zstd itself must refuse that frame.
TEST_F(ArchiveLoadDamage, ForgedDamageInTheMiddleIsRefusedByZstd) {
  const SectionEntry e = entry_of(good_, 1);
  const uint32_t frame = frame_holding(good_, e, e.stored_size / 2);
  uint64_t at = e.stored_size / 2;
  while (at > 0 && frame_holding(good_, e, at - 1) == frame) --at;  // that frame's first byte
  std::string b = good_;
  std::memset(&b[e.offset + at + 4], 0xFF, 512);
  std::vector<uint8_t> v(b.begin(), b.end());
  fuzz_support::reseal(&v);
  const std::string message = load_error(dir_ + "/t.pbrta", std::string(v.begin(), v.end()));
  const std::string prefix =
      dir_ + "/t.pbrta: section 'geometry' (#1): frame " + std::to_string(frame) + ": zstd";
  EXPECT_EQ(message.rfind(prefix, 0), 0u) << message;
}

// The file shrinks between open and load: its size is checked again before a compressed section
// is read from the mapping, so this is an error naming the section, not a SIGBUS.
TEST_F(ArchiveLoadDamage, FileThatShrinksAfterOpenIsAnError) {
  const std::string path = dir_ + "/shrinks.pbrta";
  testing_support::write_file(path, good_);
  ArchiveReader r;
  std::string error;
  ASSERT_TRUE(r.open(path, &error)) << error;
  const SectionEntry e = entry_of(good_, 1);
  ASSERT_EQ(::truncate(path.c_str(), static_cast<off_t>(e.offset + 100)), 0);
  EXPECT_FALSE(r.load_sections(2, &error));
  EXPECT_EQ(error, path +
                       ": section 'geometry' (#1): truncated while loading: the file shrank after "
                       "it was opened");
  EXPECT_EQ(r.section_data(0), nullptr);  // all or nothing
}

// An uncompressed section is used in place from the mapping: a file that shrank since open is
// refused when the load starts, before its checksum would read a lost page (SIGBUS).
TEST_F(ArchiveLoadDamage, UncompressedFileThatShrinksAfterOpenIsAnError) {
  const std::string path = dir_ + "/shrinks-none.pbrta";
  write_sections(path,
                 {{Codec::kRaw, float_bytes(1000, 1)}, {Codec::kRaw, float_bytes(2u << 20, 2)}});
  ArchiveReader r;
  std::string error;
  ASSERT_TRUE(r.open(path, &error)) << error;
  const SectionEntry e = entry_of(testing_support::read_file(path), 1);
  ASSERT_EQ(::truncate(path.c_str(), static_cast<off_t>(e.offset + 100)), 0);
  EXPECT_FALSE(r.load_sections(2, &error));
  EXPECT_EQ(error, path +
                       ": section 'geometry' (#1): truncated while loading: the file shrank after "
                       "it was opened");
  EXPECT_EQ(r.section_data(0), nullptr);
}

// A mapped decode buffer (a huge page asked for, the last one partly used) keeps its first bytes
// and gives back the pages past them: mincore refuses the range, as it does unmapped memory.
TEST(ArchiveLoad, ShrinkGivesBackThePagesPastTheBytesUsed) {
  const uint64_t used = (uint64_t{2} << 20) + 300 * 1024;
  archive_detail::Buffer b = archive_detail::allocate(used + 200 * 1024);
  ASSERT_TRUE(b);
  const uint64_t mapped = b.get_deleter().mapped_size;
  ASSERT_GE(mapped, uint64_t{4} << 20);  // the 500 KiB past 2 MiB asked for as a huge page
  std::memset(b.get(), 0x5a, mapped);
  archive_detail::shrink(&b, used);
  const uint64_t page = uint64_t(sysconf(_SC_PAGESIZE));
  const uint64_t keep = (used + page - 1) / page * page;
  EXPECT_EQ(b.get_deleter().mapped_size, keep);
  std::vector<unsigned char> resident((keep + page - 1) / page);
  EXPECT_EQ(mincore(b.get(), keep, resident.data()), 0);
  EXPECT_EQ(b.get()[used - 1], 0x5a);
  unsigned char past = 0;
  EXPECT_EQ(mincore(b.get() + keep, page, &past), -1);
  // A heap buffer is left as it is.
  archive_detail::Buffer h = archive_detail::allocate(used, true);
  ASSERT_TRUE(h);
  archive_detail::shrink(&h, 100);
  EXPECT_EQ(h.get_deleter().mapped_size, 0u);
}

}  // namespace
}  // namespace pbrta
