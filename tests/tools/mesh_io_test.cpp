// tests/tools/mesh_io_test.cpp — read_mesh / write_mesh on every format, real meshes, bad input.
//
// Round trips compare meshes as sets of triangles up to vertex and face order: each vertex read
// back is matched to the nearest original vertex (exactly equal for the lossless formats, within
// the quantization bound for Draco) and every triangle becomes the sorted triple of its matched
// originals' positions. Malformed input must fail cleanly with a message, never crash or
// allocate what a lying header asks for.
#include <gtest/gtest.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "compiler/diagnostics.h"
#include "compiler/scene_builder.h"
#include "compiler/scene_desc.h"
#include "compiler/source_files.h"
#include "format/draco_codec.h"
#include "format/draco_forgery.h"
#include "test_support.h"
#include "tools/mesh/commands.h"
#include "tools/mesh/mesh.h"

namespace meshtools {
namespace {

namespace fs = std::filesystem;
using testing_support::scratch_dir;
using testing_support::write_file;

// A wavy 6x5 grid with normals and uv; every position distinct, values that are not short
// decimals, so a writer that prints too few digits is caught.
Mesh test_mesh() {
  Mesh m;
  const int nx = 6, ny = 5;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const float x = float(i) / 3.0f - 0.7f, y = float(j) / 7.0f + 0.1f;
      const float z = 0.3f * std::sin(x * 2.1f) * std::cos(y * 1.7f);
      m.positions.insert(m.positions.end(), {x, y, z});
      const float n[3] = {-0.2f * x, 0.1f * y, 1.0f};
      const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      m.normals.insert(m.normals.end(), {n[0] / len, n[1] / len, n[2] / len});
      m.uvs.insert(m.uvs.end(), {float(i) / (nx - 1), float(j) / (ny - 1)});
    }
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const uint32_t a = uint32_t(j * nx + i), b = a + 1, c = a + uint32_t(nx), d = c + 1;
      m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
    }
  return m;
}

pbrta::MeshArrays arrays(const Mesh& m) {
  pbrta::MeshArrays a;
  a.positions = m.positions.data();
  a.normals = m.normals.empty() ? nullptr : m.normals.data();
  a.uv = m.uvs.empty() ? nullptr : m.uvs.data();
  a.indices = m.indices.data();
  a.num_vertices = m.num_vertices();
  a.num_triangles = m.num_triangles();
  return a;
}

using Triangle = std::array<std::array<float, 3>, 3>;

