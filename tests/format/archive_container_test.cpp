// tests/format/archive_container_test.cpp — the archive container (format/archive_writer.h,
// format/archive_reader.h): round trips through every codec, byte-for-byte determinism across
// thread counts, the layout rules (alignment, padding), atomic writes, one test per rejection
// with its exact message, truncation at every section boundary and a corruption sweep over every
// byte of a small archive. It also writes the seed archives of the archive fuzzer.
#include <signal.h>
#include <sys/resource.h>

#include <gtest/gtest.h>
#include <xxhash.h>
#include <zstd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "format/archive.h"
#include "format/archive_names.h"
#include "format/archive_reader.h"
#include "format/archive_writer.h"
#include "fuzz/archive_reseal.h"
#include "test_support.h"

namespace pbrta {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Building and editing archive images.

std::vector<uint8_t> text_bytes(size_t n) {
  static const char kWords[] = "shape material texture light camera sampler film filter ";
  std::vector<uint8_t> v(n);
  for (size_t i = 0; i < n; ++i) v[i] = static_cast<uint8_t>(kWords[(i * 7 + i / 13) % 57]);
  return v;
}

// Smooth floats, the kind of data shuffle4 is for.
std::vector<uint8_t> float_bytes(size_t floats, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.f, 0.01f);
  std::vector<float> f(floats);
  for (size_t i = 0; i < floats; ++i) f[i] = std::sin(0.01f * static_cast<float>(i)) + noise(rng);
  std::vector<uint8_t> v(floats * 4);
  std::memcpy(v.data(), f.data(), v.size());
  return v;
}

std::vector<uint8_t> random_bytes(size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> v(n);
  for (uint8_t& b : v) b = static_cast<uint8_t>(rng());
  return v;
}

struct TestSection {
  SectionKind kind;
  Codec codec;
  uint32_t count;
  std::vector<uint8_t> raw;
  bool shuffle = false;
};

// About ten sections of every codec, including empty ones and sizes that are not multiples of 4.
std::vector<TestSection> mixed_sections() {
  std::vector<TestSection> s;
  s.push_back({SectionKind::kScene, Codec::kRaw, 1, random_bytes(112, 1)});
  s.push_back({SectionKind::kStrings, Codec::kZstd, 40, text_bytes(3000)});
  s.push_back({SectionKind::kEntities, Codec::kRaw, 20, random_bytes(16 * 20, 2)});
  s.push_back({SectionKind::kValues, Codec::kZstd, 50, random_bytes(16 * 50, 3), true});
  s.push_back({SectionKind::kTransforms, Codec::kZstd, 3, float_bytes(272 * 3 / 4, 4)});
  s.push_back({SectionKind::kGeometry, Codec::kZstd, 1500, float_bytes(1500, 5), true});
  s.push_back({SectionKind::kTexels, Codec::kZstd, 1003, random_bytes(1003, 6), true});
  s.push_back({SectionKind::kMeshes, Codec::kRaw, 0, {}});
  s.push_back({SectionKind::kProvenance, Codec::kZstd, 0, {}});
  s.push_back({SectionKind::kImages, Codec::kRaw, 13, random_bytes(13, 7)});
  s.push_back({SectionKind::kObjectShapes, Codec::kZstd, 2, random_bytes(3, 8), true});
  return s;
}

void add_all(ArchiveWriter* w, const std::vector<TestSection>& sections) {
  for (const TestSection& s : sections) w->add_section(s.kind, s.raw, s.count, s.codec, s.shuffle);
}

// Writes sections to path; returns the file's bytes.
std::string write_archive(const std::string& path, const std::vector<TestSection>& sections,
                          int threads = 2, int level = 3) {
  ArchiveWriter w;
  add_all(&w, sections);
  std::string error;
  EXPECT_TRUE(w.write(path, kEffectTextures | kEffectAlpha, level, threads, &error)) << error;
  return testing_support::read_file(path);
}

Header get_header(const std::string& b) {
  Header h;
  std::memcpy(&h, b.data(), sizeof(h));
  return h;
}

void put_header(std::string* b, const Header& h) {
  std::memcpy(b->data(), &h, sizeof(h));
}

SectionEntry get_entry(const std::string& b, uint32_t i) {
  SectionEntry e;
  std::memcpy(&e, b.data() + sizeof(Header) + i * sizeof(SectionEntry), sizeof(e));
  return e;
}

void put_entry(std::string* b, uint32_t i, const SectionEntry& e) {
  std::memcpy(b->data() + sizeof(Header) + i * sizeof(SectionEntry), &e, sizeof(e));
}

// After an edit: recomputes the checksums so that the reader's deeper checks are reached. With
// sections, also every section's (and frame's) checksum whose bytes lie inside the image.
void reseal(std::string* b, bool sections = false) {
  if (sections) {
    std::vector<uint8_t> v(b->begin(), b->end());
    fuzz_support::reseal(&v);
    b->assign(v.begin(), v.end());
    return;
  }
  Header h = get_header(*b);
  const uint64_t table_bytes = uint64_t{h.section_count} * sizeof(SectionEntry);
  if (sizeof(Header) + table_bytes <= b->size())
    h.table_checksum = XXH3_64bits(b->data() + sizeof(Header), table_bytes);
  h.header_checksum = XXH3_64bits(&h, offsetof(Header, header_checksum));
  put_header(b, h);
}

// Opens (and loads) an image both from a file and from memory; both must fail with the same
// message, which is returned. name is the path the messages start with.
class Rejector {
 public:
  explicit Rejector(const std::string& test) : dir_(testing_support::scratch_dir(test)) {}
  std::string path() const { return dir_ + "/t.pbrta"; }

