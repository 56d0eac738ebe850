// tests/tools/mesh_ops_test.cpp — vertex normals, measured Hausdorff distance, simplification.
//
// Meshes are built in memory (icospheres, a cube, fans, grids) so the expected values can be
// derived by hand; the one real mesh is read with pbrtc::read_ply so these tests do not depend on
// the mesh tools' own readers.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <utility>

#include "compiler/ply_reader.h"
#include "test_support.h"
#include "tools/mesh/mesh_ops.h"

namespace meshtools {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Icosahedron subdivided `levels` times, vertices projected onto the sphere of `radius`: closed,
// manifold, shared vertices, outward (counter-clockwise) winding. 20 * 4^levels faces.
Mesh icosphere(int levels, double radius) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<std::array<double, 3>> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                          {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                          {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<uint32_t> f = {0, 11, 5,  0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                             4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3,  9,  4, 3,  4,  2, 3, 2, 6, 3,
                             6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6,  2, 10, 8,  6, 7, 9, 8, 1};
  auto normalize = [](std::array<double, 3> v) {
    const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    return std::array<double, 3>{v[0] / l, v[1] / l, v[2] / l};
  };
  for (auto& v : p) v = normalize(v);
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoint;
    auto mid = [&](uint32_t a, uint32_t b) {
      const auto key = std::minmax(a, b);
      auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      p.push_back(normalize({p[a][0] + p[b][0], p[a][1] + p[b][1], p[a][2] + p[b][2]}));
      const uint32_t id = static_cast<uint32_t>(p.size() - 1);
      midpoint[key] = id;
      return id;
    };
    std::vector<uint32_t> g;
    for (size_t i = 0; i < f.size(); i += 3) {
      const uint32_t a = f[i], b = f[i + 1], c = f[i + 2];
      const uint32_t ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      g.insert(g.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    f = std::move(g);
  }
  Mesh mesh;
  for (const auto& v : p) {
    for (double x : v) mesh.positions.push_back(static_cast<float>(x * radius));
  }
  mesh.indices = f;
  return mesh;
}

// Unit cube [0,1]^3, 8 shared vertices, 12 outward triangles.
Mesh cube() {
  Mesh mesh;
  for (int i = 0; i < 8; ++i) {
    mesh.positions.insert(mesh.positions.end(),
                          {float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)});
  }
  // Quads as (a, b, c, d) counter-clockwise seen from outside, split along a-c.
  const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    mesh.indices.insert(mesh.indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
  }
  return mesh;
}

// A flat grid of n x n squares over [0, size]^2 at height z.
Mesh grid(int n, double size, double z) {
  Mesh mesh;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      mesh.positions.insert(mesh.positions.end(),
                            {float(size * i / n), float(size * j / n), float(z)});
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
    }
  }
  return mesh;
}

std::array<double, 3> normal_of(const Mesh& mesh, size_t v) {
  return {mesh.normals[3 * v], mesh.normals[3 * v + 1], mesh.normals[3 * v + 2]};
}

double angle_degrees(std::array<double, 3> a, std::array<double, 3> b) {
  const double la = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  const double lb = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
  const double c = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (la * lb);
  return std::acos(std::max(-1.0, std::min(1.0, c))) * 180.0 / kPi;
}

// Every undirected edge used by exactly two faces, once in each direction: closed, manifold,
// consistently oriented.
bool is_closed_manifold(const Mesh& mesh) {
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (size_t t = 0; t < mesh.num_triangles(); ++t) {
    for (int k = 0; k < 3; ++k) {
      ++directed[{mesh.indices[3 * t + k], mesh.indices[3 * t + (k + 1) % 3]}];
    }
  }
  for (const auto& [edge, count] : directed) {
    if (count != 1) return false;
    auto it = directed.find({edge.second, edge.first});
    if (it == directed.end() || it->second != 1) return false;
  }
  return true;
}

// ---- normals ----

