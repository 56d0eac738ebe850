// tests/compiler/archive_write_test.cpp — scenes compiled to archives and loaded back.
//
// Every shared entry scene that compiles is written as an archive (zstd and
// uncompressed), loaded through SceneArchive (the path pbrtrun and pbrtc
// --verify use), and compared with the SceneDesc it came from. Output must not
// depend on the thread count, and a damaged archive must give an error that
// names the file, never a crash.
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "compiled_scene.h"
#include "compiler/archive_builder.h"
#include "compiler/parser.h"
#include "compiler/scene_builder.h"
#include "format/archive_bytes.h"
#include "format/scene_archive.h"
#include "test_support.h"

namespace pbrtc {
namespace {

std::string write(const CompiledScene& c, const std::string& scene_path, const std::string& out,
                  bool compress, int threads) {
  ArchiveOptions opt;
  opt.compress = compress;
  opt.threads = threads;
  std::string error;
  EXPECT_TRUE(write_archive(c.scene, c.files, directory_of(scene_path), out, opt, nullptr, &error))
      << error;
  return testing_support::read_file(out);
}

// The archive holds what the SceneDesc holds.
void expect_matches(const SceneDesc& s, const pbrta::SceneArchive& a, const std::string& name) {
  SCOPED_TRACE(name);
  const pbrta::SceneRecord& r = a.scene();
  EXPECT_EQ(r.num_shapes, s.shapes.size());
  EXPECT_EQ(r.num_materials, s.materials.size());
  EXPECT_EQ(r.num_textures, s.textures.size());
  EXPECT_EQ(r.num_lights, s.lights.size());
  EXPECT_EQ(r.num_area_lights, s.area_lights.size());
  EXPECT_EQ(r.num_media, s.media.size());
  EXPECT_EQ(r.num_objects, s.objects.size());
  EXPECT_EQ(r.num_instances, s.instances.size());
  ASSERT_EQ(r.num_meshes, s.meshes.size());
  EXPECT_EQ(a.type_name(r.camera), s.camera.params.type_name());
  EXPECT_EQ(a.get_int(r.film, "xresolution"), s.film.get_int("xresolution"));
  EXPECT_EQ(a.type_name(r.integrator), s.integrator.type_name());
  for (uint32_t i = 0; i < r.num_shapes; ++i) {
    const ShapeDesc& sh = s.shapes[i];
    const pbrta::ShapeRecord& rec = a.shapes[i];
    EXPECT_EQ(a.type_name(rec.entity), sh.params.type_name());
    EXPECT_EQ(rec.material, uint32_t(sh.material));
    EXPECT_EQ(rec.mesh, sh.mesh < 0 ? pbrta::kNoIndex : uint32_t(sh.mesh));
    // The transform survives bit for bit (double in both).
    const AnimatedTransform& t = s.transforms[size_t(sh.transform)];
    EXPECT_EQ(0, std::memcmp(a.transforms[rec.transform].start, t.start.m.data(), 128));
  }
  for (uint32_t m = 0; m < r.num_meshes; ++m) {
    const TriangleMesh& mesh = s.meshes[m];
    ASSERT_EQ(a.meshes[m].num_vertices, mesh.num_vertices());
    ASSERT_EQ(a.meshes[m].num_triangles, mesh.num_triangles());
    EXPECT_EQ(0, std::memcmp(a.positions(m), mesh.P.data(), mesh.P.size() * 4));
    EXPECT_EQ(0, std::memcmp(a.indices(m), mesh.indices.data(), mesh.indices.size() * 4));
    EXPECT_EQ(a.normals(m) != nullptr, !mesh.N.empty());
    if (!mesh.N.empty()) {
      EXPECT_EQ(0, std::memcmp(a.normals(m), mesh.N.data(), mesh.N.size() * 4));
    }
    EXPECT_EQ(a.uvs(m) != nullptr, !mesh.uv.empty());
  }
  // Every entity's given values come back with the same numbers.
  auto same_entity = [&](uint32_t e, const Entity& d) {
    const pbrta::EntityRecord& er = a.entities[e];
    ASSERT_EQ(er.num_values, d.values.size());
    for (uint32_t p = 0; p < er.num_values; ++p) {
      const pbrta::ValueRecord& v = a.values[er.first_value + p];
      EXPECT_EQ(bool(v.flags & pbrta::kValueGiven), d.values[p].given);
      EXPECT_EQ(v.count, d.values[p].count);
      EXPECT_EQ(v.texture,
                d.values[p].texture < 0 ? pbrta::kNoIndex : uint32_t(d.values[p].texture));
      pbrta::Kind k = d.spec().params[p].kind;
      if (pbrta::kind_store(k) == pbrta::KindStore::kFloat && d.values[p].count) {
        EXPECT_EQ(0, std::memcmp(a.floats(v), d.floats.data() + d.values[p].offset,
                                 d.values[p].count * pbrta::kind_width(k) * 4))
            << d.spec().params[p].name;
      }
    }
  };
  for (uint32_t i = 0; i < r.num_materials; ++i)
    same_entity(a.materials[i].entity, s.materials[i].params);
  for (uint32_t i = 0; i < r.num_shapes; ++i) same_entity(a.shapes[i].entity, s.shapes[i].params);
  for (uint32_t i = 0; i < r.num_lights; ++i) same_entity(a.lights[i].entity, s.lights[i].params);
  same_entity(r.camera, s.camera.params);
  same_entity(r.film, s.film);
  same_entity(r.sampler, s.sampler);
}

TEST(ArchiveWrite, EverySharedSceneRoundTripsThroughTheArchive) {
  std::string dir = testing_support::scratch_dir("archive_write_all");
  int compiled = 0;
  for (const std::string& path : testing_support::shared_entry_scenes()) {
    CompiledScene c;
    compile_scene(path, &c);
    if (!c.ok) continue;  // the scenes with a missing corpus file (see shared_scenes_test)
    ++compiled;
    for (bool compress : {true, false}) {
      std::string out =
          dir + "/scene" + std::to_string(compiled) + (compress ? ".z" : ".raw") + ".pbrta";
      write(c, path, out, compress, 0);
      pbrta::SceneArchive a;
      std::string error;
      ASSERT_TRUE(a.load(out, 2, &error)) << path << ": " << error;
      expect_matches(c.scene, a, path);
      if (!compress) {  // sections are used in place from the mapping
        for (uint32_t i = 0; i < a.reader().section_count(); ++i) {
          EXPECT_TRUE(a.reader().in_place(i)) << path << " section " << i;
        }
      }
    }
  }
  EXPECT_GE(compiled, 60);
}

TEST(ArchiveWrite, BytesDoNotDependOnThreadsOrRuns) {
  std::string dir = testing_support::scratch_dir("archive_determinism");
  for (const char* rel : {"/scenes/v3-killeroo-simple/killeroo-simple.pbrt",
                          "/scenes/rs-teapot-area-light/teapot-area-light.pbrt",
                          "/scenes/hm-instances/pbrt-v3-rs/scenes/objects/instances.pbrt"}) {
    std::string path = testing_support::shared_dir() + rel;
    CompiledScene a, b;
    compile_scene(path, &a);
    compile_scene(path, &b);  // a second, independent compile
    ASSERT_TRUE(a.ok && b.ok) << path;
    std::string one = write(a, path, dir + "/one.pbrta", true, 1);
    std::string two = write(b, path, dir + "/two.pbrta", true, 2);
    EXPECT_FALSE(one.empty());
    EXPECT_TRUE(one == two) << path << ": archive bytes differ between runs/thread counts";
    // No absolute path leaks into the archive.
    EXPECT_EQ(write(a, path, dir + "/one.pbrta", false, 1).find("/work/"), std::string::npos)
        << path;
  }
}

// Issue 4's determinism on every compilable shared scene: two independent compiles, written
// with 1 and with 2 threads, give the same bytes, and the uncompressed archive holds no absolute
// path (the corpus's directory nowhere, the provenance included).
TEST(ArchiveWrite, EveryCompilableSharedSceneIsDeterministic) {
  const std::string dir = testing_support::scratch_dir("archive_determinism_all");
  const std::string shared =
      std::filesystem::weakly_canonical(testing_support::shared_dir()).string();
  int compiled = 0;
  std::vector<std::string> differ;
  for (const std::string& path : testing_support::shared_entry_scenes()) {
    CompiledScene a, b;
    compile_scene(path, &a);
    if (!a.ok) continue;  // the scenes with a missing corpus file (see shared_scenes_test)
    compile_scene(path, &b);
    ASSERT_TRUE(b.ok) << path;
    ++compiled;
    const std::string one = write(a, path, dir + "/one.pbrta", true, 1);
    const std::string two = write(b, path, dir + "/two.pbrta", true, 2);
    if (one.empty() || one != two) differ.push_back(path);
    EXPECT_EQ(write(a, path, dir + "/raw.pbrta", false, 2).find(shared), std::string::npos)
        << path << ": an absolute path in the archive";
  }
  std::string list;
  for (const std::string& p : differ) list += "\n  " + p;
  EXPECT_TRUE(differ.empty()) << "archive bytes differ between compiles/thread counts:" << list;
  EXPECT_GE(compiled, 60);
}

TEST(ArchiveWrite, FailedWriteLeavesNoFile) {
  std::string dir = testing_support::scratch_dir("archive_failed_write");
  CompiledScene c;
  compile_scene(PBRTC_SOURCE_DIR "/tools/default-scene/scene.pbrt", &c);
  ASSERT_TRUE(c.ok);
  std::string error;
  ArchiveOptions opt;
  EXPECT_FALSE(
      write_archive(c.scene, c.files, "", dir + "/missing-dir/x.pbrta", opt, nullptr, &error));
  EXPECT_NE(error.find("missing-dir/x.pbrta"), std::string::npos) << error;
  EXPECT_TRUE(testing_support::read_file(dir + "/missing-dir/x.pbrta").empty());
}

// A real scene's archive, damaged: every byte flipped in turn, a few thousand bytes changed at
// random, and truncation at every section boundary, for each codec (zstd, none, and zstd with
// Draco meshes). No change may pass: checksums cover the header, table and sections, and the
// reader checks that the padding between them is zero. Every error names the file.
TEST(ArchiveWrite, DamagedSceneArchivesFailCleanly) {
  std::string dir = testing_support::scratch_dir("archive_damage");
  std::string path = testing_support::shared_dir() + "/scenes/rs-cornell-box/cornell_box.pbrt";
  CompiledScene c;
  compile_scene(path, &c);
  ASSERT_TRUE(c.ok);
  const std::string file = dir + "/bad.pbrta";
  enum Variant { kZstd, kNone, kDraco };
  for (Variant v : {kZstd, kNone, kDraco}) {
    SCOPED_TRACE(v == kZstd ? "zstd" : v == kNone ? "none" : "draco");
    ArchiveOptions opt;
    opt.compress = v != kNone;
    opt.draco_bits = v == kDraco ? 14 : 0;
    opt.draco_min_triangles = 1;  // cornell's boxes are small
    opt.threads = 1;
    std::string error;
    ASSERT_TRUE(write_archive(c.scene, c.files, directory_of(path), dir + "/good.pbrta", opt,
                              nullptr, &error))
        << error;
    const std::string good = testing_support::read_file(dir + "/good.pbrta");
    pbrta::Header h;
    std::memcpy(&h, good.data(), sizeof h);
    if (v == kDraco) {
      bool has_draco = false;
      for (uint32_t i = 0; i < h.section_count; ++i)
        has_draco |= pbrta::test_bytes::entry_of(good, i).codec == uint32_t(pbrta::Codec::kDraco);
      ASSERT_TRUE(has_draco) << "the Draco variant holds no Draco section";
    }
    // Loads `bytes` from memory (1 thread) or, when via_file, from a file (2 threads); the
    // error, or "" if it loaded.
    auto load = [&](const std::string& bytes, bool via_file) {
      pbrta::SceneArchive a;
      std::string e;
      if (via_file) {
        testing_support::write_file(file, bytes);
        if (a.load(file, 2, &e)) return std::string();
      } else if (a.load_memory(bytes, file, 1, &e)) {
        return std::string();
      }
      return e.empty() ? std::string("(empty error)") : e;
    };
    ASSERT_EQ(load(good, true), "");
    int changes = 0;
    auto expect_refused = [&](const std::string& bytes, const std::string& what, bool via_file) {
      ++changes;
      const std::string e = load(bytes, via_file);
      EXPECT_NE(e, "") << what << " was accepted";
      EXPECT_EQ(e.compare(0, file.size() + 2, file + ": "), 0) << what << ": " << e;
    };
    // A one-bit flip at every offset reaches every field the checksums and the padding rule
    // cover. Every 16th goes through a file as pbrtrun opens one (read whole: it is under 64 KiB;
    // the mapped path has its own tests in format/).
    for (size_t k = 0; k < good.size(); ++k) {
      std::string bad = good;
      bad[k] = char(bad[k] ^ (1u << (k % 8)));
      expect_refused(bad, "a flip at byte " + std::to_string(k), k % 16 == 0);
    }
    // Whole bytes changed at random, and three at a time: changes a single flip cannot make.
    std::mt19937 rng(7);
    for (int t = 0; t < 1500; ++t) {
      std::string bad = good;
      const int n = t % 2 ? 3 : 1;
      for (int j = 0; j < n; ++j) {
        const size_t at = rng() % bad.size();
        bad[at] = char(bad[at] ^ (1 + rng() % 255));
      }
      expect_refused(bad, "random change " + std::to_string(t), false);
    }
    // Truncation at every section boundary (each section's start, end and padded end), inside
    // the header and table, and one byte short of the whole.
    std::vector<uint64_t> cuts = {
        0, 1, 63, 64, 64 + 48 * uint64_t{h.section_count} - 1, good.size() - 1};
    for (uint32_t i = 0; i < h.section_count; ++i) {
      const pbrta::SectionEntry e = pbrta::test_bytes::entry_of(good, i);
      for (uint64_t cut : {e.offset, e.offset + 1, e.offset + e.stored_size,
                           (e.offset + e.stored_size + 15) / 16 * 16})
        cuts.push_back(cut);
    }
    for (uint64_t cut : cuts) {
      if (cut >= good.size()) continue;
      const std::string what = "a cut at byte " + std::to_string(cut);
      expect_refused(good.substr(0, cut), what, true);
      const std::string e = load(good.substr(0, cut), false);
      EXPECT_NE(e.find("truncated"), std::string::npos) << what << ": " << e;
    }
    EXPECT_GT(changes, 3000);
  }
}

// Seeds for the scene archive fuzzer (tests/fuzz/scene_archive_fuzz.cpp; CTest's
// fuzz.scene_archive runs this test first as a fixture): small shared scenes that between them
// hold every record kind, uncompressed (so a mutation lands in a record, not in zstd's bytes),
// compressed, and with a Draco mesh. Each fits the fuzzer's 64 KiB inputs whole.
TEST(ArchiveWrite, WritesSceneFuzzSeeds) {
  const std::string dir = std::string(PBRTC_BINARY_DIR) + "/fuzz-seeds/scene";
  std::filesystem::create_directories(dir);
  const std::string scenes = testing_support::shared_dir() + "/scenes/";
  const char* const kScenes[] = {
      "rs-cornell-box/cornell_box.pbrt",
      "hm-shapes/pbrt-v3-rs/scenes/shapes/all-shapes.pbrt",
      "hm-shapes/pbrt-v3-rs/scenes/shapes/triangles-alpha-mask.pbrt",
      "hm-instances/pbrt-v3-rs/scenes/objects/instances.pbrt",
      "hm-textures/pbrt-v3-rs/scenes/textures/2d-checkerboard.pbrt",
      "hm-cameras/pbrt-v3-rs/scenes/cameras/environment.pbrt",
      "hm-cameras/pbrt-v3-rs/scenes/cameras/realistic.pbrt",
      "hm-lights/pbrt-v3-rs/scenes/lights/spot.pbrt",
      "rs-procedural-textures/marble.pbrt",
      "rs-veach-mis/veach-mis/mis.pbrt",
      "rs-nurbs/nurbs_3x3.pbrt",
  };
  int n = 0;
  for (const char* name : kScenes) {
    CompiledScene c;
    compile_scene(scenes + name, &c);
    ASSERT_TRUE(c.ok) << name;
    for (int variant = 0; variant < 3; ++variant) {
      ArchiveOptions opt;
      opt.compress = variant > 0;
      opt.draco_bits = variant == 2 ? 14 : 0;
      opt.threads = 1;
      const std::string out = dir + "/seed" + std::to_string(n++) + ".pbrta";
      std::string error;
      ASSERT_TRUE(write_archive(c.scene, c.files, directory_of(c.path), out, opt, nullptr, &error))
          << error;
      EXPECT_LE(testing_support::read_file(out).size(), 65536u) << name;
      pbrta::SceneArchive a;
      EXPECT_TRUE(a.load(out, 1, &error)) << error;  // a seed the fuzzer can mutate from
    }
  }
}

}  // namespace
}  // namespace pbrtc
