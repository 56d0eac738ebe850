// tests/format/zstd_frames_test.cpp — codecs 4 and 6 (format/zstd_frames.h): a section stored as
// a frame index and one zstd frame per shuffled block of 4 MiB (codec 6: 1 MiB). The stored layout
// is what ARCHIVE.md says (a stranger's plain ZSTD_decompress of each frame gives the shuffled
// block); every size around the frame and shuffle blocks decodes exactly on 1 and 2 threads, from
// a file and from memory; the bytes do not depend on the thread count; damage to a frame or to the
// index is refused with the frame named; the uint32 bounds checked while blocks unshuffle find
// the same first offender as a plain scan, wherever it lies; and the writer takes 1 MiB frames
// only where asked to choose and where they cost little.
#include <gtest/gtest.h>
#include <xxhash.h>
#include <zstd.h>

#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <oneapi/tbb/task_arena.h>

#include "archive_bytes.h"
#include "format/archive.h"
#include "format/archive_reader.h"
#include "format/archive_writer.h"
#include "format/byte_shuffle.h"
#include "format/zstd_frames.h"
#include "test_support.h"

namespace pbrta {
namespace {

using test_bytes::entry_of;
using test_bytes::float_bytes;
using test_bytes::load_error;

// test_bytes::write_sections with every section asked for one codec.
std::string write_sections(const std::string& path, const std::vector<std::vector<uint8_t>>& raw,
                           Codec codec = Codec::kZstdShuffle4Frames) {
  std::vector<test_bytes::Raw> sections;
  for (const std::vector<uint8_t>& r : raw) sections.push_back(test_bytes::Raw{codec, r});
  return test_bytes::write_sections(path, sections);
}

FrameEntry frame_entry(const std::string& b, const SectionEntry& e, uint64_t k) {
  FrameEntry f;
  std::memcpy(&f, b.data() + e.offset + k * sizeof f, sizeof f);
  return f;
}

// After an edit of section i's frame index: its checksum, then the table's and header's.
void reseal_index(std::string* b, uint32_t i) {
  test_bytes::reseal(
      b, i, frame_count(test_bytes::entry_of(*b, i).raw_size, kFrameBlock) * sizeof(FrameEntry));
}

TEST(ZstdFrames, StoredLayoutIsAnIndexThenOnePlainZstdFramePerShuffledBlock) {
  for (Codec codec : {Codec::kZstdShuffle4Frames, Codec::kZstdShuffle4Frames1M}) {
    SCOPED_TRACE("codec " + std::to_string(uint32_t(codec)));
    const uint64_t block = frame_block(codec);
    ASSERT_EQ(block, codec == Codec::kZstdShuffle4Frames ? uint64_t{4} << 20 : uint64_t{1} << 20);
    const std::string dir = testing_support::scratch_dir("ZstdFrames.StoredLayout");
    const std::vector<uint8_t> raw = float_bytes(2 * block + 3 * kShuffleBlock + 6, 3);
    const std::string b = write_sections(dir + "/a.pbrta", {raw}, codec);
    const SectionEntry e = entry_of(b, 0);
    ASSERT_EQ(e.codec, uint32_t(codec));
    ASSERT_EQ(e.raw_size, raw.size());
    const uint64_t n = frame_count(raw.size(), block);
    ASSERT_EQ(n, 3u);
    EXPECT_EQ(e.checksum, XXH3_64bits(b.data() + e.offset, n * sizeof(FrameEntry)));
    uint64_t at = e.offset + n * sizeof(FrameEntry);
    for (uint64_t k = 0; k < n; ++k) {
      const FrameEntry f = frame_entry(b, e, k);
      EXPECT_EQ(f.reserved, 0u);
      EXPECT_EQ(f.checksum, XXH3_64bits(b.data() + at, f.stored_size));
      const uint64_t begin = k * block, size = std::min(block, raw.size() - begin);
      EXPECT_EQ(ZSTD_getFrameContentSize(b.data() + at, f.stored_size), size);
      std::vector<uint8_t> decoded(size), shuffled(size);
      ASSERT_EQ(ZSTD_decompress(decoded.data(), size, b.data() + at, f.stored_size), size);
      shuffle4(raw.data() + begin, shuffled.data(), size);  // shuffle blocks start at frame starts
      EXPECT_EQ(decoded, shuffled) << "frame " << k;
      at += f.stored_size;
    }
    EXPECT_EQ(at, e.offset + e.stored_size);  // the frames tile the rest exactly
  }
}

// ARCHIVE.md asks for a zstd frame that records its content size: a skippable frame, which zstd
// reports as holding 0 bytes, is not one, even where the section is empty.
TEST(ZstdFrames, ASkippableFrameIsNotAFrame) {
  const uint8_t skippable[8] = {0x50, 0x2A, 0x4D, 0x18, 0, 0, 0, 0};
  std::string why;
  EXPECT_FALSE(is_one_zstd_frame(skippable, sizeof skippable, 0, "empty", &why));
  EXPECT_EQ(why, "zstd: not a zstd frame");
  std::vector<uint8_t> empty(ZSTD_compressBound(0));
  const size_t n = ZSTD_compress(empty.data(), empty.size(), nullptr, 0, 3);
  ASSERT_FALSE(ZSTD_isError(n));
  EXPECT_TRUE(is_one_zstd_frame(empty.data(), n, 0, "empty", &why)) << why;
}

TEST(ZstdFrames, EverySizeAroundTheBlocksDecodesExactly) {
  for (Codec codec : {Codec::kZstdShuffle4Frames, Codec::kZstdShuffle4Frames1M}) {
    SCOPED_TRACE("codec " + std::to_string(uint32_t(codec)));
    const std::string dir = testing_support::scratch_dir("ZstdFrames.EverySize");
    const uint64_t s = kShuffleBlock, f = frame_block(codec);
    std::vector<std::vector<uint8_t>> raw;
    uint32_t seed = 10;
    for (uint64_t size : {uint64_t{0}, uint64_t{1}, uint64_t{3}, uint64_t{4}, s - 1, s + 1, f - 4,
                          f, f + 1, f + s + 3, 2 * f + 7})
      raw.push_back(float_bytes(size, seed++));
    const std::string path = dir + "/sizes.pbrta";
    const std::string bytes = write_sections(path, raw, codec);
    for (uint32_t i = 0; i < raw.size(); ++i) ASSERT_EQ(entry_of(bytes, i).codec, uint32_t(codec));
    for (int threads : {1, 2}) {
      for (bool from_file : {true, false}) {
        SCOPED_TRACE("threads " + std::to_string(threads) + (from_file ? " file" : " memory"));
        ArchiveReader r;
        std::string error;
        ASSERT_TRUE((from_file ? r.open(path, &error) : r.open_memory(bytes, "sizes", &error)) &&
                    r.load_sections(threads, &error))
            << error;
        for (uint32_t i = 0; i < raw.size(); ++i) {
          SCOPED_TRACE("section of " + std::to_string(raw[i].size()) + " bytes");
          ASSERT_EQ(r.section_size(i), raw[i].size());
          const uint8_t* d = r.section_data(i);
          ASSERT_NE(d, nullptr);
          EXPECT_EQ(reinterpret_cast<uintptr_t>(d) % 16, 0u);
          if (!raw[i].empty()) {
            EXPECT_EQ(std::memcmp(d, raw[i].data(), raw[i].size()), 0);
          }
          for (uint64_t k = 0; k < kSectionPadding; ++k) ASSERT_EQ(d[raw[i].size() + k], 0);
        }
      }
    }
  }
}

// pbrtc's choice (ArchiveWriter::choose_frame_size): 1 MiB frames for a section of more than 1 MiB
// and at most 16 MiB when they cost at most 5% more bytes. Bytes that repeat at a distance over
// 1 MiB (as killeroo-simple's mesh included twice does) compress far better in 4 MiB frames,
// which can see the repeat.
TEST(ZstdFrames, TheWriterTakes1MiBFramesWhereTheyCostLittle) {
  const std::string dir = testing_support::scratch_dir("ZstdFrames.WriterChoice");
  const uint64_t m = uint64_t{1} << 20;
  std::vector<uint8_t> repeated = float_bytes(m + 4096, 8);
  repeated.insert(repeated.end(), repeated.begin(), repeated.end());  // 2 MiB + 8 KiB, twice
  const std::vector<std::vector<uint8_t>> raw = {
      float_bytes(m, 1),          // one frame either way: codec 4
      float_bytes(m + 4, 2),      // two 1 MiB frames, alike in size: codec 6
      float_bytes(3 * m + 5, 3),  // codec 6
      repeated,                   // codec 4: the repeat is 1 MiB + 4 KiB away
      float_bytes(16 * m, 4),     // codec 6: still four 4 MiB frames, but alike in size
      float_bytes(16 * m + 4, 5)  // codec 4: over kSmallFramesMax
  };
  const Codec expected[] = {Codec::kZstdShuffle4Frames,   Codec::kZstdShuffle4Frames1M,
                            Codec::kZstdShuffle4Frames1M, Codec::kZstdShuffle4Frames,
                            Codec::kZstdShuffle4Frames1M, Codec::kZstdShuffle4Frames};
  for (bool choose : {false, true}) {
    SCOPED_TRACE(choose ? "choosing" : "as asked");
    ArchiveWriter w;
    w.choose_frame_size(choose);
    for (const std::vector<uint8_t>& r : raw)
      w.add_section(SectionKind::kGeometry, r, 1, Codec::kZstdShuffle4Frames);
    const std::string path = dir + "/c.pbrta";
    std::string error;
    ASSERT_TRUE(w.write(path, 0, 3, 2, &error)) << error;
    const std::string bytes = testing_support::read_file(path);
    for (uint32_t i = 0; i < raw.size(); ++i) {
      const SectionEntry e = entry_of(bytes, i);
      EXPECT_EQ(e.codec, uint32_t(choose ? expected[i] : Codec::kZstdShuffle4Frames)) << i;
      EXPECT_EQ(w.table()[i].codec, e.codec);
      // Codec 6 costs at most 5%: the same section asked for as codec 4 is the yardstick.
      if (e.codec == uint32_t(Codec::kZstdShuffle4Frames1M)) {
        std::vector<uint8_t> four;
        std::string why;
        ASSERT_TRUE(encode_zstd_frames(raw[i].data(), raw[i].size(), 3, kFrameBlock, &four, &why));
        EXPECT_LE(e.stored_size, four.size() + four.size() / 20) << i;
      }
    }
    ArchiveReader r;
    ASSERT_TRUE(r.open(path, &error) && r.load_sections(2, &error)) << error;
    for (uint32_t i = 0; i < raw.size(); ++i)
      EXPECT_EQ(std::memcmp(r.section_data(i), raw[i].data(), raw[i].size()), 0) << i;
    if (!choose) continue;
    // A flipped byte in a codec-6 frame names that frame, as in codec 4.
    std::string b = bytes;
    const SectionEntry e = entry_of(b, 2);
    FrameEntry f0, f1;
    std::memcpy(&f0, b.data() + e.offset, sizeof f0);
    std::memcpy(&f1, b.data() + e.offset + sizeof f0, sizeof f1);
    b[e.offset + 4 * sizeof(FrameEntry) + f0.stored_size + f1.stored_size / 2] ^= 0x04;
    EXPECT_EQ(load_error(dir + "/d.pbrta", b),
              dir + "/d.pbrta: section 'geometry' (#2): frame 1: checksum mismatch");
  }
}

TEST(ZstdFrames, BytesDoNotDependOnTheThreadCount) {
  const std::vector<uint8_t> raw = float_bytes(3 * kFrameBlock + 5, 4);
  std::vector<uint8_t> one, two;
  std::string why;
  tbb::task_arena(1).execute(
      [&] { ASSERT_TRUE(encode_zstd_frames(raw.data(), raw.size(), 3, kFrameBlock, &one, &why)); });
  tbb::task_arena(2).execute(
      [&] { ASSERT_TRUE(encode_zstd_frames(raw.data(), raw.size(), 3, kFrameBlock, &two, &why)); });
  EXPECT_EQ(one, two);
}

class ZstdFramesDamage : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing_support::scratch_dir(
        std::string("ZstdFrames.") +
        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    good_ = write_sections(dir_ + "/good.pbrta",
                           {float_bytes(1000, 5), float_bytes(2 * kFrameBlock + 100, 6)});
    e_ = entry_of(good_, 1);
    ASSERT_EQ(frame_count(e_.raw_size, kFrameBlock), 3u);
  }
  // File offset of frame k of section 1.
  uint64_t frame_at(uint64_t k) const {
    uint64_t at = e_.offset + 3 * sizeof(FrameEntry);
    for (uint64_t j = 0; j < k; ++j) at += frame_entry(good_, e_, j).stored_size;
    return at;
  }
  void put_frame_entry(std::string* b, uint64_t k, const FrameEntry& f) {
    std::memcpy(&(*b)[e_.offset + k * sizeof f], &f, sizeof f);
    reseal_index(b, 1);
  }
  std::string error_of(const std::string& b) { return load_error(dir_ + "/t.pbrta", b); }
  std::string prefix() const { return dir_ + "/t.pbrta: section 'geometry' (#1): "; }