TEST(MeshNormals, SphereNormalsPointOutwardAlongTheRadius) {
  for (NormalWeighting w : {NormalWeighting::kArea, NormalWeighting::kAngle}) {
    Mesh mesh = icosphere(4, 2.0);
    const size_t nv = mesh.num_vertices();
    compute_normals(&mesh, NormalsOptions{w, 180.0});
    ASSERT_EQ(mesh.num_vertices(), nv);
    double worst = 0;
    for (size_t v = 0; v < nv; ++v) {
      const std::array<double, 3> radial = {mesh.positions[3 * v], mesh.positions[3 * v + 1],
                                            mesh.positions[3 * v + 2]};
      worst = std::max(worst, angle_degrees(normal_of(mesh, v), radial));
    }
    // Edge length is about 0.16 on this sphere; an averaged fan is within a fraction of a degree.
    EXPECT_LT(worst, 0.5) << (w == NormalWeighting::kArea ? "area" : "angle");
  }
}

TEST(MeshNormals, CubeCreaseKeepsHardEdgesAndWideCreaseAverages) {
  Mesh hard = cube();
  std::vector<uint32_t> source;
  compute_normals(&hard, NormalsOptions{NormalWeighting::kAngle, 30.0}, &source);
  ASSERT_EQ(hard.num_vertices(), 24u);
  ASSERT_EQ(hard.num_triangles(), 12u);
  ASSERT_EQ(source.size(), 24u);
  for (uint32_t corner = 0; corner < 8; ++corner) {
    std::set<std::array<int, 3>> normals;
    for (size_t v = 0; v < 24; ++v) {
      if (source[v] != corner) continue;
      const auto n = normal_of(hard, v);
      // Each copy is exactly an axis direction pointing away from the cube.
      EXPECT_NEAR(std::abs(n[0]) + std::abs(n[1]) + std::abs(n[2]), 1.0, 1e-6);
      normals.insert({int(std::lround(n[0])), int(std::lround(n[1])), int(std::lround(n[2]))});
      for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(hard.positions[3 * v + i], hard.positions[3 * corner + i]);
      }
    }
    EXPECT_EQ(normals.size(), 3u) << "corner " << corner;
  }
  // Each face's three vertices carry that face's normal.
  for (size_t t = 0; t < 12; ++t) {
    const auto n0 = normal_of(hard, hard.indices[3 * t]);
    for (int k = 1; k < 3; ++k) EXPECT_EQ(normal_of(hard, hard.indices[3 * t + k]), n0);
  }

  Mesh smooth = cube();
  compute_normals(&smooth, NormalsOptions{NormalWeighting::kAngle, 180.0});
  ASSERT_EQ(smooth.num_vertices(), 8u);
  for (size_t v = 0; v < 8; ++v) {
    // Every face meets a corner with 90 degrees in total, so angle weighting gives the diagonal.
    const std::array<double, 3> diagonal = {smooth.positions[3 * v] - 0.5,
                                            smooth.positions[3 * v + 1] - 0.5,
                                            smooth.positions[3 * v + 2] - 0.5};
    EXPECT_LT(angle_degrees(normal_of(smooth, v), diagonal), 1e-4) << "vertex " << v;
  }
}