  std::string reject(const std::string& bytes) {
    testing_support::write_file(path(), bytes);
    std::string file_error, memory_error;
    {
      ArchiveReader r;
      bool ok = r.open(path(), &file_error) && r.load_sections(2, &file_error);
      EXPECT_FALSE(ok) << "the file was accepted";
    }
    {
      ArchiveReader r;
      bool ok = r.open_memory(bytes, path(), &memory_error) && r.load_sections(1, &memory_error);
      EXPECT_FALSE(ok) << "the image was accepted";
    }
    EXPECT_EQ(file_error, memory_error);
    return file_error;
  }

  bool accept(const std::string& bytes, ArchiveReader* r) {
    testing_support::write_file(path(), bytes);
    std::string error;
    const bool ok = r->open(path(), &error) && r->load_sections(2, &error);
    EXPECT_TRUE(ok) << error;
    return ok;
  }

 private:
  std::string dir_;
};

// ---------------------------------------------------------------------------------------------
// Round trips, determinism and layout.

TEST(ArchiveContainer, RoundTripsEveryCodec) {
  const std::string dir = testing_support::scratch_dir("ArchiveContainer.RoundTrips");
  const std::string path = dir + "/a.pbrta";
  const std::vector<TestSection> sections = mixed_sections();
  ArchiveWriter w;
  add_all(&w, sections);
  std::string error;
  ASSERT_TRUE(w.write(path, kEffectMedia | kEffectInstancing, 5, 2, &error)) << error;
  const std::string bytes = testing_support::read_file(path);
  EXPECT_EQ(w.last_file_size(), bytes.size());
  ASSERT_EQ(w.table().size(), sections.size());

  ArchiveReader r;
  ASSERT_TRUE(r.open(path, &error)) << error;
  ASSERT_TRUE(r.load_sections(2, &error)) << error;
  EXPECT_EQ(r.header().effects, uint64_t{kEffectMedia | kEffectInstancing});
  EXPECT_EQ(r.header().major, kMajorVersion);
  EXPECT_EQ(r.header().minor, kMinorVersion);
  EXPECT_EQ(r.file_size(), bytes.size());
  ASSERT_EQ(r.section_count(), sections.size());
  for (uint32_t i = 0; i < r.section_count(); ++i) {
    SCOPED_TRACE(std::string(section_kind_name(sections[i].kind)));
    const SectionEntry& e = r.entry(i);
    EXPECT_EQ(e.kind, static_cast<uint32_t>(sections[i].kind));
    EXPECT_EQ(e.codec, static_cast<uint32_t>(sections[i].codec));
    EXPECT_EQ(e.count, sections[i].count);
    EXPECT_EQ(std::memcmp(&e, &w.table()[i], sizeof(e)), 0);
    ASSERT_EQ(r.section_size(i), sections[i].raw.size());
    const uint8_t* data = r.section_data(i);
    ASSERT_NE(data, nullptr);
    EXPECT_EQ(reinterpret_cast<uintptr_t>(data) % 16, 0u);
    if (!sections[i].raw.empty()) {
      EXPECT_EQ(std::memcmp(data, sections[i].raw.data(), sections[i].raw.size()), 0);
    }
    for (uint64_t k = 0; k < kSectionPadding; ++k)
      EXPECT_EQ(data[r.section_size(i) + k], 0) << "padding byte " << k;
    if (sections[i].codec == Codec::kRaw) {
      // In place: the bytes `offset` before the data are the start of the mapped file.
      EXPECT_TRUE(r.in_place(i));
      EXPECT_EQ(std::memcmp(data - e.offset, kMagic, sizeof(kMagic)), 0);
    } else {
      EXPECT_FALSE(r.in_place(i));
    }
  }
  EXPECT_EQ(r.find_section(SectionKind::kGeometry), 5);
  EXPECT_EQ(r.find_section(SectionKind::kLights), -1);

  // The stored form of a shuffled zstd section (ARCHIVE.md section 5): the index header (4 MiB
  // frames, shuffled), one entry, then one zstd frame of the Blosc-style shuffle, tail as is.
  const SectionEntry texels = r.entry(6);
  FrameIndexHeader fh;
  std::memcpy(&fh, bytes.data() + texels.offset, sizeof fh);
  EXPECT_EQ(fh.frame_size, 4u << 20);
  EXPECT_EQ(fh.flags, uint32_t(kFrameShuffle4));
  EXPECT_EQ(fh.reserved, 0u);
  FrameEntry fe;
  std::memcpy(&fe, bytes.data() + texels.offset + 16, sizeof fe);
  EXPECT_EQ(32 + fe.stored_size, texels.stored_size);
  EXPECT_EQ(texels.checksum, XXH3_64bits(bytes.data() + texels.offset, 32));
  EXPECT_EQ(fe.checksum, XXH3_64bits(bytes.data() + texels.offset + 32, fe.stored_size));
  std::vector<uint8_t> decoded(texels.raw_size);
  ASSERT_EQ(ZSTD_decompress(decoded.data(), decoded.size(), bytes.data() + texels.offset + 32,
                            fe.stored_size),
            texels.raw_size);
  const std::vector<uint8_t>& raw = sections[6].raw;
  const size_t words = raw.size() / 4;
  for (size_t w4 = 0; w4 < words; ++w4)
    for (size_t b = 0; b < 4; ++b) ASSERT_EQ(decoded[b * words + w4], raw[4 * w4 + b]);
  for (size_t t = 4 * words; t < raw.size(); ++t) ASSERT_EQ(decoded[t], raw[t]);
  // A raw section's checksum is over its 1 MiB chunks' checksums.
  const SectionEntry scene = r.entry(0);
  EXPECT_EQ(
      scene.checksum,
      XXH3_64bits(
          std::vector<uint64_t>{XXH3_64bits(bytes.data() + scene.offset, scene.stored_size)}.data(),
          8));
}

