// tests/pbrt/pbrtc_command_test.cpp — the pbrtc command, run as users run it.
//
// The built pbrtc (and pbrtrun, for damaged archives) on a small scene written into a scratch
// directory: the default archive name, --verify and --info exit codes and messages, a damaged
// or truncated archive named with its section and refused by both programs without a crash or
// an output file, a failed compile that leaves the previous archive in place, --dump that
// compiles back, a forged Draco stream refused within the reader's budget, and the usage errors
// (exit 2).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "command_runner.h"
#include "format/archive_bytes.h"
#include "format/archive_names.h"
#include "format/archive_reader.h"
#include "format/draco_forgery.h"
#include "format/scene_archive.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using testing_support::find_in_order;
using testing_support::kBin;
using testing_support::Outcome;
using testing_support::read_file;
using testing_support::run_in;
using testing_support::run_on_terminal;
using testing_support::scratch_dir;
using testing_support::write_file;

const char* kScene = R"(LookAt 0 0 -4  0 0 0  0 1 0
Camera "perspective" "float fov" 45
Film "image" "integer xresolution" 16 "integer yresolution" 16 "string filename" "box.exr"
Sampler "halton" "integer pixelsamples" 2
WorldBegin
LightSource "point" "point from" [0 2 -3] "rgb I" [8 8 8]
Material "matte" "rgb Kd" [0.5 0.4 0.3]
Shape "trianglemesh" "point P" [-1 -1 0  1 -1 0  1 1 0  -1 1 0]
  "integer indices" [0 1 2  0 2 3]
Shape "sphere" "float radius" 0.5
WorldEnd
)";

std::string make_scene(const std::string& name) {
  std::string dir = scratch_dir("pbrtc_" + name);
  write_file(dir + "/box.pbrt", kScene);
  return dir;
}

std::string pbrtc() {
  return kBin + "/pbrtc --nthreads 1";
}

// The stored bytes of the archive's largest section: where a flipped byte is surely read.
struct Span {
  uint64_t offset = 0, size = 0;
  std::string label;
};
Span largest_section(const std::string& path) {
  pbrta::ArchiveReader r;
  std::string error;
  EXPECT_TRUE(r.open(path, &error)) << error;
  Span s;
  for (uint32_t i = 0; i < r.section_count(); ++i)
    if (r.entry(i).stored_size > s.size) {
      s.offset = r.entry(i).offset;
      s.size = r.entry(i).stored_size;
      s.label = "section '" +
                std::string(pbrta::section_kind_name(pbrta::SectionKind(r.entry(i).kind))) +
                "' (#" + std::to_string(i) + "): ";
    }
  return s;
}

TEST(PbrtcCommand, CompilesToTheScenesNameAndVerifies) {
  std::string dir = make_scene("compile");
  Outcome c = run_in(dir, pbrtc() + " box.pbrt", "compile");
  ASSERT_EQ(c.status, 0) << c.err;
  ASSERT_TRUE(fs::exists(dir + "/box.pbrta"));
  EXPECT_NE(c.err.find("-> box.pbrta"), std::string::npos) << c.err;
  Outcome v = run_in(dir, pbrtc() + " --verify box.pbrta", "verify");
  EXPECT_EQ(v.status, 0) << v.err;
  EXPECT_EQ(v.out.rfind("box.pbrta: ok (", 0), 0u) << v.out;
  Outcome i = run_in(dir, pbrtc() + " --info box.pbrta", "info");
  EXPECT_EQ(i.status, 0) << i.err;
  EXPECT_NE(i.out.find("shapes 2 (meshes 1, triangles 2)"), std::string::npos) << i.out;
  // Quiet compiles print nothing, and no temporary file is left beside the archive.
  Outcome q = run_in(dir, pbrtc() + " -q box.pbrt -o q.pbrta", "quiet");
  EXPECT_EQ(q.status, 0);
  EXPECT_EQ(q.err, "");
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir))
    files += e.path().extension() == ".pbrta" || e.path().filename().string()[0] == '.';
  EXPECT_EQ(files, 2);  // box.pbrta and q.pbrta
}