TEST(MeshNormals, AreaAndAngleWeightingDifferOnAFan) {
  // Two faces around vertex 0: A in the z = 0 plane (normal +z), corner 90 degrees, area 0.5;
  // B in the x = 0 plane (normal +x), corner atan(1/4) = 14.04 degrees, area 2.
  Mesh fan;
  fan.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 4, 0, 0, 4, 1};
  fan.indices = {0, 1, 2, 0, 3, 4};
  Mesh by_area = fan, by_angle = fan;
  compute_normals(&by_area, NormalsOptions{NormalWeighting::kArea, 180.0});
  compute_normals(&by_angle, NormalsOptions{NormalWeighting::kAngle, 180.0});
  // Area: 0.5 * (0,0,1) + 2 * (1,0,0), normalized = (4, 0, 1) / sqrt(17).
  const auto a = normal_of(by_area, 0);
  EXPECT_NEAR(a[0], 4 / std::sqrt(17.0), 1e-6);
  EXPECT_NEAR(a[1], 0.0, 1e-6);
  EXPECT_NEAR(a[2], 1 / std::sqrt(17.0), 1e-6);
  // Angle: (pi/2) * (0,0,1) + atan(1/4) * (1,0,0), normalized.
  const double wa = kPi / 2, wb = std::atan(0.25), len = std::hypot(wa, wb);
  const auto g = normal_of(by_angle, 0);
  EXPECT_NEAR(g[0], wb / len, 1e-6);
  EXPECT_NEAR(g[1], 0.0, 1e-6);
  EXPECT_NEAR(g[2], wa / len, 1e-6);
  EXPECT_NEAR(a[0], 0.970143, 1e-5);  // the hand-computed values, so a shared bug cannot hide
  EXPECT_NEAR(g[0], 0.154098, 1e-5);
  // The non-shared vertices have one face each: exactly its normal, either weighting.
  EXPECT_EQ(normal_of(by_area, 1), (std::array<double, 3>{0, 0, 1}));
  EXPECT_EQ(normal_of(by_angle, 4), (std::array<double, 3>{1, 0, 0}));
}

TEST(MeshNormals, DegenerateFacesAndIsolatedVerticesGiveFiniteNormals) {
  Mesh mesh;
  mesh.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0,  // a proper triangle
                    2, 0, 0, 3, 0, 0, 4, 0, 0,  // collinear: zero area
                    5, 5, 5,                    // isolated
                    6, 6, 6, 7, 7, 7};          // used only by a repeated-index face
  mesh.indices = {0, 1, 2, 3, 4, 5, 7, 7, 8, 0, 1, 1, 1, 3, 4};
  for (NormalWeighting w : {NormalWeighting::kArea, NormalWeighting::kAngle}) {
    for (double crease : {30.0, 180.0}) {
      Mesh m = mesh;
      compute_normals(&m, NormalsOptions{w, crease});
      ASSERT_EQ(m.normals.size(), 3 * m.num_vertices());
      for (size_t v = 0; v < m.num_vertices(); ++v) {
        const auto n = normal_of(m, v);
        for (double x : n) ASSERT_TRUE(std::isfinite(x)) << "vertex " << v;
        EXPECT_NEAR(std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), 1.0, 1e-6);
      }
      // The proper triangle's vertices keep its normal: degenerate neighbours add nothing.
      EXPECT_EQ(normal_of(m, 0), (std::array<double, 3>{0, 0, 1}));
      EXPECT_EQ(normal_of(m, 1), (std::array<double, 3>{0, 0, 1}));
    }
  }
}

// ---- Hausdorff ----

TEST(MeshHausdorff, IdenticalMeshesAreAtZero) {
  const Mesh sphere = icosphere(3, 1.0);
  const HausdorffResult h = hausdorff_distance(sphere, sphere, HausdorffOptions{20000, 1});
  EXPECT_LT(h.max, 1e-6);
  EXPECT_LT(h.rms, 1e-7);
  EXPECT_EQ(h.samples, 2 * (sphere.num_vertices() + 20000));
}

TEST(MeshHausdorff, OffsetPlaneIsAtTheOffset) {
  const double d = 0.25;
  const HausdorffResult h =
      hausdorff_distance(grid(10, 1.0, 0.0), grid(7, 1.0, d), HausdorffOptions{20000, 2});
  // Every sample is exactly d above or below the other plane.
  EXPECT_NEAR(h.max, d, 1e-6);
  EXPECT_NEAR(h.rms, d, 1e-6);
  EXPECT_NEAR(h.max_a_to_b, d, 1e-6);
  EXPECT_NEAR(h.max_b_to_a, d, 1e-6);
}