TEST(ArchiveContainer, TypedArrays) {
  const std::string dir = testing_support::scratch_dir("ArchiveContainer.TypedArrays");
  const std::string path = dir + "/a.pbrta";
  std::vector<TestSection> sections = mixed_sections();
  write_archive(path, sections);
  ArchiveReader r;
  std::string error;
  ASSERT_TRUE(r.open(path, &error)) << error;
  const EntityRecord* ents = nullptr;
  uint32_t count = 0;
  EXPECT_FALSE(r.typed_array(2, &ents, &count, &error));
  EXPECT_EQ(error, path + ": section 'entities' (#2): not loaded");
  ASSERT_TRUE(r.load_sections(1, &error)) << error;
  ASSERT_TRUE(r.typed_array(2, &ents, &count, &error)) << error;
  EXPECT_EQ(count, 20u);
  EXPECT_EQ(reinterpret_cast<const uint8_t*>(ents), r.section_data(2));
  const ValueRecord* values = nullptr;
  ASSERT_TRUE(r.typed_array(3, &values, &count, &error)) << error;
  EXPECT_EQ(count, 50u);
  const TransformRecord* xf = nullptr;
  EXPECT_FALSE(r.typed_array(1, &xf, &count, &error));
  EXPECT_EQ(error, path + ": section 'strings' (#1): 3000 bytes is not 40 records of 272 bytes");
  EXPECT_FALSE(r.typed_array(99, &xf, &count, &error));
  EXPECT_EQ(error, path + ": section #99 does not exist (the archive has 11)");
}

TEST(ArchiveContainer, DeterministicAcrossThreadCounts) {
  const std::string dir = testing_support::scratch_dir("ArchiveContainer.Deterministic");
  std::vector<TestSection> sections = mixed_sections();
  sections.push_back({SectionKind::kGeometry, Codec::kZstd, 0, float_bytes(300000, 9), true});
  sections.push_back({SectionKind::kTexels, Codec::kZstd, 0, random_bytes(200000, 10)});
  ArchiveWriter w;
  add_all(&w, sections);
  std::string error;
  ASSERT_TRUE(w.write(dir + "/t1.pbrta", 0, 9, 1, &error)) << error;
  ASSERT_TRUE(w.write(dir + "/t2.pbrta", 0, 9, 2, &error)) << error;
  ASSERT_TRUE(w.write(dir + "/t0.pbrta", 0, 9, 0, &error)) << error;
  const std::string a = testing_support::read_file(dir + "/t1.pbrta");
  EXPECT_FALSE(a.empty());
  EXPECT_TRUE(a == testing_support::read_file(dir + "/t2.pbrta"));
  EXPECT_TRUE(a == testing_support::read_file(dir + "/t0.pbrta"));
  // A fresh writer given the same sections agrees too.
  ArchiveWriter w2;
  add_all(&w2, sections);
  ASSERT_TRUE(w2.write(dir + "/u.pbrta", 0, 9, 2, &error)) << error;
  EXPECT_TRUE(a == testing_support::read_file(dir + "/u.pbrta"));
}

// Progress: the raw bytes of the zstd sections (not the stored or Draco ones), counted up as
// sections finish on any thread, never two reports at once, the last one the whole. The bytes
// written are those of a write without a progress callback.
TEST(ArchiveContainer, ReportsCompressionProgress) {
  const std::string dir = testing_support::scratch_dir("ArchiveContainer.Progress");
  std::vector<TestSection> sections = mixed_sections();
  for (uint32_t k = 0; k < 6; ++k)
    sections.push_back(
        {SectionKind::kGeometry, Codec::kZstd, 0, float_bytes(100000 + 1000 * k, 20 + k), true});
  uint64_t expected_total = 0;
  for (const TestSection& t : sections)
    if (t.codec != Codec::kRaw) expected_total += t.raw.size();
  ArchiveWriter w;
  add_all(&w, sections);
  for (int threads : {1, 2}) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    std::vector<std::pair<uint64_t, uint64_t>> calls;
    std::atomic<int> inside{0};
    bool overlapped = false;
    std::string error;
    ASSERT_TRUE(w.write(dir + "/p.pbrta", 0, 3, threads, &error,
                        [&](uint64_t done, uint64_t total) {
                          overlapped |= inside++ != 0;
                          calls.emplace_back(done, total);
                          --inside;
                        }))
        << error;
    EXPECT_FALSE(overlapped);
    ASSERT_FALSE(calls.empty());
    for (size_t k = 0; k < calls.size(); ++k) {
      EXPECT_EQ(calls[k].second, expected_total);
      if (k > 0) {
        EXPECT_LE(calls[k - 1].first, calls[k].first);  // an empty section adds nothing
      }
    }
    EXPECT_EQ(calls.back().first, expected_total);
    if (threads == 1) {
      EXPECT_GE(calls.size(), 6u);  // one thread never skips a report
    }
    ASSERT_TRUE(w.write(dir + "/q.pbrta", 0, 3, threads, &error)) << error;
    EXPECT_TRUE(testing_support::read_file(dir + "/p.pbrta") ==
                testing_support::read_file(dir + "/q.pbrta"));
  }
  // Nothing to compress, no report.
  ArchiveWriter none;
  none.add_section(SectionKind::kScene, random_bytes(112, 1), 1, Codec::kRaw);
  int reports = 0;
  std::string error;
  ASSERT_TRUE(none.write(dir + "/n.pbrta", 0, 3, 2, &error, [&](uint64_t, uint64_t) { ++reports; }))
      << error;
  EXPECT_EQ(reports, 0);
}

