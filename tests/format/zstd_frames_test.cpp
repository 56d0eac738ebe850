// tests/format/zstd_frames_test.cpp — the zstd codec (format/zstd_frames.h): a section stored as
// an index (a header naming the frame size and the shuffle flag, one entry per frame) and one
// zstd frame per block. The stored layout is what ARCHIVE.md says (a stranger's plain
// ZSTD_decompress of each frame gives the block, shuffled when the flag says so); the bytes do not
// depend on the thread count; the writer takes 1 MiB frames only where they cost little; damage to
// a frame or to the index is refused with the frame named.
#include <gtest/gtest.h>
#include <xxhash.h>
#include <zstd.h>

#include <cstring>
#include <string>
#include <vector>

#include <oneapi/tbb/task_arena.h>

#include "archive_bytes.h"
#include "format/archive.h"
#include "format/archive_reader.h"
#include "format/archive_writer.h"
#include "format/zstd_frames.h"
#include "test_support.h"

namespace pbrta {
namespace {

using test_bytes::entry_of;
using test_bytes::float_bytes;
using test_bytes::load_error;

constexpr uint64_t kMiB = uint64_t{1} << 20;

// test_bytes::write_sections with every section zstd, shuffled.
std::string write_sections(const std::string& path, const std::vector<std::vector<uint8_t>>& raw) {
  std::vector<test_bytes::Raw> sections;
  for (const std::vector<uint8_t>& r : raw) sections.push_back({Codec::kZstd, r, true});
  return test_bytes::write_sections(path, sections);
}

FrameIndexHeader index_header(const uint8_t* stored) {
  FrameIndexHeader h;
  std::memcpy(&h, stored, sizeof h);
  return h;
}

FrameEntry frame_entry(const uint8_t* stored, uint64_t k) {
  FrameEntry f;
  std::memcpy(&f, stored + sizeof(FrameIndexHeader) + k * sizeof f, sizeof f);
  return f;
}

// The stored bytes as ARCHIVE.md section 5 lays them out, for 1 and 4 MiB frames, shuffled or
// not: the header, an entry per block with the frame's XXH3, and the frames tiling the rest, each
// one plain zstd frame of its block (shuffled on its own).
TEST(ZstdFrames, StoredLayoutIsAHeaderAnIndexAndOneZstdFramePerBlock) {
  for (const uint64_t frame : {kMiB, 4 * kMiB}) {
    for (const bool shuffle : {false, true}) {
      SCOPED_TRACE(std::to_string(frame) + (shuffle ? " shuffled" : " plain"));
      const std::vector<uint8_t> raw = float_bytes(2 * frame + 3 * 1024 + 6, 3);
      std::vector<uint8_t> stored;
      std::string why;
      ASSERT_TRUE(encode_zstd_frames(raw.data(), raw.size(), 3, frame, shuffle, &stored, &why));
      const FrameIndexHeader h = index_header(stored.data());
      EXPECT_EQ(h.frame_size, frame);
      EXPECT_EQ(h.flags, shuffle ? uint32_t(kFrameShuffle4) : 0u);
      EXPECT_EQ(h.reserved, 0u);
      const uint64_t n = frame_count(raw.size(), frame);
      ASSERT_EQ(n, 3u);
      uint64_t at = sizeof h + n * sizeof(FrameEntry);
      for (uint64_t k = 0; k < n; ++k) {
        const FrameEntry f = frame_entry(stored.data(), k);
        EXPECT_EQ(f.reserved, 0u);
        EXPECT_EQ(f.checksum, XXH3_64bits(stored.data() + at, f.stored_size));
        const uint64_t begin = k * frame, size = std::min(frame, raw.size() - begin);
        EXPECT_EQ(ZSTD_getFrameContentSize(stored.data() + at, f.stored_size), size);
        std::vector<uint8_t> decoded(size),
            expected(raw.begin() + begin, raw.begin() + begin + size);
        ASSERT_EQ(ZSTD_decompress(decoded.data(), size, stored.data() + at, f.stored_size), size);
        if (shuffle) shuffle4(raw.data() + begin, expected.data(), size);
        EXPECT_EQ(decoded, expected) << "frame " << k;
        at += f.stored_size;
      }
      EXPECT_EQ(at, stored.size());  // the frames tile the rest exactly
    }
  }
}

// The shuffle as ARCHIVE.md defines it: byte k of word w at k * (size / 4) + w, the size % 4 tail
// bytes as they are; and unshuffle4 is its inverse, for every tail.
TEST(ZstdFrames, ShuffleIsTheSpecsAndUnshuffleItsInverse) {
  for (const uint64_t size : {0u, 1u, 3u, 4u, 5u, 64u, 67u, 1000u, 4099u}) {
    std::vector<uint8_t> raw = float_bytes(size, 7), shuffled(size), back(size);
    shuffle4(raw.data(), shuffled.data(), size);
    const uint64_t words = size / 4;
    for (uint64_t w = 0; w < words; ++w)
      for (uint64_t k = 0; k < 4; ++k) ASSERT_EQ(shuffled[k * words + w], raw[4 * w + k]) << size;
    for (uint64_t t = 4 * words; t < size; ++t) ASSERT_EQ(shuffled[t], raw[t]) << size;
    unshuffle4(shuffled.data(), back.data(), size);
    EXPECT_EQ(back, raw) << size;
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

// The writer's choice: 1 MiB frames for a section of more than 1 MiB and at most 16 MiB when they
// cost at most 5% more bytes than 4 MiB frames. Bytes that repeat at a distance over 1 MiB (as
// killeroo-simple's mesh included twice does) compress far better in 4 MiB frames, which can see
// the repeat. Every section loads back exactly.
TEST(ZstdFrames, TheWriterTakes1MiBFramesWhereTheyCostLittle) {
  const std::string dir = testing_support::scratch_dir("ZstdFrames.WriterChoice");
  const uint64_t m = kMiB;
  std::vector<uint8_t> repeated = float_bytes(m + 4096, 8);
  repeated.insert(repeated.end(), repeated.begin(), repeated.end());  // 2 MiB + 8 KiB, twice
  const std::vector<std::vector<uint8_t>> raw = {
      float_bytes(m, 1),          // one frame either way: 4 MiB
      float_bytes(m + 4, 2),      // two 1 MiB frames, alike in size: 1 MiB
      float_bytes(3 * m + 5, 3),  // 1 MiB
      repeated,                   // 4 MiB: the repeat is 1 MiB + 4 KiB away
      float_bytes(16 * m, 4),     // 1 MiB: still four 4 MiB frames, but alike in size
      float_bytes(16 * m + 4, 5)  // 4 MiB: over kSmallFramesMax
  };
  const uint64_t expected[] = {4 * m, m, m, 4 * m, m, 4 * m};
  const std::string path = dir + "/c.pbrta";
  const std::string bytes = write_sections(path, raw);
  for (uint32_t i = 0; i < raw.size(); ++i) {
    const SectionEntry e = entry_of(bytes, i);
    const uint8_t* stored = reinterpret_cast<const uint8_t*>(bytes.data()) + e.offset;
    EXPECT_EQ(index_header(stored).frame_size, expected[i]) << i;
    // 1 MiB frames cost at most 5%: the same section in 4 MiB frames is the yardstick.
    if (expected[i] == m) {
      std::vector<uint8_t> four;
      std::string why;
      ASSERT_TRUE(encode_zstd_frames(raw[i].data(), raw[i].size(), 3, 4 * m, true, &four, &why));
      EXPECT_LE(e.stored_size, four.size() + four.size() / 20) << i;
    }
  }
  ArchiveReader r;
  std::string error;
  ASSERT_TRUE(r.open(path, &error) && r.load_sections(2, &error)) << error;
  for (uint32_t i = 0; i < raw.size(); ++i)
    EXPECT_EQ(std::memcmp(r.section_data(i), raw[i].data(), raw[i].size()), 0) << i;
}

TEST(ZstdFrames, BytesDoNotDependOnTheThreadCount) {
  const std::vector<uint8_t> raw = float_bytes(3 * 4 * kMiB + 5, 4);
  std::vector<uint8_t> one, two;
  std::string why;
  tbb::task_arena(1).execute([&] {
    ASSERT_TRUE(encode_zstd_frames(raw.data(), raw.size(), 3, 4 * kMiB, true, &one, &why));
  });
  tbb::task_arena(2).execute([&] {
    ASSERT_TRUE(encode_zstd_frames(raw.data(), raw.size(), 3, 4 * kMiB, true, &two, &why));
  });
  EXPECT_EQ(one, two);
}

// A section of five frames (section 1; section 0 is small), damaged in its frames and index.
class ZstdFramesDamage : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing_support::scratch_dir(
        std::string("ZstdFrames.") +
        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    // Over 16 MiB, so in 4 MiB frames: five of them.
    good_ = write_sections(dir_ + "/good.pbrta",
                           {float_bytes(1000, 5), float_bytes(16 * kMiB + 100, 6)});
    e_ = entry_of(good_, 1);
    ASSERT_EQ(index_header(stored(good_)).frame_size, 4 * kMiB);
    ASSERT_EQ(frame_count(e_.raw_size, 4 * kMiB), 5u);
  }
  const uint8_t* stored(const std::string& b) const {
    return reinterpret_cast<const uint8_t*>(b.data()) + e_.offset;
  }
  uint64_t index_bytes() const { return sizeof(FrameIndexHeader) + 5 * sizeof(FrameEntry); }
  // File offset of frame k of section 1.
  uint64_t frame_at(uint64_t k) const {
    uint64_t at = e_.offset + index_bytes();
    for (uint64_t j = 0; j < k; ++j) at += frame_entry(stored(good_), j).stored_size;
    return at;
  }
  // Entry k replaced, and the index's checksum (then the table's and header's) made right.
  void put_frame_entry(std::string* b, uint64_t k, const FrameEntry& f) {
    std::memcpy(&(*b)[e_.offset + sizeof(FrameIndexHeader) + k * sizeof f], &f, sizeof f);
    test_bytes::reseal(b, 1, index_bytes());
  }
  std::string error_of(const std::string& b) { return load_error(dir_ + "/t.pbrta", b); }
  std::string prefix() const { return dir_ + "/t.pbrta: section 'geometry' (#1): "; }

  std::string dir_, good_;
  SectionEntry e_{};
};

TEST_F(ZstdFramesDamage, FlippedByteInAFrameNamesTheFrame) {
  std::string b = good_;
  b[frame_at(1) + frame_entry(stored(good_), 1).stored_size / 2] ^= 0x10;
  EXPECT_EQ(error_of(b), prefix() + "frame 1: checksum mismatch");
  // And in the index itself: the section's checksum.
  b = good_;
  b[e_.offset + 40] ^= 0x01;
  EXPECT_EQ(error_of(b), prefix() + "checksum mismatch");
}

TEST_F(ZstdFramesDamage, ForgedFrameDamageIsRefusedByZstd) {
  std::string b = good_;
  const FrameEntry f = frame_entry(stored(good_), 1);
  ASSERT_GT(f.stored_size, 1000u);
  // Its frame header and first block header: a literal block's bytes in the middle could change
  // undetected once the checksum is forged (the frames carry no checksum of their own).
  std::memset(&b[frame_at(1) + 4], 0xFF, 64);
  FrameEntry forged = f;
  forged.checksum = XXH3_64bits(b.data() + frame_at(1), f.stored_size);
  put_frame_entry(&b, 1, forged);
  const std::string m = error_of(b);
  EXPECT_EQ(m.rfind(prefix() + "frame 1: zstd", 0), 0u) << m;
}

TEST_F(ZstdFramesDamage, MalformedIndexIsRefused) {
  std::string b = good_;
  FrameEntry f = frame_entry(stored(good_), 0);
  f.reserved = 1;
  put_frame_entry(&b, 0, f);
  EXPECT_EQ(error_of(b), prefix() + "frame 0: reserved field is not zero");

  b = good_;
  f = frame_entry(stored(good_), 1);
  f.stored_size = 0;
  put_frame_entry(&b, 1, f);
  EXPECT_EQ(error_of(b).rfind(prefix() + "frame 1: 0 bytes at offset", 0), 0u);

  b = good_;
  f = frame_entry(stored(good_), 4);
  f.stored_size = static_cast<uint32_t>(e_.stored_size);  // runs past the section
  put_frame_entry(&b, 4, f);
  EXPECT_EQ(
      error_of(b).rfind(prefix() + "frame 4: " + std::to_string(e_.stored_size) + " bytes", 0), 0u);

  // A last frame one byte shorter leaves a byte over.
  b = good_;
  f = frame_entry(stored(good_), 4);
  f.stored_size -= 1;
  put_frame_entry(&b, 4, f);
  EXPECT_EQ(error_of(b), prefix() + "1 stored bytes follow the last frame");

  // The header: frame sizes that are not a power of two from 64 KiB to 16 MiB, unknown flags, a
  // reserved word set. (A valid but different frame size changes the index's length, and so its
  // checksum.)
  for (const uint32_t size : {3u << 20, 32u << 10, 32u << 20}) {
    b = good_;
    FrameIndexHeader h = index_header(stored(good_));
    h.frame_size = size;
    std::memcpy(&b[e_.offset], &h, sizeof h);
    test_bytes::reseal(&b, 1, index_bytes());
    EXPECT_EQ(error_of(b), prefix() + "frame size " + std::to_string(size) +
                               " is not a power of two from 64 KiB to 16 MiB");
  }
  for (const bool flags : {true, false}) {
    b = good_;
    FrameIndexHeader h = index_header(stored(good_));
    if (flags)
      h.flags |= 2;
    else
      h.reserved = 1;
    std::memcpy(&b[e_.offset], &h, sizeof h);
    test_bytes::reseal(&b, 1, index_bytes());
    EXPECT_EQ(error_of(b), prefix() + "unknown frame flags or reserved bits set");
  }
  // An index longer than the stored bytes, or not even a header.
  const FrameIndexHeader h{64u << 10, 0, 0};  // 16 MiB + 100 in 64 KiB frames: 257 entries
  std::vector<uint8_t> small(200, 0);
  std::memcpy(small.data(), &h, sizeof h);
  FrameIndex index;
  std::string why;
  EXPECT_FALSE(read_frame_header(small.data(), small.size(), e_.raw_size, &index, &why));
  EXPECT_EQ(why, "the frame index of 257 entries does not fit in 200 stored bytes");
  EXPECT_FALSE(read_frame_header(small.data(), 15, 0, &index, &why));
  EXPECT_EQ(why, "the frame index header does not fit in 15 bytes");
}

}  // namespace
}  // namespace pbrta