TEST(MeshHausdorff, KnownPairs) {
  // [0,1]x[0,1] against [0,2]x[0,1] in one plane: a lies on b (0 one way); b's far corner is 1
  // from a. Over b's uniform samples half are at 0 and half at u in [0, 1]: E[d^2] = 1/6, and
  // with as many zero samples from a, the combined rms is sqrt(1/12).
  const HausdorffResult h = hausdorff_distance(
      grid(4, 1.0, 0.0),
      [] {
        Mesh m = grid(4, 1.0, 0.0);
        for (size_t v = 0; v < m.num_vertices(); ++v) m.positions[3 * v] *= 2;
        return m;
      }(),
      HausdorffOptions{100000, 3});
  EXPECT_NEAR(h.max_a_to_b, 0.0, 1e-9);
  EXPECT_NEAR(h.max_b_to_a, 1.0, 1e-9);  // the vertex (2, y) is sampled exactly
  EXPECT_NEAR(h.rms, std::sqrt(1.0 / 12.0), 0.01);

  // An icosphere and the same mesh scaled by 1.1: corresponding face planes are 0.1 h apart (h
  // their distance from the centre, < 1), and the outer vertices are exactly 0.1 from the inner
  // vertices, their nearest points on the convex inner mesh. So the distance is 0.1, from b.
  const Mesh inner = icosphere(2, 1.0);
  Mesh outer = inner;
  for (float& x : outer.positions) x *= 1.1f;
  const HausdorffResult s = hausdorff_distance(inner, outer, HausdorffOptions{50000, 4});
  EXPECT_NEAR(s.max, 0.1, 1e-6);
  EXPECT_NEAR(s.max_b_to_a, 0.1, 1e-6);
  EXPECT_LT(s.max_a_to_b, 0.1);
  EXPECT_GT(s.max_a_to_b, 0.09);
}

TEST(MeshHausdorff, IsDeterministic) {
  const Mesh a = icosphere(2, 1.0), b = icosphere(3, 1.0);
  const HausdorffResult x = hausdorff_distance(a, b, HausdorffOptions{5000, 9});
  const HausdorffResult y = hausdorff_distance(a, b, HausdorffOptions{5000, 9});
  EXPECT_EQ(x.max, y.max);
  EXPECT_EQ(x.rms, y.rms);
}

// ---- simplify ----

SimplifyOptions with_ratio(double ratio) {
  SimplifyOptions options;
  options.ratio = ratio;
  return options;
}