// Triangles of `got` as sorted triples of the positions of the original vertices its vertices
// match; *max_error receives the largest per-axis distance of a match.
std::vector<Triangle> triangles_matched(const Mesh& original, const Mesh& got, double bound,
                                        bool same_order, double* max_error) {
  std::vector<uint32_t> nearest;
  *max_error =
      pbrta::draco_max_displacement(arrays(original), arrays(got), bound, same_order, &nearest);
  std::vector<Triangle> out;
  for (size_t f = 0; f < got.num_triangles(); ++f) {
    Triangle t;
    for (int k = 0; k < 3; ++k) {
      const float* p = &original.positions[3 * size_t(nearest[got.indices[3 * f + size_t(k)]])];
      t[size_t(k)] = {p[0], p[1], p[2]};
    }
    std::sort(t.begin(), t.end());
    out.push_back(t);
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<Triangle> triangles_of(const Mesh& m) {
  double unused;
  return triangles_matched(m, m, 0, true, &unused);
}

bool holds_normals(const std::string& ext) {
  return ext != "stl";
}
bool holds_uv(const std::string& ext) {
  return ext != "stl";
}
bool lossy(const std::string& ext) {
  return ext == "drc";
}

// Attribute values of got's vertices against their matched originals.
void expect_attributes_close(const Mesh& original, const Mesh& got, double normal_tol,
                             double uv_tol, const std::string& what) {
  std::vector<uint32_t> nearest;
  const double bound =
      pbrta::draco_position_bound(original.positions.data(), original.num_vertices(), 11);
  pbrta::draco_max_displacement(arrays(original), arrays(got), bound, false, &nearest);
  double worst_n = 0, worst_uv = 0;
  for (size_t v = 0; v < got.num_vertices(); ++v) {
    const size_t o = nearest[v];
    for (int k = 0; k < 3 && !got.normals.empty(); ++k)
      worst_n = std::max(worst_n, double(std::fabs(got.normals[3 * v + size_t(k)] -
                                                   original.normals[3 * o + size_t(k)])));
    for (int k = 0; k < 2 && !got.uvs.empty(); ++k)
      worst_uv =
          std::max(worst_uv,
                   double(std::fabs(got.uvs[2 * v + size_t(k)] - original.uvs[2 * o + size_t(k)])));
  }
  EXPECT_LE(worst_n, normal_tol) << what;
  EXPECT_LE(worst_uv, uv_tol) << what;
}

const char* const kFormats[] = {"obj", "ply", "off", "stl", "drc", "pbrt"};

TEST(MeshIo, ExtensionOf) {
  EXPECT_EQ(extension_of("a/b.PLY"), "ply");
  EXPECT_EQ(extension_of("x.tar.DRC"), "drc");
  EXPECT_EQ(extension_of("dir.d/noext"), "");
  EXPECT_EQ(extension_of(".hidden"), "");
}

// Every ordered pair of formats: write the mesh as A, read it, write that as B, read it.
TEST(MeshIo, RoundTripsEveryFormatPair) {
  const std::string dir = scratch_dir("mesh_io_pairs");
  const Mesh original = test_mesh();
  const std::vector<Triangle> want = triangles_of(original);
  const double bound =
      pbrta::draco_position_bound(original.positions.data(), original.num_vertices(), 14) +
      pbrta::draco_position_slack(original.positions.data(), original.num_vertices());
  for (const std::string a : kFormats)
    for (const std::string b : kFormats) {
      const std::string what = a + " -> " + b;
      WriteOptions opt;
      std::string error;
      const std::string pa = dir + "/a_" + a + "_" + b + "." + a;
      const std::string pb = dir + "/b_" + a + "_" + b + "." + b;
      Mesh ma, mb;
      ASSERT_TRUE(write_mesh(pa, original, opt, &error)) << what << ": " << error;
      ASSERT_TRUE(read_mesh(pa, &ma, &error)) << what << ": " << error;
      ASSERT_TRUE(write_mesh(pb, ma, opt, &error)) << what << ": " << error;
      ASSERT_TRUE(read_mesh(pb, &mb, &error)) << what << ": " << error;
      EXPECT_EQ(mb.num_triangles(), original.num_triangles()) << what;
      const bool is_lossy = lossy(a) || lossy(b);
      double err = 0;
      const std::vector<Triangle> got = triangles_matched(original, mb, bound, false, &err);
      EXPECT_EQ(got, want) << what;
      EXPECT_LE(err, is_lossy ? 2 * bound : 0.0) << what;  // two encodings can add up
      const bool normals = holds_normals(a) && holds_normals(b);
      const bool uv = holds_uv(a) && holds_uv(b);
      EXPECT_EQ(!mb.normals.empty(), normals) << what;
      EXPECT_EQ(!mb.uvs.empty(), uv) << what;
      // Draco: normals to 10 octahedral bits (well under a degree), uv to 12 bits.
      expect_attributes_close(original, mb, is_lossy ? 0.01 : 0.0, is_lossy ? 2.0 / 4095 : 0.0,
                              what);
    }
}

TEST(MeshIo, AsciiPlyAndPlymeshStyleRoundTrip) {
  const std::string dir = scratch_dir("mesh_io_ascii");
  const Mesh original = test_mesh();
  WriteOptions opt;
  opt.ply_ascii = true;
  std::string error;
  Mesh back;
  ASSERT_TRUE(write_mesh(dir + "/m.ply", original, opt, &error)) << error;
  EXPECT_EQ(testing_support::read_file(dir + "/m.ply").rfind("ply\nformat ascii 1.0\n", 0), 0u);
  ASSERT_TRUE(read_mesh(dir + "/m.ply", &back, &error)) << error;
  EXPECT_EQ(back.positions, original.positions);
  EXPECT_EQ(back.normals, original.normals);
  EXPECT_EQ(back.uvs, original.uvs);
  EXPECT_EQ(back.indices, original.indices);

  opt.pbrt = PbrtStyle::kPlymesh;
  ASSERT_TRUE(write_mesh(dir + "/shape.pbrt", original, opt, &error)) << error;
  EXPECT_TRUE(fs::exists(dir + "/shape.ply"));
  ASSERT_TRUE(read_mesh(dir + "/shape.pbrt", &back, &error)) << error;
  EXPECT_EQ(back.positions, original.positions);
  EXPECT_EQ(back.indices, original.indices);
  // No temporary files are left behind.
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
}

TEST(MeshIo, FaceIndicesSurvivePlyDracoAndPbrt) {
  const std::string dir = scratch_dir("mesh_io_face_indices");
  Mesh m = test_mesh();
  for (size_t f = 0; f < m.num_triangles(); ++f) m.face_indices.push_back(int32_t(f / 2));
  for (const std::string ext : {"ply", "drc", "pbrt"}) {
    std::string error;
    Mesh back;
    WriteOptions opt;
    opt.draco_sequential = true;
    ASSERT_TRUE(write_mesh(dir + "/m." + ext, m, opt, &error)) << error;
    ASSERT_TRUE(read_mesh(dir + "/m." + ext, &back, &error)) << error;
    EXPECT_EQ(back.face_indices, m.face_indices) << ext;
  }
}

// Every PLY of the shared corpus through Draco and back at 11, 14 and 16 bits, both encodings.
TEST(MeshIo, SharedPlyMeshesThroughDraco) {
  std::vector<std::string> plys;
  for (const auto& e : fs::recursive_directory_iterator(testing_support::shared_dir() + "/scenes"))
    if (e.is_regular_file() && extension_of(e.path().string()) == "ply")
      plys.push_back(e.path().string());
  std::sort(plys.begin(), plys.end());
  ASSERT_FALSE(plys.empty());
  const std::string dir = scratch_dir("mesh_io_shared_draco");
  for (const std::string& ply : plys) {
    Mesh original;
    std::string error;
    ASSERT_TRUE(read_mesh(ply, &original, &error)) << error;
    const std::vector<Triangle> want = triangles_of(original);
    for (int bits : {11, 14, 16})
      for (bool sequential : {false, true}) {
        const std::string what = ply + " at " + std::to_string(bits) +
                                 (sequential ? " bits, sequential" : " bits, edgebreaker");
        WriteOptions opt;
        opt.draco_bits = bits;
        opt.draco_sequential = sequential;
        Mesh drc, back;
        ASSERT_TRUE(write_mesh(dir + "/m.drc", original, opt, &error)) << what << error;
        ASSERT_TRUE(read_mesh(dir + "/m.drc", &drc, &error)) << what << error;
        ASSERT_TRUE(write_mesh(dir + "/m.ply", drc, opt, &error)) << what << error;
        ASSERT_TRUE(read_mesh(dir + "/m.ply", &back, &error)) << what << error;
        EXPECT_EQ(back.num_triangles(), original.num_triangles()) << what;
        const double bound =
            pbrta::draco_position_bound(original.positions.data(), original.num_vertices(), bits) +
            pbrta::draco_position_slack(original.positions.data(), original.num_vertices());
        if (sequential && back.num_vertices() == original.num_vertices()) {
          // Same order: vertex v came from vertex v, triangle f from triangle f.
          EXPECT_EQ(back.indices, original.indices) << what;
          double err = pbrta::draco_max_displacement(arrays(original), arrays(back), bound, true);
          EXPECT_LE(err, bound) << what;
        } else {
          double err = 0;
          EXPECT_EQ(triangles_matched(original, back, bound, false, &err), want) << what;
          EXPECT_LE(err, bound) << what;
          EXPECT_FALSE(sequential) << what << ": sequential changed the vertex count";
        }
      }
  }
}

// ---- malformed input ----

void expect_read_fails(const std::string& path, const std::string& reason_part) {
  ASSERT_FALSE(reason_part.empty()) << "say what the failure must say";
  Mesh m;
  std::string error;
  EXPECT_FALSE(read_mesh(path, &m, &error)) << path;
  EXPECT_NE(error.find(reason_part), std::string::npos) << path << ": " << error;
  EXPECT_EQ(error.rfind(path, 0), 0u) << "the message names the file: " << error;
  EXPECT_EQ(m.num_vertices(), 0u);
  EXPECT_EQ(m.num_triangles(), 0u);
}

TEST(MeshIo, EmptyFilesAreErrors) {
  const std::string dir = scratch_dir("mesh_io_empty");
  for (const std::string ext : kFormats)
    expect_read_fails(write_file(dir + "/e." + ext, ""), "empty file");
  expect_read_fails(write_file(dir + "/c.obj", "# only a comment\n"), "no vertices");
  expect_read_fails(dir + "/missing.obj", "cannot open");
  expect_read_fails(write_file(dir + "/x.xyz", "1 2 3\n"), "unknown mesh format");
}

TEST(MeshIo, TruncatedBinaryPly) {
  const std::string dir = scratch_dir("mesh_io_trunc_ply");
  std::string error;
  ASSERT_TRUE(write_mesh(dir + "/m.ply", test_mesh(), WriteOptions{}, &error)) << error;
  const std::string bytes = testing_support::read_file(dir + "/m.ply");
  for (size_t cut : {bytes.size() - 1, bytes.size() / 2, bytes.find("end_header") + 11})
    expect_read_fails(write_file(dir + "/t" + std::to_string(cut) + ".ply", bytes.substr(0, cut)),
                      "exceeds what the file can hold");
}

TEST(MeshIo, CountsThatLie) {
  const std::string dir = scratch_dir("mesh_io_lying_counts");
  expect_read_fails(write_file(dir + "/huge.off", "OFF\n1000000000 1 0\n0 0 0\n"), "header");
  expect_read_fails(write_file(dir + "/faces.off", "OFF\n3 1000000000 0\n0 0 0\n"), "header");
  expect_read_fails(write_file(dir + "/short.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                    "header promises 4 vertices and 1 faces, but only 26 bytes follow");
  // Binary STL: a header promising 1e9 triangles in a file of one.
  std::string stl(84 + 50, '\0');
  uint32_t n = 1000000000;
  std::memcpy(&stl[80], &n, 4);
  expect_read_fails(write_file(dir + "/lie.stl", stl), "header says 1000000000 triangles");
  n = 2;  // one record short
  std::memcpy(&stl[80], &n, 4);
  expect_read_fails(write_file(dir + "/short.stl", stl), "header says 2 triangles");
  expect_read_fails(write_file(dir + "/huge.ply",
                               "ply\nformat binary_little_endian 1.0\n"
                               "element vertex 1000000000\nproperty float x\n"
                               "property float y\nproperty float z\n"
                               "element face 1\nproperty list uchar int "
                               "vertex_indices\nend_header\n"),
                    "vertex count 1000000000 exceeds what the file can hold (0 bytes left)");
  expect_read_fails(write_file(dir + "/junk.drc", "DRACO\x02\x02\x01\x01\0\0garbage"), "draco: ");
}

// A .drc file forged to keep Draco busy for seconds (format/draco_forgery.h) is refused within
// the budget Draco runs under (format/isolated_jobs.h), by the same reader pbrt-mesh uses.
TEST(MeshIo, AForgedDracoFileIsRefusedWithinItsBudget) {
  const std::string dir = scratch_dir("mesh_io_forged_drc");
  const pbrta::test_forgery::UvGrid g = pbrta::test_forgery::uv_grid(8);
  Mesh grid;
  grid.positions = g.P;
  grid.uvs = g.uv;
  grid.indices = g.indices;
  WriteOptions opt;
  opt.draco_bits = 14;
  std::string error;
  ASSERT_TRUE(write_mesh(dir + "/good.drc", grid, opt, &error)) << error;
  Mesh back;
  ASSERT_TRUE(read_mesh(dir + "/good.drc", &back, &error)) << error;
  std::string bytes = testing_support::read_file(dir + "/good.drc");
  ASSERT_TRUE(pbrta::test_forgery::forge_orientation_count(reinterpret_cast<uint8_t*>(&bytes[0]),
                                                           bytes.size(), g.num_vertices()));
  expect_read_fails(write_file(dir + "/forged.drc", bytes),
                    "draco: decoding ran past its budget of 1 s of CPU time");
}

TEST(MeshIo, NanCoordinatesAreRejected) {
  const std::string dir = scratch_dir("mesh_io_nan");
  expect_read_fails(write_file(dir + "/n.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"), "line 2");
  expect_read_fails(write_file(dir + "/i.obj", "v 0 0 0\nv 1e50 0 0\nv 0 1 0\nf 1 2 3\n"),
                    "not a finite number");
  expect_read_fails(write_file(dir + "/n.off", "OFF\n3 1 0\n0 0 0\n1 inf 0\n0 1 0\n3 0 1 2\n"),
                    "vertex 1");
  expect_read_fails(write_file(dir + "/n.ply",
                               "ply\nformat ascii 1.0\nelement vertex 3\n"
                               "property float x\nproperty float y\n"
                               "property float z\nelement face 1\n"
                               "property list uchar int vertex_indices\n"
                               "end_header\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n"),
                    "vertex 1: coordinate is NaN");
  expect_read_fails(write_file(dir + "/n.stl",
                               "solid x\nfacet normal 0 0 1\nouter loop\n"
                               "vertex 0 0 0\nvertex 1 0 NaN\nvertex 0 1 0\n"
                               "endloop\nendfacet\nendsolid x\n"),
                    "line 5");
  std::string stl(84 + 50, '\0');
  const uint32_t n = 1;
  std::memcpy(&stl[80], &n, 4);
  const float nan = std::nanf("");
  std::memcpy(&stl[84 + 12 + 4], &nan, 4);
  expect_read_fails(write_file(dir + "/nb.stl", stl), "not finite");
  expect_read_fails(write_file(dir + "/n.pbrt",
                               "Shape \"trianglemesh\" \"integer indices\" "
                               "[0 1 2] \"point P\" [0 0 0 1 0 0 0 1 nan]\n"),
                    ":1:75: expected a number or ']', got 'nan'");
}

TEST(MeshIo, OutOfRangeIndicesAreRejected) {
  const std::string dir = scratch_dir("mesh_io_range");
  expect_read_fails(write_file(dir + "/a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n"),
                    "line 4: vertex index \"99\" out of range");
  expect_read_fails(write_file(dir + "/b.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n"),
                    "out of range");
  expect_read_fails(write_file(dir + "/c.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 0 2\n"),
                    "out of range");
  expect_read_fails(
      write_file(dir + "/d.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/2 2/1 3/1\n"),
      "texture index");
  expect_read_fails(write_file(dir + "/e.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"),
                    "out of range");
  expect_read_fails(write_file(dir + "/f.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n9 0 1 2\n"),
                    "bad vertex count");
  expect_read_fails(write_file(dir + "/g.ply",
                               "ply\nformat ascii 1.0\nelement vertex 3\n"
                               "property float x\nproperty float y\n"
                               "property float z\nelement face 1\n"
                               "property list uchar int vertex_indices\n"
                               "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"),
                    "face 0: index 7 out of range (3 vertices)");
  expect_read_fails(write_file(dir + "/h.pbrt",
                               "Shape \"trianglemesh\" \"integer indices\" "
                               "[0 1 5] \"point P\" [0 0 0 1 0 0 0 1 0]\n"),
                    ":1:41: trianglemesh index 5 (entry 2) is out of range: 3 vertices");
  // And nothing invalid is written either.
  Mesh bad = test_mesh();
  bad.indices[4] = 1000;
  std::string error;
  EXPECT_FALSE(write_mesh(dir + "/bad.obj", bad, WriteOptions{}, &error));
  EXPECT_NE(error.find("out of range"), std::string::npos) << error;
  EXPECT_FALSE(fs::exists(dir + "/bad.obj"));
}

TEST(MeshIo, ObjPolygonsSeamsAndRelativeIndices) {
  const std::string dir = scratch_dir("mesh_io_obj");
  // A quad with negative indices, then a triangle whose corners use a second uv for vertex 1
  // (a seam): it becomes its own vertex.
  const std::string obj =
      "o quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n"
      "f -4/1 -3/2 -2/3 -1/4\nv 2 0 0\nf 2/5 5/2 3/3\n";
  Mesh m;
  std::string error;
  ASSERT_TRUE(read_mesh(write_file(dir + "/q.obj", obj), &m, &error)) << error;
  EXPECT_EQ(m.num_triangles(), 3u);
  EXPECT_EQ(m.num_vertices(), 6u);  // 4 corners of the quad, vertex 5, and vertex 2 with uv 5
  EXPECT_EQ(m.uvs.size(), 12u);
  EXPECT_TRUE(m.normals.empty());
}

// `pbrt-mesh convert` writes shapes pbrtc compiles: inline and as a plymesh.
TEST(MeshIo, ConvertOutputCompilesWithPbrtc) {
  const std::string dir = scratch_dir("mesh_io_convert_pbrtc");
  const Mesh original = test_mesh();
  std::string error;
  ASSERT_TRUE(write_mesh(dir + "/in.obj", original, WriteOptions{}, &error)) << error;
  for (const bool plymesh : {false, true}) {
    const std::string out = dir + (plymesh ? "/shape_ply.pbrt" : "/shape_inline.pbrt");
    CLI::App app;
    int exit_code = -1;
    add_convert_command(&app, &exit_code);
    std::vector<std::string> args = {"pbrt-mesh", "convert", dir + "/in.obj", out, "--quiet"};
    if (plymesh) args.push_back("--plymesh");
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    ASSERT_NO_THROW(app.parse(int(argv.size()), argv.data()));
    ASSERT_EQ(exit_code, 0);
    const std::string scene =
        write_file(dir + "/scene.pbrt",
                   "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
                   "AttributeBegin\nTranslate 1 0 0\nInclude \"" +
                       fs::path(out).filename().string() + "\"\nAttributeEnd\nWorldEnd\n");
    pbrtc::SourceFiles files;
    pbrtc::Diagnostics diag(&files);
    pbrtc::SceneDesc desc;
    ASSERT_TRUE(pbrtc::build_scene(scene, &files, &diag, &desc))
        << (diag.all().empty() ? "" : diag.all()[0].text);
    size_t triangles = 0;
    for (const pbrtc::ShapeDesc& s : desc.shapes)
      if (s.mesh != pbrtc::kNone) triangles += desc.meshes[size_t(s.mesh)].num_triangles();
    EXPECT_EQ(triangles, original.num_triangles()) << out;
    // Reading the written scene back as a mesh gives the object-space triangles.
    Mesh back;
    ASSERT_TRUE(read_mesh(scene, &back, &error)) << error;
    EXPECT_EQ(triangles_of(back), triangles_of(original));
  }
}

}  // namespace
}  // namespace meshtools