TEST(ArchiveContainer, LayoutAlignmentAndPadding) {
  const std::string dir = testing_support::scratch_dir("ArchiveContainer.Layout");
  const std::vector<TestSection> sections = mixed_sections();
  const std::string b = write_archive(dir + "/a.pbrta", sections);
  const Header h = get_header(b);
  EXPECT_EQ(std::memcmp(h.magic, kMagic, 8), 0);
  EXPECT_EQ(h.flags, 0u);
  EXPECT_EQ(h.reserved0, 0u);
  EXPECT_EQ(h.table_offset, 64u);
  EXPECT_EQ(h.file_size, b.size());
  EXPECT_EQ(h.section_count, sections.size());
  EXPECT_EQ(h.header_checksum, XXH3_64bits(b.data(), 56));
  EXPECT_EQ(h.table_checksum, XXH3_64bits(b.data() + 64, 48 * sections.size()));
  uint64_t prev_end = 64 + 48 * sections.size();
  for (uint32_t i = 0; i < h.section_count; ++i) {
    const SectionEntry e = get_entry(b, i);
    EXPECT_EQ(e.offset % 16, 0u);
    EXPECT_GE(e.offset, prev_end);
    EXPECT_EQ(e.reserved, 0u);
    for (uint64_t k = prev_end; k < e.offset; ++k) EXPECT_EQ(b[k], 0) << "byte " << k;
    prev_end = e.offset + e.stored_size + kSectionPadding;
    ASSERT_LE(prev_end, b.size());
    for (uint64_t k = e.offset + e.stored_size; k < prev_end; ++k) EXPECT_EQ(b[k], 0);
  }
  EXPECT_EQ(b.size() % 16, 0u);
  for (uint64_t k = prev_end; k < b.size(); ++k) EXPECT_EQ(b[k], 0);

  // No sections: just the header.
  ArchiveWriter empty;
  std::string error;
  ASSERT_TRUE(empty.write(dir + "/empty.pbrta", 0, 3, 1, &error)) << error;
  EXPECT_EQ(empty.last_file_size(), 64u);
  ArchiveReader r;
  ASSERT_TRUE(r.open(dir + "/empty.pbrta", &error)) << error;
  ASSERT_TRUE(r.load_sections(1, &error)) << error;
  EXPECT_EQ(r.section_count(), 0u);
}

// A section that compresses beyond the reader's zip-bomb bound is stored as it is, and a
// multitude of such small sections trips the total bound, which the writer also respects.
TEST(ArchiveContainer, WriterKeepsWithinTheReadersBounds) {
  const std::string dir = testing_support::scratch_dir("ArchiveContainer.WriterBounds");
  ArchiveWriter w;
  w.add_section(SectionKind::kTexels, std::vector<uint8_t>(4 << 20, 0), 0, Codec::kZstd);
  w.add_section(SectionKind::kGeometry, std::vector<uint8_t>(1 << 20, 0), 0, Codec::kZstd);
  std::string error;
  ASSERT_TRUE(w.write(dir + "/big.pbrta", 0, 3, 2, &error)) << error;
  // The bound is the zstd format's own limit, so even all-zero data stays compressed (a flat
  // texture's pyramid must), and the reader accepts it.
  EXPECT_EQ(w.table()[0].codec, static_cast<uint32_t>(Codec::kZstd));
  EXPECT_LT(w.table()[0].stored_size, w.table()[0].raw_size / 1000);
  EXPECT_EQ(w.table()[1].codec, static_cast<uint32_t>(Codec::kZstd));
  ArchiveReader r;
  ASSERT_TRUE(r.open(dir + "/big.pbrta", &error) && r.load_sections(2, &error)) << error;

  ArchiveWriter many;
  for (int i = 0; i < 70; ++i)
    many.add_section(SectionKind::kTexels, std::vector<uint8_t>(1 << 20, 0), 0, Codec::kZstd);
  ASSERT_TRUE(many.write(dir + "/many.pbrta", 0, 1, 2, &error)) << error;
  // Many compressible sections all stay compressed: the total bound never binds first.
  int raw_sections = 0;
  for (const SectionEntry& e : many.table()) raw_sections += e.codec == 0;
  EXPECT_EQ(raw_sections, 0);
  ArchiveReader r2;
  ASSERT_TRUE(r2.open(dir + "/many.pbrta", &error) && r2.load_sections(2, &error)) << error;
}

// ---------------------------------------------------------------------------------------------
// Atomic writes.

TEST(ArchiveContainer, WriteIntoMissingDirectoryFailsCleanly) {
  const std::string dir = testing_support::scratch_dir("ArchiveContainer.MissingDir");
  const std::string path = dir + "/no/such/dir/a.pbrta";
  ArchiveWriter w;
  add_all(&w, mixed_sections());
  std::string error;
  EXPECT_FALSE(w.write(path, 0, 3, 1, &error));
  EXPECT_EQ(error, "cannot write '" + path + "': No such file or directory");
  EXPECT_FALSE(fs::exists(dir + "/no"));
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(ArchiveContainer, FailedWriteLeavesTheOldFileIntact) {
  const std::string dir = testing_support::scratch_dir("ArchiveContainer.FailedWrite");
  const std::string path = dir + "/a.pbrta";
  const std::string good = write_archive(path, mixed_sections());
  ASSERT_FALSE(good.empty());

  // A write that runs out of room halfway: limit the file size (root ignores permissions, but
  // not RLIMIT_FSIZE) and ignore SIGXFSZ so write() fails with EFBIG instead.
  ArchiveWriter w;
  w.add_section(SectionKind::kTexels, random_bytes(1 << 20, 11), 0, Codec::kRaw);
  rlimit old_limit;
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &old_limit), 0);
  auto old_handler = signal(SIGXFSZ, SIG_IGN);
  rlimit small = old_limit;
  small.rlim_cur = 4096;
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
  std::string error;
  const bool ok = w.write(path, 0, 3, 1, &error);
  setrlimit(RLIMIT_FSIZE, &old_limit);
  signal(SIGXFSZ, old_handler);
  EXPECT_FALSE(ok);
  EXPECT_EQ(error, "cannot write '" + path + "': File too large");
  EXPECT_TRUE(testing_support::read_file(path) == good);
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    EXPECT_EQ(entry.path().filename(), "a.pbrta");
    ++files;
  }
  EXPECT_EQ(files, 1);

  // The path is a directory: the rename fails, the temporary is removed.
  const std::string sub = dir + "/sub";
  fs::create_directories(sub + "/keep");
  EXPECT_FALSE(w.write(sub, 0, 3, 1, &error));
  EXPECT_EQ(error, "cannot write '" + sub + "': Is a directory");
  EXPECT_TRUE(fs::is_directory(sub + "/keep"));
  files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    (void)entry;
    ++files;
  }
  EXPECT_EQ(files, 2);  // a.pbrta and sub: no temporary left
}