TEST(MeshSimplify, SphereKeepsTenPercentStaysClosedAndClose) {
  Mesh sphere = icosphere(5, 1.0);  // 20480 faces
  sphere.uvs.resize(2 * sphere.num_vertices());
  for (size_t v = 0; v < sphere.num_vertices(); ++v) {
    sphere.uvs[2 * v] = sphere.positions[3 * v];  // any per-vertex value: it must travel along
    sphere.uvs[2 * v + 1] = sphere.positions[3 * v + 2];
  }
  compute_normals(&sphere, NormalsOptions{});
  Mesh out;
  SimplifyReport report;
  std::string error;
  ASSERT_TRUE(simplify(sphere, with_ratio(0.1), &out, &report, &error)) << error;
  EXPECT_EQ(report.faces_before, 20480u);
  EXPECT_EQ(report.faces_after, out.num_triangles());
  EXPECT_NEAR(double(out.num_triangles()), 2048.0, 2.0);
  EXPECT_TRUE(is_closed_manifold(out));
  EXPECT_EQ(out.num_vertices(), out.num_triangles() / 2 + 2);  // genus 0: V = F / 2 + 2
  ASSERT_TRUE(report.normals_recomputed);
  ASSERT_EQ(out.normals.size(), 3 * out.num_vertices());
  ASSERT_EQ(out.uvs.size(), 2 * out.num_vertices());
  for (size_t v = 0; v < out.num_vertices(); ++v) {
    // Halfedge collapses keep input vertices: on the sphere, with their own uv.
    const double r = std::sqrt(double(out.positions[3 * v]) * out.positions[3 * v] +
                               double(out.positions[3 * v + 1]) * out.positions[3 * v + 1] +
                               double(out.positions[3 * v + 2]) * out.positions[3 * v + 2]);
    EXPECT_NEAR(r, 1.0, 1e-6);
    EXPECT_EQ(out.uvs[2 * v], out.positions[3 * v]);
    EXPECT_EQ(out.uvs[2 * v + 1], out.positions[3 * v + 2]);
  }
  // Bound. Both meshes are closed, inscribed in the unit sphere (all vertices on it) and
  // surround the centre, so every ray from the centre crosses each of them between radius
  // 1 - s and 1, where s is the mesh's largest face sagitta: a face lies in the plane cutting its
  // circumcircle (radius rc) out of the sphere, at most 1 - sqrt(1 - rc^2) deep. Following the
  // ray from a point of one mesh to the other gives Hausdorff <= max(s_in, s_out), a bound taken
  // from the actual faces. For the rms, the ideal: F equilateral faces of area 4 pi / F have
  // rc^2 = 16 pi / (3 sqrt(3) F), depth (rc^2 - rho^2) / 2 at distance rho from the centre,
  // rms depth about 0.3 rc^2; a greedy quadric decimation is not that uniform, so it gets 2x.
  auto max_sagitta = [](const Mesh& m) {
    double worst = 0;
    for (size_t t = 0; t < m.num_triangles(); ++t) {
      double p[3][3];
      for (int k = 0; k < 3; ++k) {
        for (int i = 0; i < 3; ++i) p[k][i] = m.positions[3 * m.indices[3 * t + k] + i];
      }
      double e[3];  // edge lengths; rc = abc / (4 area)
      for (int k = 0; k < 3; ++k) {
        const double* u = p[k];
        const double* w = p[(k + 1) % 3];
        e[k] = std::sqrt((u[0] - w[0]) * (u[0] - w[0]) + (u[1] - w[1]) * (u[1] - w[1]) +
                         (u[2] - w[2]) * (u[2] - w[2]));
      }
      const double s = (e[0] + e[1] + e[2]) / 2;
      const double area = std::sqrt(std::max(0.0, s * (s - e[0]) * (s - e[1]) * (s - e[2])));
      const double rc = e[0] * e[1] * e[2] / (4 * area);
      worst = std::max(worst, 1 - std::sqrt(std::max(0.0, 1 - rc * rc)));
    }
    return worst;
  };
  const double bound = std::max(max_sagitta(sphere), max_sagitta(out));
  const double f = double(out.num_triangles());
  const double ideal_rms = 0.3 * 16 * kPi / (3 * std::sqrt(3.0) * f);
  ASSERT_TRUE(report.measured);
  const HausdorffResult& h = report.hausdorff;
  std::printf(
      "sphere 20480 -> %zu faces: Hausdorff max %.6g rms %.6g (bound %.6g, ideal rms "
      "%.6g)\n",
      out.num_triangles(), h.max, h.rms, bound, ideal_rms);
  EXPECT_LE(h.max, bound * (1 + 1e-6));
  EXPECT_GT(h.max, 0.25 * bound);  // the sampler finds the deep face interiors, not just vertices
  EXPECT_LT(h.rms, 2 * ideal_rms);
  EXPECT_LT(h.max, 0.01);  // 1% of the radius
}

TEST(MeshSimplify, NonManifoldInputIsAnErrorNamingTheFaces) {
  // Three triangles on one edge (0, 1): the third cannot join OpenMesh's halfedge structure.
  Mesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1};
  m.indices = {0, 1, 2, 1, 0, 3, 0, 1, 4};
  Mesh out;
  SimplifyReport report;
  std::string error;
  EXPECT_FALSE(simplify(m, with_ratio(0.5), &out, &report, &error));
  EXPECT_NE(error.find("1 of 3 faces could not be added"), std::string::npos) << error;
  EXPECT_FALSE(simplify(cube(), with_ratio(0.0), &out, &report, &error));
  EXPECT_NE(error.find("ratio"), std::string::npos) << error;
}