  std::string dir_, good_;
  SectionEntry e_{};
};

TEST_F(ZstdFramesDamage, FlippedByteInAFrameNamesTheFrame) {
  std::string b = good_;
  b[frame_at(1) + frame_entry(good_, e_, 1).stored_size / 2] ^= 0x10;
  EXPECT_EQ(error_of(b), prefix() + "frame 1: checksum mismatch");
  // And in the index itself: the section's checksum.
  b = good_;
  b[e_.offset + 20] ^= 0x01;
  EXPECT_EQ(error_of(b), prefix() + "checksum mismatch");
}

TEST_F(ZstdFramesDamage, ForgedFrameDamageIsRefusedByZstd) {
  std::string b = good_;
  const FrameEntry f = frame_entry(good_, e_, 1);
  ASSERT_GT(f.stored_size, 1000u);
  std::memset(&b[frame_at(1) + f.stored_size / 2], 0xFF, 64);
  FrameEntry forged = f;
  forged.checksum = XXH3_64bits(b.data() + frame_at(1), f.stored_size);
  put_frame_entry(&b, 1, forged);
  const std::string m = error_of(b);
  EXPECT_EQ(m.rfind(prefix() + "frame 1: zstd", 0), 0u) << m;
}

TEST_F(ZstdFramesDamage, MalformedIndexIsRefused) {
  std::string b = good_;
  FrameEntry f = frame_entry(good_, e_, 0);
  f.reserved = 1;
  put_frame_entry(&b, 0, f);
  EXPECT_EQ(error_of(b), prefix() + "frame 0: reserved field is not zero");

  b = good_;
  f = frame_entry(good_, e_, 1);
  f.stored_size = 0;
  put_frame_entry(&b, 1, f);
  EXPECT_EQ(error_of(b).rfind(prefix() + "frame 1: 0 bytes at offset", 0), 0u);

  b = good_;
  f = frame_entry(good_, e_, 2);
  f.stored_size = static_cast<uint32_t>(e_.stored_size);  // runs past the section
  put_frame_entry(&b, 2, f);
  EXPECT_EQ(
      error_of(b).rfind(prefix() + "frame 2: " + std::to_string(e_.stored_size) + " bytes", 0), 0u);

  // A last frame one byte shorter leaves a byte over.
  b = good_;
  f = frame_entry(good_, e_, 2);
  f.stored_size -= 1;
  put_frame_entry(&b, 2, f);
  EXPECT_EQ(error_of(b), prefix() + "1 stored bytes follow the last frame");
}

// bounds[b]'s first offender by a plain scan, as a byte offset, or its end.
uint64_t plain_first(const std::vector<uint8_t>& raw, const ArchiveReader::U32Bound& u) {
  for (uint64_t at = u.begin; at < u.end; at += 4) {
    uint32_t v;
    std::memcpy(&v, raw.data() + at, 4);
    if (v >= u.limit) return at;
  }
  return u.end;
}

// Indices-like values (small, below 1000) in a section of three frames; bounds over several
// ranges, with offenders at the start, at shuffle-block and frame boundaries, deep inside and at
// the very end: every thread count reports what a plain scan finds.
TEST(ZstdFrames, BoundsFindTheFirstOffenderWhereverItIs) {
  const std::string dir = testing_support::scratch_dir("ZstdFrames.Bounds");
  const uint64_t words = (2 * kFrameBlock + 3 * kShuffleBlock + 40) / 4;
  std::vector<uint8_t> raw(words * 4);
  std::mt19937 rng(7);
  for (uint64_t w = 0; w < words; ++w) {
    const uint32_t v = rng() % 1000;
    std::memcpy(&raw[4 * w], &v, 4);
  }
  auto put = [&](uint64_t byte, uint32_t v) { std::memcpy(&raw[byte], &v, 4); };
  const uint64_t s = kShuffleBlock, f = kFrameBlock;
  put(0, 5000);              // first word
  put(s - 4, 1000);          // last word of a shuffle block, exactly the limit
  put(f, 0xFFFFFFFFu);       // first word of frame 1
  put(f + 2 * s + 8, 1001);  // inside
  put(words * 4 - 4, 2000);  // very last word
  const std::vector<ArchiveReader::U32Bound> bounds = {
      {0, 0, 64, 1000},                 // offender at 0
      {0, 16, s + 16, 1000},            // across a shuffle block: s - 4
      {0, s, f + 64, 1000},             // across a frame: f
      {0, f + 4, f + 3 * s, 1000},      // f + 2s + 8
      {0, f + 3 * s, words * 4, 1000},  // the last word
      {0, 64, s - 16, 1000},            // none
      {0, 0, words * 4, 0xFFFFFFFFu},   // only 0xFFFFFFFF is not below: f
      {0, 100, 100, 1},                 // empty
      {0, 8, 12, 0},                    // limit 0: everything offends
  };
  const std::string path = dir + "/b.pbrta";
  write_sections(path, {raw});
  for (int threads : {1, 2}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    ArchiveReader r;
    std::string error;
    ASSERT_TRUE(r.open(path, &error)) << error;
    std::vector<uint64_t> first;
    ASSERT_TRUE(r.load_sections(threads, {0}, bounds, &first, &error)) << error;
    ASSERT_EQ(first.size(), bounds.size());
    for (size_t b = 0; b < bounds.size(); ++b)
      EXPECT_EQ(first[b], plain_first(raw, bounds[b])) << "bound " << b;
    EXPECT_EQ(std::memcmp(r.section_data(0), raw.data(), raw.size()), 0);
  }
  // The same bounds on the same bytes stored uncompressed, as one zstd frame and in 1 MiB frames
  // (codecs 0, 1, 6).
  for (Codec codec : {Codec::kNone, Codec::kZstd, Codec::kZstdShuffle4Frames1M}) {
    ArchiveWriter w;
    w.add_section(SectionKind::kGeometry, raw, 1, codec);
    std::string error;
    ASSERT_TRUE(w.write(path, 0, 3, 2, &error)) << error;
    ArchiveReader r;
    std::vector<uint64_t> first;
    ASSERT_TRUE(r.open(path, &error) && r.load_sections(2, {0}, bounds, &first, &error)) << error;
    for (size_t b = 0; b < bounds.size(); ++b)
      EXPECT_EQ(first[b], plain_first(raw, bounds[b]))
          << "codec " << uint32_t(codec) << " bound " << b;
  }
}

// Bounds planned from a section loaded first (as SceneArchive plans triangle-index bounds from
// the mesh records): the plan runs once, after that section is loaded and before the gated one
// starts, while an ungated section loads beside them; the bounds it returns are checked like any
// others. A plan that breaks the contract fails the whole call and leaves nothing loaded.
TEST(ZstdFrames, PlannedBoundsComeFromTheSectionsLoadedFirst) {
  const std::string dir = testing_support::scratch_dir("ZstdFrames.PlannedBounds");
  const uint64_t words = (kFrameBlock + 3 * kShuffleBlock + 40) / 4;
  std::vector<uint8_t> raw(words * 4);
  std::mt19937 rng(11);
  for (uint64_t w = 0; w < words; ++w) {
    const uint32_t v = rng() % 1000;
    std::memcpy(&raw[4 * w], &v, 4);
  }
  const uint32_t offender = 70000;
  std::memcpy(&raw[kFrameBlock + 8], &offender, 4);
  // The records: (begin, end, limit) as three u32 each.
  const std::vector<uint32_t> records = {
      0, 4096, 1000, uint32_t(kFrameBlock), uint32_t(words * 4), 1000, 64, 128, 0};
  std::vector<uint8_t> record_bytes(records.size() * 4);
  std::memcpy(record_bytes.data(), records.data(), record_bytes.size());
  const std::vector<uint8_t> beside = float_bytes(kFrameBlock + 5 * kShuffleBlock, 5);
  // The records whole (codec 1) and by frame (codec 4, whose data is otherwise published only at
  // the end of the call).
  std::string error;
  for (Codec records_codec : {Codec::kZstd, Codec::kZstdShuffle4Frames}) {
    ArchiveWriter w;
    w.add_section(SectionKind::kMeshes, record_bytes, 3, records_codec);
    w.add_section(SectionKind::kGeometry, raw, 1, Codec::kZstdShuffle4Frames);
    w.add_section(SectionKind::kTransforms, beside, 1, Codec::kZstdShuffle4Frames);
    const std::string path = dir + "/p" + std::to_string(uint32_t(records_codec)) + ".pbrta";
    ASSERT_TRUE(w.write(path, 0, 3, 2, &error)) << error;
    for (int threads : {1, 2}) {
      SCOPED_TRACE("records codec " + std::to_string(uint32_t(records_codec)) + ", threads " +
                   std::to_string(threads));
      ArchiveReader r;
      ASSERT_TRUE(r.open(path, &error)) << error;
      int calls = 0;
      bool records_loaded = false;
      std::vector<ArchiveReader::U32Bound> bounds;
      ArchiveReader::BoundPlan plan{{0},
                                    {1},
                                    [&]() -> const std::vector<ArchiveReader::U32Bound>& {
                                      ++calls;
                                      records_loaded = r.section_data(0) != nullptr;
                                      const uint8_t* d = r.section_data(0);
                                      for (uint64_t k = 0; d != nullptr && k < 3; ++k) {
                                        uint32_t v[3];
                                        std::memcpy(v, d + 12 * k, 12);
                                        bounds.push_back({1, v[0], v[1], v[2]});
                                      }
                                      return bounds;
                                    },
                                    {},
                                    {}};
      std::vector<uint64_t> first;
      ASSERT_TRUE(r.load_sections(threads, {0, 1, 2}, plan, &first, &error)) << error;
      EXPECT_EQ(calls, 1);
      EXPECT_TRUE(records_loaded);
      ASSERT_EQ(first.size(), 3u);
      // A gated frame decoded before the plan would have missed its bounds.
      for (size_t b = 0; b < 3; ++b) EXPECT_EQ(first[b], plain_first(raw, bounds[b])) << b;
      EXPECT_EQ(first[0], 4096u);  // no offender: its end
      EXPECT_EQ(first[1], kFrameBlock + 8);
      EXPECT_EQ(first[2], 64u);  // limit 0: its first word
      EXPECT_EQ(std::memcmp(r.section_data(1), raw.data(), raw.size()), 0);
      EXPECT_EQ(std::memcmp(r.section_data(2), beside.data(), beside.size()), 0);
    }
  }
  const std::string path = dir + "/p1.pbrta";

  // Contract breaches, each an internal error with nothing loaded.
  const std::vector<ArchiveReader::U32Bound> in_ungated = {{2, 0, 64, 10}};
  const std::vector<ArchiveReader::U32Bound> none;
  struct Breach {
    const char* what;
    std::vector<uint32_t> first, gated;
    const std::vector<ArchiveReader::U32Bound>* bounds;
  };
  const Breach breaches[] = {
      {"a bound in a section that is not gated", {0}, {1}, &in_ungated},
      {"a section both first and gated", {1}, {1}, &none},
  };
  for (const Breach& b : breaches) {
    for (int threads : {1, 2}) {
      SCOPED_TRACE(std::string(b.what) + ", threads " + std::to_string(threads));
      ArchiveReader r;
      ASSERT_TRUE(r.open(path, &error)) << error;
      ArchiveReader::BoundPlan plan{
          b.first,
          b.gated,
          [&]() -> const std::vector<ArchiveReader::U32Bound>& { return *b.bounds; },
          {},
          {}};
      std::vector<uint64_t> first;
      EXPECT_FALSE(r.load_sections(threads, {0, 1, 2}, plan, &first, &error));
      EXPECT_NE(error.find("internal error"), std::string::npos) << error;
      for (uint32_t i = 0; i < 3; ++i) EXPECT_EQ(r.section_data(i), nullptr) << i;
    }
  }
}

// Work on some sections while the others load (as SceneArchive checks the records while the
// transforms decode): when_loaded() runs once, when every section it needs is in whole, whatever
// the thread count, told how much no thread has started on; first thing when it needs none; and
// not at all when one of them failed.
TEST(ZstdFrames, WhenLoadedRunsOnceItsSectionsAreIn) {
  const std::string dir = testing_support::scratch_dir("ZstdFrames.WhenLoaded");
  const std::vector<uint8_t> records = float_bytes(3000, 2);
  const std::vector<uint8_t> values = float_bytes(kFrameBlock + 7 * kShuffleBlock, 3);
  const std::vector<uint8_t> beside = float_bytes(2 * kFrameBlock + 5 * kShuffleBlock, 4);
  ArchiveWriter w;
  w.add_section(SectionKind::kEntities, records, 1, Codec::kZstd);
  w.add_section(SectionKind::kValues, values, 1, Codec::kZstdShuffle4Frames);
  w.add_section(SectionKind::kTransforms, beside, 1, Codec::kZstdShuffle4Frames);
  const std::string path = dir + "/w.pbrta";
  std::string error;
  ASSERT_TRUE(w.write(path, 0, 3, 2, &error)) << error;
  auto no_bounds = []() -> const std::vector<ArchiveReader::U32Bound>& {
    static const std::vector<ArchiveReader::U32Bound> none;
    return none;
  };
  // Loads `file` with when_loaded() needing `needs` (taken first or not): its calls, and whether
  // at the (last) call sections 0 and 1 were whole and section 2 not yet published.
  struct Seen {
    int calls = 0;
    bool whole[2] = {false, false};
    bool beside_published = false;
    uint64_t not_started = 0;
    bool loaded = false;
  };
  auto load = [&](const std::string& file, const std::vector<uint32_t>& needs, int threads,
                  bool needs_first = true) {
    Seen seen;
    ArchiveReader r;
    EXPECT_TRUE(r.open(file, &error)) << error;
    ArchiveReader::BoundPlan plan{
        {},
        {},
        no_bounds,
        needs,
        [&](uint64_t not_started) {
          ++seen.calls;
          seen.not_started = not_started;
          const uint8_t* d0 = r.section_data(0);
          const uint8_t* d1 = r.section_data(1);
          seen.whole[0] = d0 && std::memcmp(d0, records.data(), records.size()) == 0;
          seen.whole[1] = d1 && std::memcmp(d1, values.data(), values.size()) == 0;
          seen.beside_published = r.section_data(2) != nullptr;
        },
        needs_first};
    std::vector<uint64_t> first;
    seen.loaded = r.load_sections(threads, {0, 1, 2}, plan, &first, &error);
    return seen;
  };
  for (int threads : {1, 2}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    Seen s = load(path, {0, 1}, threads);
    EXPECT_TRUE(s.loaded) << error;
    EXPECT_EQ(s.calls, 1);
    EXPECT_TRUE(s.whole[0]);
    EXPECT_TRUE(s.whole[1]);
    // The needed sections go first: on one thread, none of the other one has started.
    if (threads == 1) {
      EXPECT_EQ(s.not_started, beside.size());
    }
    EXPECT_LE(s.not_started, beside.size());
    // Largest first instead, the records (3000 bytes) come last: nothing is left then.
    s = load(path, {0, 1}, threads, false);
    EXPECT_TRUE(s.loaded) << error;
    EXPECT_EQ(s.calls, 1);
    EXPECT_TRUE(s.whole[0] && s.whole[1]);
    if (threads == 1) {
      EXPECT_EQ(s.not_started, 0u);
    }
    s = load(path, {}, threads);
    EXPECT_TRUE(s.loaded) << error;
    EXPECT_EQ(s.calls, 1);
    EXPECT_FALSE(s.whole[0] || s.whole[1] || s.beside_published);  // before anything loaded
    EXPECT_EQ(s.not_started, records.size() + values.size() + beside.size());
  }
  // A damaged frame of a needed section: the load fails, and the work never runs.
  std::string bytes = testing_support::read_file(path);
  ArchiveReader r;
  ASSERT_TRUE(r.open(path, &error)) << error;
  const SectionEntry values_entry = r.entry(1);
  bytes[values_entry.offset + values_entry.stored_size - 10] ^= 0x5A;
  const std::string damaged = testing_support::write_file(dir + "/damaged.pbrta", bytes);
  for (int threads : {1, 2}) {
    SCOPED_TRACE("damaged, threads " + std::to_string(threads));
    const Seen s = load(damaged, {0, 1}, threads);
    EXPECT_FALSE(s.loaded);
    EXPECT_NE(error.find("section 'values' (#1)"), std::string::npos) << error;
    EXPECT_EQ(s.calls, 0);
  }
}

}  // namespace
}  // namespace pbrta