TEST(PbrtcCommand, ADamagedArchiveIsRefusedWithItsSection) {
  std::string dir = make_scene("damaged");
  ASSERT_EQ(run_in(dir, pbrtc() + " -q --codec none box.pbrt -o good.pbrta").status, 0);
  std::string bytes = read_file(dir + "/good.pbrta");
  const Span s = largest_section(dir + "/good.pbrta");
  ASSERT_GT(s.size, 0u);
  bytes[s.offset + s.size / 2] ^= 0x5a;
  write_file(dir + "/bad.pbrta", bytes);

  Outcome v = run_in(dir, pbrtc() + " --verify bad.pbrta", "verify");
  EXPECT_EQ(v.status, 1);
  EXPECT_NE(v.err.find("bad.pbrta: " + s.label + "checksum mismatch"), std::string::npos) << v.err;
  EXPECT_EQ(v.out.find("ok"), std::string::npos) << v.out;
  // A good and a bad archive: the good one is reported, the exit code says one failed.
  Outcome both = run_in(dir, pbrtc() + " --verify good.pbrta bad.pbrta", "both");
  EXPECT_EQ(both.status, 1);
  EXPECT_NE(both.out.find("good.pbrta: ok"), std::string::npos) << both.out;

  // pbrtrun loads through the same code: the same message, and no image written.
  Outcome r = run_in(dir, kBin + "/pbrtrun -q --nthreads 1 bad.pbrta -o out.exr", "render");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find(s.label + "checksum mismatch"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/out.exr"));
}

TEST(PbrtcCommand, ATruncatedArchiveIsRefused) {
  std::string dir = make_scene("truncated");
  ASSERT_EQ(run_in(dir, pbrtc() + " -q box.pbrt -o good.pbrta").status, 0);
  const std::string bytes = read_file(dir + "/good.pbrta");
  for (size_t keep : {size_t(0), size_t(7), bytes.size() / 2, bytes.size() - 1}) {
    SCOPED_TRACE("kept " + std::to_string(keep) + " bytes");
    write_file(dir + "/cut.pbrta", bytes.substr(0, keep));
    Outcome v = run_in(dir, pbrtc() + " --verify cut.pbrta", "verify");
    EXPECT_EQ(v.status, 1);
    EXPECT_EQ(v.err.rfind("pbrtc: error: cut.pbrta: ", 0), 0u) << v.err;
    Outcome r = run_in(dir, kBin + "/pbrtrun -q cut.pbrta -o out.exr", "render");
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("cut.pbrta"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir + "/out.exr"));
  }
}

// A grid of n x n quads with uv: 64+ triangles, so --draco-bits compresses it through Draco.
std::string uv_grid_scene(const pbrta::test_forgery::UvGrid& g) {
  auto list = [](const auto& v) {
    std::string out;
    for (auto x : v) out += " " + std::to_string(x);
    return out;
  };
  std::string scene = kScene;
  scene.insert(scene.find("WorldEnd"), "Shape \"trianglemesh\" \"point P\" [" + list(g.P) +
                                           "] \"point2 uv\" [" + list(g.uv) +
                                           "] \"integer indices\" [" + list(g.indices) + "]\n");
  return scene;
}

