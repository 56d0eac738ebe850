// tests/compiler/draco_archive_test.cpp — pbrtc's lossy mesh compression (ArchiveOptions::
// draco_bits) on the shared corpus's real meshes: at 11, 14 and 16 bits the archive loads and
// verifies through SceneArchive, every mesh keeps its triangle count, every decoded vertex lies
// within the bound the bits imply of an original vertex, and the archive is smaller than the
// zstd-only one; the bytes do not depend on the thread count; sequential encoding keeps the
// order; meshes Draco cannot carry stay lossless; and a plymesh may name a .drc file.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "compiled_scene.h"
#include "compiler/archive_builder.h"
#include "compiler/parser.h"
#include "compiler/scene_builder.h"
#include "format/archive_bytes.h"
#include "format/archive_names.h"
#include "format/archive_reader.h"
#include "format/archive_writer.h"
#include "format/draco_codec.h"
#include "format/draco_forgery.h"
#include "compiler/ply_reader.h"
#include "format/scene_archive.h"
#include "test_support.h"

namespace pbrtc {
namespace {

// Writes c with these options; returns the file's bytes (empty on failure).
std::string write(const CompiledScene& c, const std::string& out, ArchiveOptions opt,
                  ArchiveStats* stats = nullptr) {
  std::string error;
  EXPECT_TRUE(write_archive(c.scene, c.files, directory_of(c.path), out, opt, stats, &error))
      << error;
  return testing_support::read_file(out);
}

bool is_draco(const pbrta::SceneArchive& a, uint32_t m) {
  return a.reader().entry(a.meshes[m].section).codec == uint32_t(pbrta::Codec::kDraco);
}

// Checks the archive's meshes against the scene's: Draco meshes within the bound, the others
// bit for bit. Returns how many were Draco's.
int expect_meshes_match(const SceneDesc& s, const pbrta::SceneArchive& a, int bits,
                        bool sequential) {
  int draco = 0;
  EXPECT_EQ(a.meshes.size, s.meshes.size());
  for (uint32_t m = 0; m < a.meshes.size && m < s.meshes.size(); ++m) {
    SCOPED_TRACE("mesh " + std::to_string(m));
    const TriangleMesh& orig = s.meshes[m];
    const pbrta::MeshArrays got = a.mesh_arrays(m);
    EXPECT_EQ(got.num_triangles, orig.num_triangles());
    EXPECT_EQ(got.normals != nullptr, !orig.N.empty());
    EXPECT_EQ(got.uv != nullptr, !orig.uv.empty());
    if (!is_draco(a, m)) {
      EXPECT_EQ(got.num_vertices, orig.num_vertices());
      if (got.num_vertices != orig.num_vertices()) continue;
      EXPECT_EQ(0, std::memcmp(got.positions, orig.P.data(), orig.P.size() * 4));
      EXPECT_EQ(0, std::memcmp(got.indices, orig.indices.data(), orig.indices.size() * 4));
      continue;
    }
    ++draco;
    EXPECT_GE(orig.num_triangles(), 64u);
    const double bound = pbrta::draco_position_bound(orig.P.data(), orig.num_vertices(), bits);
    const double slack = pbrta::draco_position_slack(orig.P.data(), orig.num_vertices());
    const bool same_order = sequential && got.num_vertices == orig.num_vertices();
    EXPECT_LE(pbrta::draco_max_displacement(arrays_of(orig), got, bound, same_order),
              bound + slack);
    if (sequential) {
      EXPECT_EQ(got.num_vertices, orig.num_vertices());
      EXPECT_EQ(0, std::memcmp(got.indices, orig.indices.data(), orig.indices.size() * 4));
    }
  }
  return draco;
}

struct SharedMesh {
  const char* scene;
  int meshes_with_draco;  // meshes of 64+ triangles
};

class DracoSharedScenes : public ::testing::TestWithParam<SharedMesh> {};

TEST_P(DracoSharedScenes, CompressWithinTheBound) {
  const std::string scene = testing_support::shared_dir() + "/scenes/" + GetParam().scene;
  CompiledScene c;
  compile_scene(scene, &c);
  ASSERT_TRUE(c.ok) << (c.errors.empty() ? "" : c.errors[0]);
  const std::string dir = testing_support::scratch_dir("draco_shared");
  ArchiveOptions opt;
  opt.threads = 2;
  const uint64_t zstd_size = write(c, dir + "/zstd.pbrta", opt).size();
  ASSERT_GT(zstd_size, 0u);
  for (int bits : {11, 14, 16}) {
    SCOPED_TRACE(std::to_string(bits) + " bits");
    opt.draco_bits = bits;
    ArchiveStats stats;
    const std::string path = dir + "/draco" + std::to_string(bits) + ".pbrta";
    const std::string bytes = write(c, path, opt, &stats);
    EXPECT_LT(bytes.size(), zstd_size * 2 / 3);
    ASSERT_EQ(stats.draco.size(), size_t(GetParam().meshes_with_draco));
    for (const DracoMeshStats& d : stats.draco) {
      EXPECT_LE(d.displacement, d.bound + d.slack) << "mesh " << d.mesh;
      EXPECT_LT(d.stored_bytes, d.raw_bytes / 5);
    }
    pbrta::SceneArchive a;
    std::string error;
    ASSERT_TRUE(a.load(path, 2, &error)) << error;
    EXPECT_EQ(expect_meshes_match(c.scene, a, bits, false), GetParam().meshes_with_draco);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Shared, DracoSharedScenes,
    ::testing::Values(SharedMesh{"v3-caustic-glass-sppm/f16-11a.pbrt", 1},
                      SharedMesh{"v3-killeroo-simple/killeroo-simple.pbrt", 2}),
    [](const auto& info) { return std::string(info.param.scene).substr(3, 7); });

TEST(DracoArchive, SameBytesWhateverTheThreadCount) {
  CompiledScene c;
  compile_scene(testing_support::shared_dir() + "/scenes/v3-killeroo-simple/killeroo-simple.pbrt",
                &c);
  ASSERT_TRUE(c.ok);
  const std::string dir = testing_support::scratch_dir("draco_threads");
  ArchiveOptions opt;
  opt.draco_bits = 12;
  opt.threads = 1;
  const std::string one = write(c, dir + "/1.pbrta", opt);
  opt.threads = 2;
  const std::string two = write(c, dir + "/2.pbrta", opt);
  ASSERT_FALSE(one.empty());
  EXPECT_TRUE(one == two);
  // And decoding gives the same arrays with one thread or several.
  pbrta::SceneArchive a1, a2;
  std::string error;
  ASSERT_TRUE(a1.load(dir + "/1.pbrta", 1, &error)) << error;
  ASSERT_TRUE(a2.load(dir + "/1.pbrta", 2, &error)) << error;
  for (uint32_t i = 0; i < a1.reader().section_count(); ++i)
    EXPECT_EQ(0, std::memcmp(a1.reader().section_data(i), a2.reader().section_data(i),
                             a1.reader().section_size(i)));
}

// Draco's own work on a forged stream is not bounded (format/draco_codec.h), so the reader
// decodes Draco sections last, and not at all when another section has failed: a fault
// elsewhere is reported even when it lies after a Draco section that would fail too.
TEST(DracoArchive, OtherFaultsAreFoundBeforeDracoRuns) {
  CompiledScene c;
  compile_scene(testing_support::shared_dir() + "/scenes/v3-killeroo-simple/killeroo-simple.pbrt",
                &c);
  ASSERT_TRUE(c.ok);
  const std::string dir = testing_support::scratch_dir("draco_last");
  ArchiveOptions opt;
  opt.draco_bits = 12;
  const std::string good = write(c, dir + "/good.pbrta", opt);
  ASSERT_FALSE(good.empty());
  pbrta::SceneArchive a;
  std::string error;
  ASSERT_TRUE(a.load(dir + "/good.pbrta", 2, &error)) << error;
  uint32_t draco = pbrta::kNoIndex, later = pbrta::kNoIndex;
  for (uint32_t i = 0; i < a.reader().section_count(); ++i) {
    const uint32_t codec = a.reader().entry(i).codec;
    if (codec == uint32_t(pbrta::Codec::kDraco) && draco == pbrta::kNoIndex) draco = i;
    if (codec != uint32_t(pbrta::Codec::kDraco) && draco != pbrta::kNoIndex) later = i;
  }
  ASSERT_NE(later, pbrta::kNoIndex) << "no section after the first Draco one";
  const std::string prefix = dir + "/bad.pbrta: section '";
  auto label = [&](uint32_t i) {
    return std::string(pbrta::section_kind_name(pbrta::SectionKind(a.reader().entry(i).kind))) +
           "' (#" + std::to_string(i) + "): ";
  };
  // The Draco stream's magic broken, its checksum made right: Draco is reached, and refuses it.
  std::string bytes = good;
  const pbrta::SectionEntry d = pbrta::test_bytes::entry_of(bytes, draco);
  bytes[d.offset] = 'X';
  pbrta::test_bytes::reseal(&bytes, draco, d.stored_size);
  EXPECT_EQ(pbrta::test_bytes::load_error(dir + "/bad.pbrta", bytes),
            prefix + label(draco) + "draco: not a Draco stream");
  // A later section damaged too (in its frame index: the section's checksum): it is the one
  // reported, Draco having never run.
  const pbrta::SectionEntry l = pbrta::test_bytes::entry_of(bytes, later);
  ASSERT_EQ(l.codec, uint32_t(pbrta::Codec::kZstd));
  bytes[l.offset + 24] ^= 0x10;
  EXPECT_EQ(pbrta::test_bytes::load_error(dir + "/bad.pbrta", bytes),
            prefix + label(later) + "checksum mismatch");
}

TEST(DracoArchive, SequentialKeepsTheOrder) {
  CompiledScene c;
  compile_scene(testing_support::shared_dir() + "/scenes/v3-caustic-glass-sppm/f16-11a.pbrt", &c);
  ASSERT_TRUE(c.ok);
  const std::string path = testing_support::scratch_dir("draco_sequential") + "/s.pbrta";
  ArchiveOptions opt;
  opt.draco_bits = 14;
  opt.draco_sequential = true;
  ArchiveStats stats;
  write(c, path, opt, &stats);
  ASSERT_EQ(stats.draco.size(), 1u);
  pbrta::SceneArchive a;
  std::string error;
  ASSERT_TRUE(a.load(path, 2, &error)) << error;
  EXPECT_EQ(expect_meshes_match(c.scene, a, 14, true), 1);
}

// A trianglemesh grid of n x n quads, with tangents if asked, and a degenerate triangle (one
// naming a vertex twice) at the end if asked.
std::string grid_mesh(int n, bool tangents, bool degenerate = false) {
  std::string p = "\"point P\" [", idx = "\"integer indices\" [", s = "\"vector S\" [";
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) {
      p += " " + std::to_string(x) + " " + std::to_string(y) + " " + std::to_string((x * y) % 3);
      s += " 1 0 0";
    }
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const int a = y * (n + 1) + x, b = a + 1, c = a + n + 2, d = a + n + 1;
      for (int v : {a, b, c, a, c, d}) idx += " " + std::to_string(v);
    }
  if (degenerate) idx += " 0 1 1";
  return "Shape \"trianglemesh\" " + p + " ] " + idx + " ]" + (tangents ? " " + s + " ]" : "") +
         "\n";
}

std::string scene_text(const std::string& shapes) {
  return "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
         "LightSource \"point\"\n" +
         shapes + "WorldEnd\n";
}

TEST(DracoArchive, WhatDracoCannotCarryStaysLossless) {
  const std::string dir = testing_support::scratch_dir("draco_lossless");
  const std::string path = testing_support::write_file(
      dir + "/s.pbrt", scene_text(grid_mesh(8, true) + grid_mesh(5, false) + grid_mesh(6, false) +
                                  grid_mesh(7, false, true)));
  CompiledScene c;
  compile_scene(path, &c);
  ASSERT_TRUE(c.ok) << (c.errors.empty() ? "" : c.errors[0]);
  ASSERT_EQ(c.scene.meshes.size(), 4u);
  ArchiveOptions opt;
  opt.draco_bits = 11;
  ArchiveStats stats;
  write(c, dir + "/s.pbrta", opt, &stats);
  pbrta::SceneArchive a;
  std::string error;
  ASSERT_TRUE(a.load(dir + "/s.pbrta", 2, &error)) << error;
  EXPECT_FALSE(is_draco(a, 0));  // 128 triangles, but tangents
  EXPECT_FALSE(is_draco(a, 1));  // 50 triangles
  EXPECT_TRUE(is_draco(a, 2));   // 72 triangles
  EXPECT_FALSE(is_draco(a, 3));  // edgebreaker would drop its degenerate triangle
  EXPECT_EQ(stats.draco_kept_lossless, 1u);
  ASSERT_EQ(stats.draco.size(), 1u);
  EXPECT_EQ(stats.draco[0].mesh, 2u);
  EXPECT_NE(a.tangents(0), nullptr);
  EXPECT_EQ(expect_meshes_match(c.scene, a, 11, false), 1);
}

// Rewrites the archive at `from` to `to` with every section but the Draco ones uncompressed,
// after edit() has seen (and may have changed) each section's raw bytes and count.
using SectionEdit = std::function<void(pbrta::SectionKind, std::vector<uint8_t>*, uint32_t*)>;
void rewrite_archive(const std::string& from, const std::string& to, const SectionEdit& edit) {
  pbrta::ArchiveReader r;
  std::string error;
  ASSERT_TRUE(r.open(from, &error) && r.load_sections(1, &error)) << error;
  const std::string file = testing_support::read_file(from);
  pbrta::ArchiveWriter w;
  for (uint32_t i = 0; i < r.section_count(); ++i) {
    const pbrta::SectionEntry& e = r.entry(i);
    std::vector<uint8_t> raw(r.section_data(i), r.section_data(i) + e.raw_size);
    uint32_t count = e.count;
    edit(pbrta::SectionKind(e.kind), &raw, &count);
    if (e.codec == uint32_t(pbrta::Codec::kDraco)) {
      std::vector<uint8_t> stored(file.begin() + std::ptrdiff_t(e.offset),
                                  file.begin() + std::ptrdiff_t(e.offset + e.stored_size));
      w.add_encoded_section(pbrta::SectionKind(e.kind), std::move(raw), std::move(stored), count,
                            pbrta::Codec::kDraco);
    } else {
      w.add_section(pbrta::SectionKind(e.kind), std::move(raw), count, pbrta::Codec::kRaw);
    }
  }
  ASSERT_TRUE(w.write(to, r.header().effects, 3, 1, &error)) << error;
}

// ARCHIVE.md section 5: a Draco section's mesh record carries the counts its stream decodes to,
// and no other record names that section. Counts that lay out to the same bytes (4 more
// vertices, 4 fewer triangles, positions only) pass every layout check and are refused all the
// same; so is a second record naming the section.
TEST(DracoArchive, TheRecordCarriesTheStreamsCounts) {
  const std::string dir = testing_support::scratch_dir("draco_counts");
  const std::string path =
      testing_support::write_file(dir + "/s.pbrt", scene_text(grid_mesh(8, false)));
  CompiledScene c;
  compile_scene(path, &c);
  ASSERT_TRUE(c.ok) << (c.errors.empty() ? "" : c.errors[0]);
  ArchiveOptions opt;
  opt.draco_bits = 12;
  write(c, dir + "/good.pbrta", opt);
  pbrta::SceneArchive good;
  std::string error;
  ASSERT_TRUE(good.load(dir + "/good.pbrta", 2, &error)) << error;
  ASSERT_EQ(good.meshes.size, 1u);
  ASSERT_TRUE(is_draco(good, 0));
  const pbrta::MeshRecord m = good.meshes[0];
  ASSERT_EQ(good.reader().decoded_vertices(m.section), m.num_vertices);
  ASSERT_EQ(good.reader().decoded_triangles(m.section), m.num_triangles);
  const std::string prefix = dir + "/bad.pbrta: section 'meshes' (#";

  // The rewrite alone loads: only the edits below are at fault.
  rewrite_archive(dir + "/good.pbrta", dir + "/same.pbrta",
                  [](pbrta::SectionKind, std::vector<uint8_t>*, uint32_t*) {});
  pbrta::SceneArchive same;
  EXPECT_TRUE(same.load(dir + "/same.pbrta", 2, &error)) << error;

  pbrta::MeshRecord forged = m;
  forged.num_vertices += 4;
  forged.num_triangles -= 4;
  ASSERT_EQ(pbrta::single_mesh_layout(&forged), good.reader().section_size(m.section));
  rewrite_archive(dir + "/good.pbrta", dir + "/bad.pbrta",
                  [&](pbrta::SectionKind kind, std::vector<uint8_t>* raw, uint32_t*) {
                    if (kind == pbrta::SectionKind::kMeshes)
                      std::memcpy(raw->data(), &forged, sizeof forged);
                  });
  for (int threads : {1, 2}) {
    pbrta::SceneArchive bad;
    EXPECT_FALSE(bad.load(dir + "/bad.pbrta", threads, &error));
    EXPECT_NE(
        error.find("mesh 0: " + std::to_string(forged.num_vertices) + " vertices and " +
                   std::to_string(forged.num_triangles) + " triangles, but its draco " +
                   "section (#" + std::to_string(m.section) + ") decodes to " +
                   std::to_string(m.num_vertices) + " and " + std::to_string(m.num_triangles)),
        std::string::npos)
        << error;
    EXPECT_EQ(error.rfind(prefix, 0), 0u) << error;
  }

  // A second record naming the same section (the counts of meshes raised to match).
  rewrite_archive(dir + "/good.pbrta", dir + "/bad.pbrta",
                  [&](pbrta::SectionKind kind, std::vector<uint8_t>* raw, uint32_t* count) {
                    if (kind == pbrta::SectionKind::kMeshes) {
                      raw->resize(2 * sizeof m);
                      std::memcpy(raw->data() + sizeof m, &m, sizeof m);
                      *count = 2;
                    } else if (kind == pbrta::SectionKind::kScene) {
                      pbrta::SceneRecord sr;
                      std::memcpy(&sr, raw->data(), sizeof sr);
                      sr.num_meshes = 2;
                      std::memcpy(raw->data(), &sr, sizeof sr);
                    }
                  });
  pbrta::SceneArchive twice;
  EXPECT_FALSE(twice.load(dir + "/bad.pbrta", 2, &error));
  EXPECT_NE(error.find("mesh 1: its draco section (#" + std::to_string(m.section) +
                       ") holds mesh 0 already"),
            std::string::npos)
      << error;
}

TEST(DracoArchive, PlymeshReadsDrcFiles) {
  // The glass mesh, encoded with the same wrapper into a .DRC file (the extension in any case).
  pbrtc::PlyMesh ply;
  pbrtc::PlyError ply_error;
  ASSERT_TRUE(pbrtc::read_ply(
      testing_support::shared_dir() + "/scenes/v3-caustic-glass-sppm/geometry/mesh_00001.ply", &ply,
      &ply_error))
      << ply_error.message;
  pbrta::MeshArrays in;
  in.positions = ply.positions.data();
  in.normals = ply.normals.empty() ? nullptr : ply.normals.data();
  in.indices = ply.indices.data();
  in.num_vertices = ply.num_vertices();
  in.num_triangles = ply.num_triangles();
  pbrta::DracoOptions o;
  o.position_bits = 16;
  std::vector<uint8_t> stream;
  std::string error;
  ASSERT_TRUE(pbrta::draco_encode(in, o, &stream, &error)) << error;
  const std::string dir = testing_support::scratch_dir("draco_drc");
  testing_support::write_file(dir + "/glass.DRC", std::string(stream.begin(), stream.end()));
  testing_support::write_file(dir + "/junk.drc", "DRACO but not really");
  const std::string path = testing_support::write_file(
      dir + "/s.pbrt", scene_text("Shape \"plymesh\" \"string filename\" \"glass.DRC\"\n"));
  CompiledScene c;
  compile_scene(path, &c);
  ASSERT_TRUE(c.ok) << (c.errors.empty() ? "" : c.errors[0]);
  ASSERT_EQ(c.scene.meshes.size(), 1u);
  pbrta::DecodedMesh d;
  ASSERT_TRUE(pbrta::draco_decode(stream.data(), stream.size(), &d, &error)) << error;
  const TriangleMesh& m = c.scene.meshes[0];
  EXPECT_EQ(m.num_triangles(), in.num_triangles);
  EXPECT_EQ(m.P, d.positions);
  EXPECT_EQ(m.N, d.normals);
  EXPECT_EQ(m.indices, d.indices);
  const double bound = pbrta::draco_position_bound(in.positions, in.num_vertices, 16);
  EXPECT_LE(pbrta::draco_max_displacement(in, arrays_of(m), bound, false),
            bound + pbrta::draco_position_slack(in.positions, in.num_vertices));
  // It compiles into an archive like any mesh, with or without Draco again.
  ArchiveOptions opt;
  write(c, dir + "/s.pbrta", opt);
  pbrta::SceneArchive a;
  ASSERT_TRUE(a.load(dir + "/s.pbrta", 2, &error)) << error;
  EXPECT_EQ(a.meshes[0].num_triangles, in.num_triangles);

  // The first error of compiling a scene whose plymesh names `file` in dir.
  auto first_error = [&](const std::string& file) {
    const std::string scene = testing_support::write_file(
        dir + "/" + file + ".pbrt",
        scene_text("Shape \"plymesh\" \"string filename\" \"" + file + "\"\n"));
    CompiledScene b;
    compile_scene(scene, &b);
    EXPECT_FALSE(b.ok);
    return b.errors.empty() ? std::string("(no error)") : b.errors[0];
  };
  EXPECT_EQ(first_error("junk.drc"), "cannot read Draco file \"" + dir +
                                         "/junk.drc\": draco: bitstream "
                                         "version 32.98; this reader takes 2.2");

  // A forged file (format/draco_forgery.h) costs the compile the budget Draco runs under, not the
  // seconds Draco would spend on it, and is an error like any unreadable file.
  const pbrta::test_forgery::UvGrid g = pbrta::test_forgery::uv_grid(8);
  ASSERT_TRUE(pbrta::draco_encode(g.view(), pbrta::DracoOptions{}, &stream, &error)) << error;
  ASSERT_TRUE(
      pbrta::test_forgery::forge_orientation_count(stream.data(), stream.size(), g.num_vertices()));
  testing_support::write_file(dir + "/forged.drc", std::string(stream.begin(), stream.end()));
  EXPECT_EQ(first_error("forged.drc"), "cannot read Draco file \"" + dir +
                                           "/forged.drc\": draco: decoding ran past its budget "
                                           "of 1 s of CPU time (a forged or damaged stream)");
}

}  // namespace
}  // namespace pbrtc
