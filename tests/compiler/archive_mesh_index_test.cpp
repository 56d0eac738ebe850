// tests/compiler/archive_mesh_index_test.cpp — SceneArchive's check of every triangle's vertex
// indices, with each mesh's layout check: a bad index deep in a large mesh is found whatever the
// thread count, the message names the first bad one in mesh order, and an earlier mesh's bad
// index is reported before a later mesh's bad layout (the order a serial check finds them in),
// whether the archive is raw (used in place) or zstd (decoded by frame). Also: a large mesh
// archived with zstd loads to the same arrays as the raw archive.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "compiler/archive_builder.h"
#include "compiler/parser.h"
#include "compiler/scene_builder.h"
#include "format/archive.h"
#include "format/archive_writer.h"
#include "format/scene_archive.h"
#include "fuzz/archive_reseal.h"
#include "test_support.h"

namespace pbrtc {
namespace {

// A trianglemesh grid of n x n quads: (n+1)^2 vertices, 2 n^2 triangles.
std::string grid_mesh(int n) {
  std::string p = "\"point P\" [", idx = "\"integer indices\" [";
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x)
      p += " " + std::to_string(x) + " " + std::to_string(y) + " " + std::to_string((x * y) % 3);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const int a = y * (n + 1) + x, b = a + 1, c = a + n + 2, d = a + n + 1;
      for (int v : {a, b, c, a, c, d}) idx += " " + std::to_string(v);
    }
  return "Shape \"trianglemesh\" " + p + " ] " + idx + " ]\n";
}

class MeshIndexCheck : public ::testing::Test {
 protected:
  // 224 x 224 quads: 100352 triangles, 301056 indices, more than one 2^18-index chunk.
  static constexpr int kBig = 224;
  static constexpr uint32_t kBigVertices = (kBig + 1) * (kBig + 1);
  // 40 x 40 quads: 3200 triangles, 38400 bytes of indices, enough to be checked as they decode;
  // the 3 x 3 mesh between them (216 bytes) is read back.
  static constexpr int kMid = 40;
  static constexpr uint32_t kMidVertices = (kMid + 1) * (kMid + 1);