// A forged Draco stream with a valid checksum, of the kind that kept Draco busy for seconds
// (format/draco_forgery.h): both
// programs refuse it within the reader's budget (format/isolated_jobs.h), with the section and
// the reason, and pbrtrun writes no image.
TEST(PbrtcCommand, AForgedDracoStreamIsRefusedWithinItsBudget) {
  const std::string dir = scratch_dir("pbrtc_forged_draco");
  const pbrta::test_forgery::UvGrid grid = pbrta::test_forgery::uv_grid(8);
  write_file(dir + "/grid.pbrt", uv_grid_scene(grid));
  Outcome c = run_in(dir, pbrtc() + " -q --draco-bits 14 grid.pbrt -o good.pbrta", "compile");
  ASSERT_EQ(c.status, 0) << c.err;
  std::string bytes = read_file(dir + "/good.pbrta");
  pbrta::ArchiveReader r;
  std::string error;
  ASSERT_TRUE(r.open(dir + "/good.pbrta", &error)) << error;
  uint32_t draco = 0;
  while (draco < r.section_count() && r.entry(draco).codec != uint32_t(pbrta::Codec::kDraco))
    ++draco;
  ASSERT_LT(draco, r.section_count()) << "no Draco section";
  const pbrta::SectionEntry e = r.entry(draco);
  ASSERT_TRUE(pbrta::test_forgery::forge_orientation_count(
      reinterpret_cast<uint8_t*>(&bytes[e.offset]), e.stored_size, grid.num_vertices()))
      << "the orientation count is not where this Draco version writes it";
  pbrta::test_bytes::reseal(&bytes, draco, e.stored_size);
  write_file(dir + "/bad.pbrta", bytes);
  const std::string reason = "bad.pbrta: section 'geometry' (#" + std::to_string(draco) +
                             "): draco: decoding ran past its budget of 1 s of CPU time";

  Outcome v = run_in(dir, pbrtc() + " --verify good.pbrta bad.pbrta", "verify");
  EXPECT_EQ(v.status, 1);
  EXPECT_NE(v.out.find("good.pbrta: ok"), std::string::npos) << v.out;
  EXPECT_NE(v.err.find(reason), std::string::npos) << v.err;
  Outcome render = run_in(dir, kBin + "/pbrtrun -q bad.pbrta -o out.exr", "render");
  EXPECT_EQ(render.status, 1);
  EXPECT_NE(render.err.find(reason), std::string::npos) << render.err;
  EXPECT_FALSE(fs::exists(dir + "/out.exr"));
}

// Progress on a terminal: each phase of the compile (here the Draco meshes and their triangle
// count, then compression and its byte count) on one line rewritten in place, erased before the
// summary line; none of it through a pipe or with --quiet.
TEST(PbrtcCommand, ShowsProgressOnlyOnATerminal) {
  const std::string dir = scratch_dir("pbrtc_progress");
  write_file(dir + "/grid.pbrt", uv_grid_scene(pbrta::test_forgery::uv_grid(8)));
  const Outcome t = run_on_terminal(dir, pbrtc() + " --draco-bits 14 grid.pbrt");
  ASSERT_EQ(t.status, 0) << t.out;
  const std::string line = "\r\033[Kgrid.pbrt: ";
  // The grid alone has the 64 triangles Draco needs; the box's 2 stay lossless.
  const std::vector<size_t> at = find_in_order(
      t.out, {line + "Draco meshes (1)", line + "Draco meshes, 128 of 128 triangles",
              line + "compressing (", line + "compressing, ", "\r\033[Kpbrtc: grid.pbrt: "});
  ASSERT_EQ(at.size(), 5u);
  const size_t summary = at[4];
  const size_t bytes = t.out.rfind(line + "compressing, ", summary);
  // The last count is the whole: "compressing, X of X KiB" (MiB from 1 MiB).
  const std::string last = t.out.substr(bytes + line.size(), summary - bytes - line.size());
  double done = -1, total = -2;
  ASSERT_EQ(std::sscanf(last.c_str(), "compressing, %lf of %lf KiB", &done, &total), 2) << last;
  EXPECT_EQ(done, total);
  EXPECT_GT(total, 0.5);
  EXPECT_TRUE(fs::exists(dir + "/grid.pbrta"));
  // A phase with nothing to do is not shown: the scene has no image.
  EXPECT_EQ(t.out.find("images ("), std::string::npos) << t.out;
  // Images count distinct files: two textures of one file decode it once.
  std::string pfm = "PF\n2 2\n-1.0\n";
  for (int k = 0; k < 12; ++k) {
    const float v = 0.1f * float(k);
    pfm.append(reinterpret_cast<const char*>(&v), 4);
  }
  write_file(dir + "/tex.pfm", pfm);
  std::string textured = kScene;
  textured.insert(textured.find("Material"),
                  "Texture \"a\" \"spectrum\" \"imagemap\" \"string filename\" \"tex.pfm\"\n"
                  "Texture \"b\" \"spectrum\" \"imagemap\" \"string filename\" \"tex.pfm\"\n"
                  "Material \"matte\" \"texture Kd\" \"a\"\n"
                  "Shape \"sphere\" \"float radius\" 0.2\n"
                  "Material \"matte\" \"texture Kd\" \"b\"\n");
  write_file(dir + "/textured.pbrt", textured);
  const Outcome img = run_on_terminal(dir, pbrtc() + " textured.pbrt");
  ASSERT_EQ(img.status, 0) << img.out;
  EXPECT_NE(img.out.find("\r\033[Ktextured.pbrt: images (1)"), std::string::npos) << img.out;

  const Outcome piped = run_in(dir, pbrtc() + " --draco-bits 14 grid.pbrt", "piped");
  EXPECT_EQ(piped.status, 0);
  EXPECT_EQ(piped.err.find('\033'), std::string::npos) << piped.err;
  EXPECT_EQ(piped.err.rfind("pbrtc: grid.pbrt: ", 0), 0u) << piped.err;
  const Outcome quiet = run_on_terminal(dir, pbrtc() + " -q --draco-bits 14 grid.pbrt");
  EXPECT_EQ(quiet.status, 0);
  EXPECT_EQ(quiet.out, "");
}