// ---------------------------------------------------------------------------------------------
// Rejections, each with its exact message.

class ArchiveRejection : public ::testing::Test {
 protected:
  void SetUp() override {
    rejector_ =
        std::make_unique<Rejector>(std::string("ArchiveRejection.") +
                                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
    const std::string dir = testing_support::scratch_dir(
        std::string("ArchiveRejection.src.") +
        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    good_ = write_archive(dir + "/good.pbrta", mixed_sections());
    ASSERT_FALSE(good_.empty());
  }
  std::string reject(const std::string& bytes) { return rejector_->reject(bytes); }
  std::string p() const { return rejector_->path(); }

  std::unique_ptr<Rejector> rejector_;
  std::string good_;
};

TEST_F(ArchiveRejection, TooShort) {
  EXPECT_EQ(reject(""), p() + ": truncated: the file has 0 bytes, less than the 64-byte header");
  EXPECT_EQ(reject(good_.substr(0, 63)),
            p() + ": truncated: the file has 63 bytes, less than the 64-byte header");
}

TEST_F(ArchiveRejection, BadMagic) {
  std::string b = good_;
  b[1] = 'Q';
  EXPECT_EQ(reject(b), p() + ": not a pbrt scene archive (bad magic)");
}

TEST_F(ArchiveRejection, HeaderChecksum) {
  std::string b = good_;
  b[16] ^= 4;  // effects
  EXPECT_EQ(reject(b), p() + ": header checksum mismatch");
}

TEST_F(ArchiveRejection, VersionsOtherThanTwoAreRefused) {
  std::string b = good_;
  Header h = get_header(b);
  h.major = 3;
  h.minor = 0;
  put_header(&b, h);
  reseal(&b);
  EXPECT_EQ(reject(b),
            p() + ": archive version 3.0: this reader reads 2.x; update pbrtc and pbrtrun");
  h.major = 1;
  h.minor = 4;
  put_header(&b, h);
  reseal(&b);
  EXPECT_EQ(reject(b), p() + ": archive version 1.4: recompile with this pbrtc");
}

TEST_F(ArchiveRejection, NewerMinorVersionIsAcceptedAndUnknownKindsSkipped) {
  std::string b = good_;
  Header h = get_header(b);
  h.minor = kMinorVersion + 1;
  put_header(&b, h);
  SectionEntry e = get_entry(b, 4);
  e.kind = 99;
  put_entry(&b, 4, e);
  reseal(&b);
  ArchiveReader r;
  ASSERT_TRUE(rejector_->accept(b, &r));
  EXPECT_EQ(r.header().minor, kMinorVersion + 1);
  EXPECT_TRUE(r.skipped(4));
  EXPECT_EQ(r.section_data(4), nullptr);
  EXPECT_FALSE(r.skipped(5));
  EXPECT_NE(r.section_data(5), nullptr);
  EXPECT_EQ(r.find_section(SectionKind::kTransforms), -1);

  // The same unknown kind in the reader's own version is damage.
  h.minor = kMinorVersion;
  put_header(&b, h);
  reseal(&b);
  EXPECT_EQ(reject(b), p() + ": section 'kind 99' (#4): unknown section kind 99 in a version 2." +
                           std::to_string(kMinorVersion) + " archive");
}

TEST_F(ArchiveRejection, ReservedHeaderFields) {
  std::string b = good_;
  Header h = get_header(b);
  h.flags = 1;
  put_header(&b, h);
  reseal(&b);
  EXPECT_EQ(reject(b), p() + ": reserved header fields are not zero");
  h.flags = 0;
  h.table_offset = 128;
  put_header(&b, h);
  reseal(&b);
  EXPECT_EQ(reject(b), p() + ": section table offset is 128; expected 64");
}

TEST_F(ArchiveRejection, TableChecksum) {
  std::string b = good_;
  b[64 + 48 * 3 + 20] ^= 1;  // stored_size of #3
  EXPECT_EQ(reject(b), p() + ": section table checksum mismatch");
}

TEST_F(ArchiveRejection, SectionCountBeyondTheFile) {
  std::string b = good_;
  Header h = get_header(b);
  h.section_count = 0xFFFFFFFFu;
  put_header(&b, h);
  reseal(&b);
  EXPECT_EQ(reject(b), p() + ": truncated: the section table (4294967295 sections) ends at byte " +
                           std::to_string(64 + 48 * uint64_t{0xFFFFFFFFu}) + " but the file has " +
                           std::to_string(b.size()) + " bytes");
}

TEST_F(ArchiveRejection, MisalignedOffset) {
  std::string b = good_;
  SectionEntry e = get_entry(b, 2);
  e.offset += 8;
  put_entry(&b, 2, e);
  reseal(&b);
  EXPECT_EQ(reject(b), p() + ": section 'entities' (#2): offset " + std::to_string(e.offset) +
                           " is not a multiple of 16");
}

TEST_F(ArchiveRejection, OffsetInsideTheTable) {
  std::string b = good_;
  SectionEntry e = get_entry(b, 0);
  e.offset = 64;
  put_entry(&b, 0, e);
  reseal(&b);
  EXPECT_EQ(reject(b), p() +
                           ": section 'scene' (#0): offset 64 lies inside the header or section "
                           "table, which end at byte 592");
}

TEST_F(ArchiveRejection, OffsetOutOfBounds) {
  std::string b = good_;
  SectionEntry e = get_entry(b, 9);
  e.offset = b.size() + 4096;
  put_entry(&b, 9, e);
  reseal(&b);
  EXPECT_EQ(reject(b), p() + ": section 'images' (#9): truncated: section ends at byte " +
                           std::to_string(e.offset + 13) + " but the file has " +
                           std::to_string(b.size()) + " bytes");
  // offset + stored_size overflows uint64.
  std::string c = good_;
  SectionEntry e2 = get_entry(c, 2);
  e2.offset = 0xFFFFFFFFFFFFFFF0ull;
  put_entry(&c, 2, e2);
  reseal(&c);
  EXPECT_EQ(reject(c), p() +
                           ": section 'entities' (#2): truncated: section ends at byte > 2^64 "
                           "but the file has " +
                           std::to_string(c.size()) + " bytes");
  // Ends inside the file but its padding does not.
  e.offset = b.size() - 16;
  put_entry(&b, 9, e);
  reseal(&b);
  EXPECT_EQ(reject(b), p() +
                           ": section 'images' (#9): truncated: the padding after the section "
                           "ends at byte " +
                           std::to_string(b.size() + 13) + " but the file has " +
                           std::to_string(b.size()) + " bytes");
}

TEST_F(ArchiveRejection, OverlappingSections) {
  std::string b = good_;
  const SectionEntry e1 = get_entry(b, 1);
  SectionEntry e2 = get_entry(b, 2);
  e2.offset = e1.offset + 16;
  put_entry(&b, 2, e2);
  reseal(&b);
  EXPECT_EQ(reject(b), p() + ": section 'entities' (#2): starts at byte " +
                           std::to_string(e2.offset) +
                           ", inside section 'strings' (#1) or its "
                           "padding, which end at byte " +
                           std::to_string(e1.offset + e1.stored_size + 16));
  // Touching the previous section's 16 bytes of padding is overlap too.
  const SectionEntry e9 = get_entry(b, 9);
  SectionEntry e10 = get_entry(b, 10);
  b = good_;
  e10.offset = e9.offset + 16;  // images is 13 bytes: its padding ends at offset + 29
  put_entry(&b, 10, e10);
  reseal(&b);
  EXPECT_EQ(reject(b), p() + ": section 'object_shapes' (#10): starts at byte " +
                           std::to_string(e10.offset) +
                           ", inside section 'images' (#9) or its "
                           "padding, which end at byte " +
                           std::to_string(e9.offset + 29));
}

TEST_F(ArchiveRejection, UnknownCodecAndReservedEntryField) {
  std::string b = good_;
  SectionEntry e = get_entry(b, 3);
  e.codec = uint32_t(Codec::kCount);
  put_entry(&b, 3, e);
  reseal(&b);
  EXPECT_EQ(reject(b), p() + ": section 'values' (#3): unknown codec " +
                           std::to_string(uint32_t(Codec::kCount)));
  e.codec = 2;  // Draco: geometry sections of one mesh only
  put_entry(&b, 3, e);
  reseal(&b);
  EXPECT_EQ(reject(b), p() +
                           ": section 'values' (#3): codec 'draco' is only for a geometry "
                           "section of one mesh (this one is kind 4 with count 50)");
  e.codec = 1;
  e.reserved = 7;
  put_entry(&b, 3, e);
  reseal(&b);
  EXPECT_EQ(reject(b), p() + ": section 'values' (#3): reserved field is not zero");
}

TEST_F(ArchiveRejection, RawSizeBounds) {
  std::string b = good_;
  SectionEntry e = get_entry(b, 1);  // zstd strings
  e.raw_size = e.stored_size * kMaxZstdRatio + (1 << 20) + 1;
  put_entry(&b, 1, e);
  reseal(&b);
  EXPECT_EQ(reject(b), p() + ": section 'strings' (#1): raw size " + std::to_string(e.raw_size) +
                           " is implausible for " + std::to_string(e.stored_size) +
                           " bytes of zstd (at most 32768x + 1 MiB)");
  e.raw_size = (uint64_t{1} << 40) + 1;
  put_entry(&b, 1, e);
  reseal(&b);
  EXPECT_EQ(reject(b), p() +
                           ": section 'strings' (#1): raw size 1099511627777 exceeds the limit "
                           "of 2^40 bytes");
  b = good_;
  e = get_entry(b, 2);  // raw entities
  e.raw_size += 1;
  put_entry(&b, 2, e);
  reseal(&b);
  EXPECT_EQ(reject(b), p() +
                           ": section 'entities' (#2): raw size 321 differs from stored size 320 "
                           "with codec 'raw'");
}

TEST_F(ArchiveRejection, FileSizeField) {
  std::string b = good_;
  b.append(16, '\0');
  EXPECT_EQ(reject(b), p() + ": the header records " + std::to_string(good_.size()) +
                           " bytes but the file has " + std::to_string(b.size()) + " bytes");
  // Trailing garbage the header accounts for is nonzero padding.
  Header h = get_header(b);
  h.file_size = b.size();
  put_header(&b, h);
  b[b.size() - 3] = 1;
  reseal(&b);
  EXPECT_EQ(reject(b), p() + ": section 'object_shapes' (#10): nonzero byte at offset " +
                           std::to_string(b.size() - 3) + " in the padding after the section");
}

// (No test reaches the total bound with entries that each pass the per-section bound: every
// section adds at least 64 bytes of table and padding to the file, worth 2 MiB of total
// allowance, more than the per-section slack of 1 MiB. The total bound stays as a second line.)

TEST_F(ArchiveRejection, NonzeroPadding) {
  std::string b = good_;
  const SectionEntry e = get_entry(b, 0);
  b[e.offset + e.stored_size + 5] = 'x';
  EXPECT_EQ(reject(b), p() + ": section 'scene' (#0): nonzero byte at offset " +
                           std::to_string(e.offset + e.stored_size + 5) +
                           " in the padding after the section");
}

TEST_F(ArchiveRejection, SectionChecksumMismatch) {
  // A raw section's chunks, a zstd section's index (header and entry: its first 32 bytes) or one
  // of its frames.
  for (uint32_t i : {0u, 1u, 3u, 6u}) {
    for (const bool in_index : {false, true}) {
      std::string b = good_;
      const SectionEntry e = get_entry(b, i);
      const bool zstd = e.codec == uint32_t(Codec::kZstd);
      if (in_index && !zstd) continue;
      const uint64_t at = in_index ? 20 : e.stored_size / 2;
      ASSERT_TRUE(!zstd || in_index || at >= 32) << "the middle of a frame";
      b[e.offset + at] ^= 0x20;
      EXPECT_EQ(reject(b), p() + ": section '" +
                               std::string(section_kind_name(static_cast<SectionKind>(e.kind))) +
                               "' (#" + std::to_string(i) + "): " +
                               (zstd && !in_index ? "frame 0: " : "") + "checksum mismatch");
    }
  }
}

TEST_F(ArchiveRejection, ZstdContentSizeLies) {
  std::string b = good_;
  SectionEntry e = get_entry(b, 5);  // geometry, shuffled
  const uint64_t real = e.raw_size;
  e.raw_size = real + 4;
  put_entry(&b, 5, e);
  reseal(&b);
  EXPECT_EQ(reject(b), p() + ": section 'geometry' (#5): frame 0: zstd frame content size is " +
                           std::to_string(real) + " but the block has " + std::to_string(real + 4) +
                           " bytes");
}

TEST_F(ArchiveRejection, ZstdDamage) {
  // A damaged frame whose checksum was forged: zstd itself must refuse it. (The frame follows
  // the index: a 16-byte header and one 16-byte entry.)
  std::string b = good_;
  const SectionEntry e = get_entry(b, 1);
  const uint64_t frame = e.offset + 32;
  for (uint64_t k = frame + 8; k < e.offset + e.stored_size; ++k) b[k] = static_cast<char>(0xFF);
  reseal(&b, true);
  const std::string message = reject(b);
  EXPECT_EQ(message.rfind(p() + ": section 'strings' (#1): frame 0: zstd: ", 0), 0u) << message;
  // Not a frame at all.
  b = good_;
  std::memset(b.data() + frame, 0x42, 8);
  reseal(&b, true);
  EXPECT_EQ(reject(b), p() + ": section 'strings' (#1): frame 0: zstd: not a zstd frame");
  // A malformed index header: a frame size that is not a power of two, an unknown flag.
  for (const uint32_t word : {1u, 2u}) {
    b = good_;
    const uint32_t bad = word == 1 ? (3u << 20) : 6u;  // the flags word: bit 1 is unknown
    std::memcpy(b.data() + e.offset + 4 * (word - 1), &bad, 4);
    reseal(&b, true);
    EXPECT_EQ(reject(b), p() + ": section 'strings' (#1): " +
                             (word == 1 ? "frame size 3145728 is not a power of two from 64 KiB "
                                          "to 16 MiB"
                                        : "unknown frame flags or reserved bits set"));
  }
}

// ---------------------------------------------------------------------------------------------
// Truncation and a corruption sweep.

TEST_F(ArchiveRejection, TruncationAtEverySectionBoundary) {
  const Header h = get_header(good_);
  std::vector<uint64_t> cuts = {64, 65, 64 + 48, 64 + 48 * uint64_t{h.section_count} - 1};
  for (uint32_t i = 0; i < h.section_count; ++i) {
    const SectionEntry e = get_entry(good_, i);
    for (uint64_t c : {e.offset, e.offset + 1, e.offset + e.stored_size,
                       e.offset + e.stored_size + 15, e.offset + e.stored_size + 16})
      cuts.push_back(c);
  }
  std::mt19937 rng(12);
  for (int k = 0; k < 200; ++k) cuts.push_back(rng() % good_.size());
  for (uint64_t cut : cuts) {
    if (cut >= good_.size()) continue;
    SCOPED_TRACE("cut at " + std::to_string(cut));
    const std::string b = good_.substr(0, cut);
    const std::string message = reject(b);
    // The exact message: the first structure that no longer fits.
    std::string expected;
    const std::string has = " but the file has " + std::to_string(cut) + " bytes";
    if (cut < 64) {
      expected = p() + ": truncated: the file has " + std::to_string(cut) +
                 " bytes, less than the 64-byte header";
    } else if (cut < 64 + 48 * uint64_t{h.section_count}) {
      expected = p() + ": truncated: the section table (11 sections) ends at byte 592" + has;
    } else {
      for (uint32_t i = 0; i < h.section_count && expected.empty(); ++i) {
        const SectionEntry e = get_entry(good_, i);
        const std::string where = p() + ": section '" +
                                  std::string(section_kind_name(static_cast<SectionKind>(e.kind))) +
                                  "' (#" + std::to_string(i) + "): truncated: ";
        if (e.offset + e.stored_size > cut)
          expected =
              where + "section ends at byte " + std::to_string(e.offset + e.stored_size) + has;
        else if (e.offset + e.stored_size + 16 > cut)
          expected = where + "the padding after the section ends at byte " +
                     std::to_string(e.offset + e.stored_size + 16) + has;
      }
      if (expected.empty())
        expected = p() + ": truncated: the header records " + std::to_string(good_.size()) +
                   " bytes" + has;
    }
    EXPECT_EQ(message, expected);
  }
}

TEST(ArchiveContainer, CorruptionSweep) {
  const std::string dir = testing_support::scratch_dir("ArchiveContainer.CorruptionSweep");
  const std::string path = dir + "/sweep.pbrta";
  const std::string good = write_archive(path, mixed_sections());
  const Header h = get_header(good);
  // Which bytes are padding (neither header, table nor section).
  std::vector<bool> padding(good.size(), true);
  for (uint64_t k = 0; k < 64 + 48 * uint64_t{h.section_count}; ++k) padding[k] = false;
  for (uint32_t i = 0; i < h.section_count; ++i) {
    const SectionEntry e = get_entry(good, i);
    for (uint64_t k = e.offset; k < e.offset + e.stored_size; ++k) padding[k] = false;
  }
  auto check = [&](const std::string& b, uint64_t where, bool via_file) {
    ArchiveReader r;
    std::string error;
    bool ok;
    if (via_file) {
      testing_support::write_file(path, b);
      ok = r.open(path, &error) && r.load_sections(2, &error);
    } else {
      ok = r.open_memory(b, path, &error) && r.load_sections(1, &error);
    }
    if (ok) {
      // Only padding could change unnoticed, and the reader checks that it is zero.
      ADD_FAILURE() << "a change at byte " << where << " (padding: " << padding[where]
                    << ") was accepted";
    } else {
      EXPECT_EQ(error.rfind(path + ": ", 0), 0u) << error;
    }
    return ok;
  };
  // Every byte, one at a time, with a one-bit flip; every 16th also through the file system.
  for (uint64_t k = 0; k < good.size(); ++k) {
    std::string b = good;
    b[k] ^= static_cast<char>(1u << (k % 8));
    check(b, k, k % 16 == 0);
  }
  // A few thousand random changes of whole bytes.
  std::mt19937 rng(13);
  for (int n = 0; n < 3000; ++n) {
    std::string b = good;
    const uint64_t k = rng() % good.size();
    b[k] ^= static_cast<char>(1 + rng() % 255);
    check(b, k, false);
  }
  // Truncation at every section boundary.
  for (uint32_t i = 0; i < h.section_count; ++i) {
    const SectionEntry e = get_entry(good, i);
    for (uint64_t c : {e.offset, e.offset + e.stored_size, e.offset + e.stored_size + 16})
      if (c < good.size()) check(good.substr(0, c), c, true);
  }
  std::printf("swept %zu bytes\n", good.size());
}

// ---------------------------------------------------------------------------------------------
// Seeds for the archive fuzzer (tests/fuzz/archive_fuzz.cpp; CTest's fuzz.archive runs this test
// first as a fixture). Small, so the fuzzer's 64 KiB inputs hold them whole.

TEST(ArchiveContainer, WritesFuzzSeeds) {
  const fs::path dir = fs::path(PBRTC_BINARY_DIR) / "fuzz-seeds" / "archive";
  fs::create_directories(dir);
  std::string error;
  {
    ArchiveWriter w;
    add_all(&w, mixed_sections());
    ASSERT_TRUE(w.write((dir / "mixed.pbrta").string(), kEffectAll, 3, 1, &error)) << error;
  }
  {  // shuffled frames, at zstd's highest level
    ArchiveWriter w;
    w.add_section(SectionKind::kScene, random_bytes(112, 21), 1, Codec::kRaw);
    w.add_section(SectionKind::kGeometry, float_bytes(2000, 22), 2000, Codec::kZstd, true);
    ASSERT_TRUE(w.write((dir / "geometry.pbrta").string(), 0, 19, 1, &error)) << error;
  }
  {  // plain frames
    ArchiveWriter w;
    w.add_section(SectionKind::kStrings, text_bytes(100), 3, Codec::kZstd);
    ASSERT_TRUE(w.write((dir / "strings.pbrta").string(), 0, 1, 1, &error)) << error;
  }
  {  // raw: one chunk, and an empty section (no chunk)
    ArchiveWriter w;
    w.add_section(SectionKind::kGeometry, float_bytes(3000, 24), 3000, Codec::kRaw);
    w.add_section(SectionKind::kTexels, {}, 0, Codec::kRaw);
    ASSERT_TRUE(w.write((dir / "chunked.pbrta").string(), 0, 3, 1, &error)) << error;
  }
  {  // several frames (of a repeating pattern, so the seed stays small)
    std::vector<uint8_t> pattern((uint64_t{8} << 20) + 4096);
    for (size_t k = 0; k < pattern.size(); ++k) pattern[k] = uint8_t(k % 12 < 4 ? k / 12 : 0);
    ArchiveWriter w;
    w.add_section(SectionKind::kGeometry, pattern, 1, Codec::kZstd, true);
    ASSERT_TRUE(w.write((dir / "frames.pbrta").string(), 0, 3, 1, &error)) << error;
    FrameIndexHeader fh;
    std::memcpy(
        &fh,
        testing_support::read_file((dir / "frames.pbrta").string()).data() + w.table()[0].offset,
        sizeof fh);
    EXPECT_GE(pattern.size() / fh.frame_size, 2u);
  }
  for (const char* name :
       {"mixed.pbrta", "geometry.pbrta", "strings.pbrta", "chunked.pbrta", "frames.pbrta"}) {
    ArchiveReader r;
    EXPECT_TRUE(r.open((dir / name).string(), &error) && r.load_sections(1, &error)) << error;
    EXPECT_LE(fs::file_size(dir / name), 65536u);
  }
}

}  // namespace
}  // namespace pbrta