  void SetUp() override {
    dir_ = testing_support::scratch_dir(
        std::string("MeshIndexCheck.") +
        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    scene_ = testing_support::write_file(
        dir_ + "/s.pbrt",
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
        "LightSource \"point\"\n" +
            grid_mesh(kBig) + grid_mesh(3) + grid_mesh(kMid) + "WorldEnd\n");
  }

  // Compiles the scene to path, compressed or not; returns the archive's bytes.
  std::string compile_to(const std::string& path, bool compress) {
    SourceFiles files;
    Diagnostics diag(&files, nullptr);
    SceneDesc scene;
    EXPECT_TRUE(build_scene(scene_, &files, &diag, &scene));
    ArchiveOptions opt;
    opt.compress = compress;
    std::string error;
    EXPECT_TRUE(write_archive(scene, files, directory_of(scene_), path, opt, nullptr, &error))
        << error;
    return testing_support::read_file(path);
  }

  static pbrta::SectionEntry entry(const std::string& b, uint32_t i) {
    pbrta::SectionEntry e;
    std::memcpy(&e, b.data() + sizeof(pbrta::Header) + i * sizeof e, sizeof e);
    return e;
  }
  static void reseal(std::string* b) {
    std::vector<uint8_t> sealed(b->begin(), b->end());
    fuzz_support::reseal(&sealed);
    b->assign(sealed.begin(), sealed.end());
  }

  // The uncompressed archive, its mesh records and where they are in the file.
  void load_plain() {
    plain_ = compile_to(dir_ + "/plain.pbrta", false);
    std::string error;
    ASSERT_TRUE(archive_.load(dir_ + "/plain.pbrta", 1, &error)) << error;
    ASSERT_EQ(archive_.meshes.size, 3u);
    ASSERT_EQ(archive_.meshes[0].num_vertices, kBigVertices);
    ASSERT_EQ(archive_.meshes[2].num_vertices, kMidVertices);
    const int s = archive_.reader().find_section(pbrta::SectionKind::kMeshes);
    ASSERT_GE(s, 0);
    meshes_at_ = entry(plain_, uint32_t(s)).offset;
    // The big mesh's geometry spans two 1 MiB chunks, used in place.
    ASSERT_EQ(entry(plain_, archive_.meshes[0].section).codec, uint32_t(pbrta::Codec::kRaw));
    ASSERT_GT(entry(plain_, archive_.meshes[0].section).raw_size, uint64_t{1} << 20);
  }
  // File offset of mesh m's index k.
  uint64_t index_at(uint32_t m, uint64_t k) const {
    const pbrta::MeshRecord& r = archive_.meshes[m];
    return entry(plain_, r.section).offset + r.indices + 4 * k;
  }
  void set_u32(std::string* b, uint64_t at, uint32_t v) { std::memcpy(&(*b)[at], &v, 4); }

  std::string load_error(std::string bytes, int threads) {
    reseal(&bytes);
    const std::string path = dir_ + "/bad.pbrta";
    testing_support::write_file(path, bytes);
    pbrta::SceneArchive a;
    std::string error;
    EXPECT_FALSE(a.load(path, threads, &error)) << "accepted";
    return error;
  }

  // As load_error, after storing every section of the (resealed) archive again with zstd, the
  // geometry shuffled, in several frames.
  std::string load_error_zstd(std::string bytes, int threads) {
    reseal(&bytes);
    pbrta::ArchiveReader in;
    std::string error;
    EXPECT_TRUE(in.open_memory(bytes, "plain", &error) && in.load_sections(1, &error)) << error;
    pbrta::ArchiveWriter w;
    for (uint32_t i = 0; i < in.section_count(); ++i) {
      const pbrta::SectionEntry& e = in.entry(i);
      const bool bulk = e.kind == uint32_t(pbrta::SectionKind::kGeometry);
      w.add_section(pbrta::SectionKind(e.kind), in.section_data(i), in.section_size(i), e.count,
                    pbrta::Codec::kZstd, bulk);
    }
    const std::string path = dir_ + "/bad.pbrta";
    EXPECT_TRUE(w.write(path, in.header().effects, 3, 2, &error)) << error;
    EXPECT_EQ(w.table()[archive_.meshes[0].section].codec, uint32_t(pbrta::Codec::kZstd));
    pbrta::SceneArchive a;
    EXPECT_FALSE(a.load(path, threads, &error)) << "accepted";
    return error;
  }

  std::string dir_, scene_, plain_;
  pbrta::SceneArchive archive_;
  uint64_t meshes_at_ = 0;
};

TEST_F(MeshIndexCheck, BadIndexDeepInALargeMeshIsFoundOnAnyThreadCount) {
  load_plain();
  const std::string prefix =
      dir_ + "/bad.pbrta: section 'meshes' (#" +
      std::to_string(archive_.reader().find_section(pbrta::SectionKind::kMeshes)) + "): ";
  // In the second chunk (index 280001 of 301056), then also one in the first: the first wins.
  std::string b = plain_;
  set_u32(&b, index_at(0, 280001), kBigVertices);
  // Raw (used in place), and zstd (the big mesh's indices span two frames).
  for (bool zstd : {false, true}) {
    SCOPED_TRACE(zstd ? "zstd" : "raw");
    auto error_of = [&](const std::string& bytes, int threads) {
      return zstd ? load_error_zstd(bytes, threads) : load_error(bytes, threads);
    };
    std::string b = plain_;
    set_u32(&b, index_at(0, 280001), kBigVertices);
    for (int threads : {1, 2}) {
      EXPECT_EQ(error_of(b, threads), prefix + "mesh 0: triangle 93333 has vertex index " +
                                          std::to_string(kBigVertices) + " (" +
                                          std::to_string(kBigVertices) + " vertices)");
    }
    set_u32(&b, index_at(0, 5), 0xFFFFFFFFu);
    set_u32(&b, index_at(1, 0), 16);  // the small mesh has 16 vertices
    for (int threads : {1, 2})
      EXPECT_EQ(error_of(b, threads), prefix + "mesh 0: triangle 1 has vertex index 4294967295 (" +
                                          std::to_string(kBigVertices) + " vertices)");
    // Only the small mesh's.
    b = plain_;
    set_u32(&b, index_at(1, 53), 16);
    EXPECT_EQ(error_of(b, 2), prefix + "mesh 1: triangle 17 has vertex index 16 (16 vertices)");
    // A small mesh's (read back after decoding) before a later large one's (checked as it
    // decodes), and the large one's alone.
    set_u32(&b, index_at(2, 9000), kMidVertices);
    for (int threads : {1, 2})
      EXPECT_EQ(error_of(b, threads),
                prefix + "mesh 1: triangle 17 has vertex index 16 (16 vertices)");
    set_u32(&b, index_at(1, 53), 15);
    for (int threads : {1, 2})
      EXPECT_EQ(error_of(b, threads), prefix + "mesh 2: triangle 3000 has vertex index " +
                                          std::to_string(kMidVertices) + " (" +
                                          std::to_string(kMidVertices) + " vertices)");
    // Mesh 0's bad index comes before mesh 1's bad layout, as in a serial check.
    b = plain_;
    set_u32(&b, index_at(0, 300000), kBigVertices + 7);
    pbrta::MeshRecord m1 = archive_.meshes[1];
    m1.indices += 4;
    std::memcpy(&b[meshes_at_ + sizeof m1], &m1, sizeof m1);
    for (int threads : {1, 2})
      EXPECT_EQ(error_of(b, threads), prefix + "mesh 0: triangle 100000 has vertex index " +
                                          std::to_string(kBigVertices + 7) + " (" +
                                          std::to_string(kBigVertices) + " vertices)");
    // Without it, the layout error.
    set_u32(&b, index_at(0, 300000), 0);
    EXPECT_EQ(error_of(b, 2), prefix + "mesh 1: indices offset is not 16-byte aligned");
  }
}

TEST_F(MeshIndexCheck, ZstdArchiveLoadsTheSameArrays) {
  load_plain();
  compile_to(dir_ + "/z.pbrta", true);
  for (int threads : {1, 2}) {
    pbrta::SceneArchive z;
    std::string error;
    ASSERT_TRUE(z.load(dir_ + "/z.pbrta", threads, &error)) << error;
    ASSERT_EQ(z.meshes.size, 3u);
    const pbrta::MeshRecord& m = z.meshes[0];
    // In several frames.
    EXPECT_EQ(z.reader().entry(m.section).codec, uint32_t(pbrta::Codec::kZstd));
    EXPECT_GT(z.reader().section_size(m.section), uint64_t{1} << 20);
    for (uint32_t k = 0; k < 3; ++k) {
      const pbrta::MeshRecord& p = archive_.meshes[k];
      ASSERT_EQ(z.meshes[k].num_triangles, p.num_triangles);
      EXPECT_EQ(std::memcmp(z.indices(k), archive_.indices(k), 12 * uint64_t(p.num_triangles)), 0);
      EXPECT_EQ(std::memcmp(z.positions(k), archive_.positions(k), 12 * uint64_t(p.num_vertices)),
                0);
    }
  }
}

}  // namespace
}  // namespace pbrtc