// The Draco report's "largest vertex displacement" is what the archive holds: the largest
// per-axis distance from a decoded vertex to the nearest vertex the scene gave, measured here
// by brute force, and within the bound the bits imply.
TEST(PbrtcCommand, TheDracoReportStatesTheDisplacementTheArchiveHolds) {
  const std::string dir = scratch_dir("pbrtc_draco_report");
  const int n = 16;
  std::vector<float> P;  // as pbrtc reads them back from the text below
  std::string points, indices;
  char number[32];
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x)
      for (double c : {0.37 * x, 0.53 * y, std::sin(0.7 * x * y)}) {
        std::snprintf(number, sizeof number, " %.9g", c);
        points += number;
        P.push_back(std::strtof(number, nullptr));
      }
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const int a = y * (n + 1) + x;
      for (int v : {a, a + 1, a + n + 2, a, a + n + 2, a + n + 1})
        indices += " " + std::to_string(v);
    }
  std::string scene = kScene;
  scene.insert(scene.find("WorldEnd"), "Shape \"trianglemesh\" \"point P\" [" + points +
                                           "] \"integer indices\" [" + indices + "]\n");
  write_file(dir + "/bumps.pbrt", scene);
  double reported[2] = {};
  for (int k = 0; k < 2; ++k) {
    const int bits = k == 0 ? 8 : 14;
    SCOPED_TRACE(std::to_string(bits) + " bits");
    const std::string out = "b" + std::to_string(bits) + ".pbrta";
    const Outcome c = run_in(
        dir, pbrtc() + " --draco-bits " + std::to_string(bits) + " bumps.pbrt -o " + out, "c");
    ASSERT_EQ(c.status, 0) << c.err;
    const size_t at = c.err.find("largest vertex displacement ");
    ASSERT_NE(at, std::string::npos) << c.err;
    double bound = 0, rounding = 0;
    unsigned mesh = 0;
    ASSERT_EQ(
        std::sscanf(c.err.c_str() + at,
                    "largest vertex displacement %lf (mesh %u: bound %lf + float rounding %lf)",
                    &reported[k], &mesh, &bound, &rounding),
        4)
        << c.err;
    EXPECT_NE(c.err.find("every mesh within its bound"), std::string::npos) << c.err;

    pbrta::SceneArchive a;
    std::string error;
    ASSERT_TRUE(a.load(dir + "/" + out, 1, &error)) << error;
    ASSERT_LT(mesh, a.meshes.size);
    const pbrta::MeshRecord& m = a.meshes[mesh];
    ASSERT_EQ(m.num_vertices, P.size() / 3) << "the report names another mesh";
    const float* got = a.positions(mesh);
    double measured = 0;
    for (uint32_t v = 0; v < m.num_vertices; ++v) {
      double nearest = 1e30;
      for (size_t o = 0; o < P.size(); o += 3) {
        double d = 0;
        for (int j = 0; j < 3; ++j) d = std::max(d, std::fabs(double(got[3 * v + j]) - P[o + j]));
        nearest = std::min(nearest, d);
      }
      measured = std::max(measured, nearest);
    }
    // The bound the bits imply (half a quantization step over the largest extent), and float
    // rounding of a few ulps of the largest magnitude on top.
    double lo[3] = {1e30, 1e30, 1e30}, hi[3] = {-1e30, -1e30, -1e30}, largest = 0;
    for (size_t o = 0; o < P.size(); ++o) {
      lo[o % 3] = std::min(lo[o % 3], double(P[o]));
      hi[o % 3] = std::max(hi[o % 3], double(P[o]));
      largest = std::max(largest, std::fabs(double(P[o])));
    }
    const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    const double expected_bound = extent / ((1 << bits) - 1) / 2;
    EXPECT_GT(measured, 0.5 * expected_bound);  // it did quantize
    EXPECT_LE(measured, expected_bound + 8 * largest * 0x1p-24);
    // Printed with 3 significant digits.
    EXPECT_NEAR(reported[k], measured, 0.006 * measured);
    EXPECT_NEAR(bound, expected_bound, 0.006 * expected_bound);
    EXPECT_LE(rounding, 8 * largest * 0x1p-24);
  }
  EXPECT_GT(reported[0], 10 * reported[1]);  // 6 bits fewer: steps 64 times as large
}