TEST(MeshSimplify, MaxQuadricErrorStopsEarly) {
  // A flat grid has zero quadric error inside and a cube's corners do not: with a tiny bound the
  // cube cannot lose any face, while the flat grid still decimates.
  Mesh out;
  SimplifyReport report;
  std::string error;
  SimplifyOptions options = with_ratio(0.1);
  options.max_quadric_error = 1e-12;
  ASSERT_TRUE(simplify(cube(), options, &out, &report, &error)) << error;
  EXPECT_EQ(out.num_triangles(), 12u);
  ASSERT_TRUE(simplify(grid(20, 1.0, 0.0), options, &out, &report, &error)) << error;
  EXPECT_LT(out.num_triangles(), 800u);
  EXPECT_LT(report.hausdorff.max, 1e-6);  // flat stays flat
}

std::string largest_shared_ply() {
  std::string best;
  uintmax_t best_size = 0;
  for (const auto& entry :
       std::filesystem::recursive_directory_iterator(testing_support::shared_dir() + "/scenes")) {
    if (!entry.is_regular_file() || entry.path().extension() != ".ply") continue;
    if (entry.file_size() > best_size) best_size = entry.file_size(), best = entry.path().string();
  }
  return best;
}

TEST(MeshSimplify, RealSharedMeshToAQuarter) {
  const std::string path = largest_shared_ply();
  ASSERT_FALSE(path.empty()) << "no .ply under the shared scenes";
  pbrtc::PlyMesh ply;
  pbrtc::PlyError ply_error;
  ASSERT_TRUE(pbrtc::read_ply(path, &ply, &ply_error)) << path << ": " << ply_error.message;
  Mesh mesh;
  mesh.positions = std::move(ply.positions);
  mesh.normals = std::move(ply.normals);
  mesh.uvs = std::move(ply.uvs);
  mesh.indices = std::move(ply.indices);
  mesh.face_indices = std::move(ply.face_indices);

  SimplifyOptions options = with_ratio(0.25);
  Mesh out;
  std::string error;
  {
    SimplifyOptions unmeasured = options;
    unmeasured.measure = false;
    const auto t0 = std::chrono::steady_clock::now();
    ASSERT_TRUE(simplify(mesh, unmeasured, &out, nullptr, &error)) << path << ": " << error;
    std::printf("decimation alone: %.2f s\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  SimplifyReport report;
  const auto start = std::chrono::steady_clock::now();
  ASSERT_TRUE(simplify(mesh, options, &out, &report, &error)) << path << ": " << error;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double diag = bbox_diagonal(mesh);
  std::printf(
      "%s: faces %zu -> %zu, vertices %zu -> %zu, Hausdorff max %.6g (%.4f%% of diag "
      "%.6g) rms %.6g (%.5f%%), %zu samples, %.2f s with measurement\n",
      path.c_str(), report.faces_before, report.faces_after, report.vertices_before,
      report.vertices_after, report.hausdorff.max, 100 * report.hausdorff.max / diag, diag,
      report.hausdorff.rms, 100 * report.hausdorff.rms / diag, report.hausdorff.samples, seconds);
  EXPECT_NEAR(double(report.faces_after), 0.25 * double(report.faces_before),
              0.01 * double(report.faces_before));
  ASSERT_TRUE(report.measured);
  EXPECT_EQ(report.bbox_diagonal, diag);

  // The reported figure is what hausdorff_distance measures on the written result...
  const HausdorffResult same = hausdorff_distance(mesh, out, options.hausdorff);
  EXPECT_EQ(report.hausdorff.max, same.max);
  EXPECT_EQ(report.hausdorff.rms, same.rms);
  // ... and an independent sampling (other seed, twice the samples) agrees with it.
  const HausdorffResult again = hausdorff_distance(mesh, out, HausdorffOptions{200000, 77});
  std::printf("re-measured: max %.6g rms %.6g\n", again.max, again.rms);
  EXPECT_NEAR(again.max, report.hausdorff.max, 0.1 * report.hausdorff.max + 1e-5 * diag);
  EXPECT_NEAR(again.rms, report.hausdorff.rms, 0.05 * report.hausdorff.rms);
  EXPECT_LT(report.hausdorff.max, 0.01 * diag);
}

}  // namespace
}  // namespace meshtools