TEST(PbrtcCommand, AFailedCompileLeavesTheOldArchive) {
  std::string dir = make_scene("failed");
  ASSERT_EQ(run_in(dir, pbrtc() + " -q box.pbrt").status, 0);
  const std::string before = read_file(dir + "/box.pbrta");
  std::string broken = kScene;
  broken.replace(broken.find("\"float radius\" 0.5"), 18, "\"float radius\" \"big\"");
  write_file(dir + "/box.pbrt", broken);
  Outcome c = run_in(dir, pbrtc() + " box.pbrt", "compile");
  EXPECT_EQ(c.status, 1);
  EXPECT_NE(c.err.find("box.pbrt:10:"), std::string::npos) << c.err;
  EXPECT_NE(c.err.find(": error: "), std::string::npos) << c.err;
  EXPECT_NE(c.err.find("no archive written"), std::string::npos) << c.err;
  EXPECT_TRUE(read_file(dir + "/box.pbrta") == before);
}

TEST(PbrtcCommand, ADumpCompilesBackToTheSameArchive) {
  std::string dir = make_scene("dump");
  ASSERT_EQ(run_in(dir, pbrtc() + " -q box.pbrt -o a.pbrta").status, 0);
  Outcome d = run_in(dir, pbrtc() + " --dump a.pbrta out", "dump");
  ASSERT_EQ(d.status, 0) << d.err;
  ASSERT_TRUE(fs::exists(dir + "/out/a.pbrt"));
  ASSERT_EQ(run_in(dir, pbrtc() + " -q out/a.pbrt -o b.pbrta", "recompile").status, 0);
  // Everything but provenance (file names and lines) is the same: same size, same --info table
  // apart from the provenance row and the totals it moves.
  Outcome ia = run_in(dir, pbrtc() + " --info a.pbrta", "info_a");
  Outcome ib = run_in(dir, pbrtc() + " --info b.pbrta", "info_b");
  ASSERT_EQ(ia.status, 0);
  ASSERT_EQ(ib.status, 0);
  auto rows = [](const std::string& info) {
    std::string kept;
    bool table = false;
    for (const std::string& row : testing_support::lines_of(info)) {
      table |= row == "  sections:";
      if (table && row.find("provenance") == std::string::npos &&
          row.find("total") == std::string::npos)
        kept += row + "\n";
    }
    return kept;
  };
  EXPECT_EQ(rows(ia.out), rows(ib.out));
  EXPECT_NE(rows(ia.out).find("meshes"), std::string::npos);
}

TEST(PbrtcCommand, UsageErrorsExitTwo) {
  std::string dir = make_scene("usage");
  Outcome a = run_in(dir, pbrtc() + " --dump box.pbrta", "dump");
  EXPECT_EQ(a.status, 2);
  EXPECT_NE(a.err.find("--dump takes an archive and an output directory"), std::string::npos);
  Outcome b = run_in(dir, pbrtc() + " --codec none --draco-bits 12 box.pbrt", "draco");
  EXPECT_EQ(b.status, 2);
  EXPECT_NE(b.err.find("cannot go with --codec none"), std::string::npos) << b.err;
  Outcome c = run_in(dir, pbrtc() + " --codec lz4 box.pbrt", "codec");
  EXPECT_NE(c.status, 0);
  EXPECT_NE(c.err.find("--codec"), std::string::npos) << c.err;
  EXPECT_FALSE(fs::exists(dir + "/box.pbrta"));
}

}  // namespace
