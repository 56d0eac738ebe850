// tests/compiler/refine_test.cpp — loopsubdiv, nurbs and heightfield refined at compile time.
//
// Loop subdivision is checked by its invariants (four triangles per triangle per level, a closed
// mesh stays closed and consistently wound, a vertex's limit position does not depend on the
// level) and against limit weights worked out by hand; NURBS against surfaces known in closed
// form (a plane, a quadratic B-spline patch, a rational circle); heightfields exactly. Invalid
// input gives an error at the shape. The shared scenes that use these shapes compile to meshes
// of the expected size, and the archive records where a refined mesh came from.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "compiler/archive_builder.h"
#include "compiler/diagnostics.h"
#include "compiler/refine.h"
#include "compiler/scene_builder.h"
#include "format/scene_archive.h"
#include "test_support.h"

namespace pbrtc {
namespace {

struct Build {
  SourceFiles files;
  Diagnostics diag{&files};
  SceneDesc scene;
  bool ok = false;

  explicit Build(const std::string& world) {
    ok = build_scene_from_string("scene.pbrt", "WorldBegin\n" + world + "WorldEnd\n",
                                 "/nonexistent-pbrtc", &files, &diag, &scene);
  }
  std::string report() const {
    std::string r;
    for (const Diagnostic& d : diag.all()) r += d.text + "\n";
    return r;
  }
  // The mesh of shape i (which must have one).
  const TriangleMesh& mesh(size_t i = 0) const {
    return scene.meshes.at(size_t(scene.shapes.at(i).mesh));
  }
};

// Compiles a scene with one shape that must be rejected; returns the one error's text.
std::string error_of(const std::string& shape) {
  Build b(shape);
  EXPECT_FALSE(b.ok);
  EXPECT_TRUE(b.scene.shapes.empty());
  EXPECT_EQ(b.diag.error_count(), 1) << b.report();
  return b.diag.all().empty() ? "" : b.diag.all().back().text;
}

struct Vec {
  double x, y, z;
};
Vec sub(Vec a, Vec b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
Vec cross(Vec a, Vec b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
double dot(Vec a, Vec b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
double length(Vec a) {
  return std::sqrt(dot(a, a));
}
Vec point(const TriangleMesh& m, size_t i) {
  return {m.P[3 * i], m.P[3 * i + 1], m.P[3 * i + 2]};
}
Vec normal(const TriangleMesh& m, size_t i) {
  return {m.N[3 * i], m.N[3 * i + 1], m.N[3 * i + 2]};
}
// The normal the winding of triangle t implies.
Vec winding_normal(const TriangleMesh& m, size_t t) {
  Vec a = point(m, m.indices[3 * t]), b = point(m, m.indices[3 * t + 1]),
      c = point(m, m.indices[3 * t + 2]);
  return cross(sub(b, a), sub(c, a));
}

// Every undirected edge is used by exactly two triangles, once in each direction.
void expect_closed_and_consistent(const TriangleMesh& m) {
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (size_t t = 0; t < m.num_triangles(); ++t)
    for (int k = 0; k < 3; ++k)
      ++directed[{m.indices[3 * t + size_t(k)], m.indices[3 * t + size_t(k + 1) % 3]}];
  for (const auto& [e, n] : directed) {
    EXPECT_EQ(n, 1) << "edge " << e.first << "->" << e.second;
    auto it = directed.find({e.second, e.first});
    EXPECT_TRUE(it != directed.end() && it->second == 1) << "edge " << e.first << "-" << e.second;
  }
}

// ---- loopsubdiv ------------------------------------------------------------------------------

// A regular tetrahedron, wound counter-clockwise seen from outside.
const float kTetraP[] = {1, 1, 1, -1, -1, 1, -1, 1, -1, 1, -1, -1};
const int32_t kTetraIndices[] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};

TriangleMesh subdivide_tetra(int levels) {
  TriangleMesh m;
  std::string error;
  EXPECT_TRUE(loop_subdivide(levels, kTetraIndices, 12, kTetraP, 4, &m, &error)) << error;
  return m;
}

TEST(LoopSubdiv, TetrahedronQuadruplesTrianglesAndStaysClosed) {
  for (int levels = 0; levels <= 4; ++levels) {
    SCOPED_TRACE(levels);
    TriangleMesh m = subdivide_tetra(levels);
    size_t triangles = size_t(4) << (2 * levels);
    ASSERT_EQ(m.num_triangles(), triangles);
    // Euler: V - E + F = 2 with E = 3F/2.
    EXPECT_EQ(m.num_vertices(), triangles / 2 + 2);
    EXPECT_EQ(m.N.size(), m.P.size());
    EXPECT_TRUE(m.uv.empty());
    EXPECT_EQ(m.refine_level, uint32_t(levels));
    expect_closed_and_consistent(m);
    for (size_t i = 0; i < m.num_vertices(); ++i) {
      // The limit surface lies inside the control polyhedron (all weights are positive).
      Vec p = point(m, i);
      for (size_t t = 0; t < 4; ++t) {
        Vec a{kTetraP[3 * kTetraIndices[3 * t]], kTetraP[3 * kTetraIndices[3 * t] + 1],
              kTetraP[3 * kTetraIndices[3 * t] + 2]};
        Vec b{kTetraP[3 * kTetraIndices[3 * t + 1]], kTetraP[3 * kTetraIndices[3 * t + 1] + 1],
              kTetraP[3 * kTetraIndices[3 * t + 1] + 2]};
        Vec c{kTetraP[3 * kTetraIndices[3 * t + 2]], kTetraP[3 * kTetraIndices[3 * t + 2] + 1],
              kTetraP[3 * kTetraIndices[3 * t + 2] + 2]};
        EXPECT_LT(dot(sub(p, a), cross(sub(b, a), sub(c, a))), 1e-6) << "vertex " << i;
      }
    }
  }
}

TEST(LoopSubdiv, LimitPositionsDoNotDependOnTheLevel) {
  // Vertex i of one level is vertex i of the next, and its limit position is the same point.
  for (int levels = 0; levels < 4; ++levels) {
    TriangleMesh coarse = subdivide_tetra(levels), fine = subdivide_tetra(levels + 1);
    for (size_t i = 0; i < coarse.P.size(); ++i)
      EXPECT_NEAR(coarse.P[i], fine.P[i], 1e-5) << "level " << levels << " float " << i;
  }
}

TEST(LoopSubdiv, NormalsFollowTheLimitSurfaceAgainstTheWinding) {
  // pbrt-v3's limit tangents turn clockwise seen from the side the triangles wind
  // counter-clockwise, so S x T points to the other side: inward for this outward-wound
  // tetrahedron. (pbrt-v3 then orients the triangles' geometric normals by these.)
  TriangleMesh m = subdivide_tetra(3);
  for (size_t i = 0; i < m.num_vertices(); ++i) {
    Vec n = normal(m, i);
    ASSERT_GT(length(n), 1e-6) << "vertex " << i;
    EXPECT_LT(dot(n, point(m, i)), 0) << "vertex " << i;
  }
  for (size_t t = 0; t < m.num_triangles(); ++t) {
    Vec w = winding_normal(m, t);
    for (int k = 0; k < 3; ++k) {
      Vec n = normal(m, m.indices[3 * t + size_t(k)]);
      EXPECT_LT(dot(n, w) / (length(n) * length(w)), -0.8) << "triangle " << t;
    }
  }
}

TEST(LoopSubdiv, LevelZeroKeepsTheTrianglesAndMovesToTheLimit) {
  TriangleMesh m = subdivide_tetra(0);
  ASSERT_EQ(m.indices.size(), 12u);
  for (size_t i = 0; i < 12; ++i) EXPECT_EQ(m.indices[i], uint32_t(kTetraIndices[i]));
  // Valence 3: gamma = 1 / (3 + 3 / (8 * 3/16)) = 1/5, so the limit is 2/5 p + 1/5 (others).
  for (size_t v = 0; v < 4; ++v) {
    for (int c = 0; c < 3; ++c) {
      double others = 0;
      for (size_t w = 0; w < 4; ++w)
        if (w != v) others += kTetraP[3 * w + size_t(c)];
      EXPECT_NEAR(m.P[3 * v + size_t(c)], 0.4 * kTetraP[3 * v + size_t(c)] + 0.2 * others, 1e-6);
    }
  }
}

// A 5 x 5 grid in the z = 0 plane, every cell split along the same diagonal, so every interior
// vertex has valence 6 and every boundary vertex but the corners valence 4.
void grid(std::vector<float>* P, std::vector<int32_t>* indices) {
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 5; ++x) P->insert(P->end(), {float(x), float(y), 0.f});
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) {
      int32_t a = y * 5 + x;
      indices->insert(indices->end(), {a, a + 1, a + 6, a, a + 6, a + 5});
    }
  }
}

TEST(LoopSubdiv, PlanarGridStaysPlanar) {
  std::vector<float> P;
  std::vector<int32_t> indices;
  grid(&P, &indices);
  TriangleMesh m;
  std::string error;
  ASSERT_TRUE(loop_subdivide(2, indices.data(), indices.size(), P.data(), 25, &m, &error)) << error;
  EXPECT_EQ(m.num_triangles(), 32u * 16u);
  for (size_t i = 0; i < m.num_vertices(); ++i) {
    EXPECT_EQ(m.P[3 * i + 2], 0.f) << "vertex " << i;
    Vec n = normal(m, i);
    // Counter-clockwise seen from +z, so the limit normal is -z (see above).
    EXPECT_NEAR(n.z / length(n), -1, 1e-6) << "vertex " << i;
  }
  // The middle vertex's neighbourhood is symmetric about it, so its limit is itself.
  EXPECT_NEAR(m.P[3 * 12], 2, 1e-6);  // the middle vertex, x
  EXPECT_NEAR(m.P[3 * 12 + 1], 2, 1e-6);
}

TEST(LoopSubdiv, LimitPositionsMatchHandComputedWeights) {
  std::vector<float> P;
  std::vector<int32_t> indices;
  grid(&P, &indices);
  P[3 * 12 + 2] = 1;  // lift the middle (interior) vertex
  P[3 * 2 + 2] = 1;   // and the middle of the bottom edge (boundary, valence 4)
  for (int levels : {0, 1, 3}) {
    SCOPED_TRACE(levels);
    TriangleMesh m;
    std::string error;
    ASSERT_TRUE(loop_subdivide(levels, indices.data(), indices.size(), P.data(), 25, &m, &error));
    // Interior valence 6: gamma = 1 / (6 + 3 / (8 / 16)) = 1/12; the limit is
    // (1 - 6/12) p + 1/12 of each neighbour.
    EXPECT_NEAR(m.P[3 * 12 + 2], 0.5, 1e-6);
    // Vertex 13 neighbours the middle: 1/12 of its height.
    EXPECT_NEAR(m.P[3 * 13 + 2], 1.0 / 12, 1e-6);
    // Vertex 7 is interior and neighbours both lifted vertices.
    EXPECT_NEAR(m.P[3 * 7 + 2], 2.0 / 12, 1e-6);
    if (levels == 0) {
      // Boundary: pbrt-v3 takes 3/5 p + 1/5 of each neighbour along the boundary. (The cubic
      // B-spline the boundary rules converge to has 2/3 and 1/6, so unlike the interior rule
      // this one moves with the level; pbrt-v3 does that too.)
      EXPECT_NEAR(m.P[3 * 2 + 2], 0.6, 1e-6);
      EXPECT_NEAR(m.P[3 * 1 + 2], 0.2, 1e-6);
      EXPECT_NEAR(m.P[3 * 3 + 2], 0.2, 1e-6);
    }
  }
}

TEST(LoopSubdiv, SceneShapeUsesLevelsAndItsAlias) {
  const std::string tetra =
      "\"point P\" [1 1 1  -1 -1 1  -1 1 -1  1 -1 -1] "
      "\"integer indices\" [0 1 2  0 3 1  0 2 3  1 3 2]\n";
  {
    Build b("Shape \"loopsubdiv\" " + tetra);
    ASSERT_TRUE(b.ok) << b.report();
    EXPECT_EQ(b.mesh().num_triangles(), 4u * 64u);  // default: 3 levels
    EXPECT_EQ(b.mesh().refine_level, 3u);
    // The bulk arrays stay with the shape.
    uint32_t n = 0;
    EXPECT_NE(b.scene.shapes[0].params.get_floats("P", &n), nullptr);
    EXPECT_EQ(n, 4u);
  }
  {
    Build b("Shape \"loopsubdiv\" \"integer nlevels\" [1] " + tetra);
    ASSERT_TRUE(b.ok) << b.report();
    EXPECT_EQ(b.mesh().num_triangles(), 16u);
    EXPECT_EQ(b.mesh().refine_level, 1u);
  }
  {
    Build b("Shape \"loopsubdiv\" \"integer levels\" [2] " + tetra);
    ASSERT_TRUE(b.ok) << b.report();
    EXPECT_EQ(b.mesh().num_triangles(), 64u);
    EXPECT_EQ(count_scene(b.scene).triangles, 64u);
  }
}

TEST(LoopSubdiv, OpenMeshesSubdivideWithBoundaryRules) {
  // One triangle: every vertex is a boundary vertex of valence 2.
  Build b(
      "Shape \"loopsubdiv\" \"integer levels\" [2] \"point P\" [0 0 0  1 0 0  0 1 0] "
      "\"integer indices\" [0 1 2]\n");
  ASSERT_TRUE(b.ok) << b.report();
  const TriangleMesh& m = b.mesh();
  EXPECT_EQ(m.num_triangles(), 16u);
  EXPECT_EQ(m.num_vertices(), 15u);
  for (size_t i = 0; i < m.num_vertices(); ++i) {
    EXPECT_EQ(m.P[3 * i + 2], 0.f);
    Vec n = normal(m, i);
    ASSERT_GT(length(n), 0) << "vertex " << i;
    EXPECT_NEAR(n.z / length(n), -1, 1e-6) << "vertex " << i;
  }
  // A corner's limit at level 0: 3/5 of itself and 1/5 of each other corner.
  TriangleMesh level0;
  std::string error;
  const float P[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const int32_t idx[] = {0, 1, 2};
  ASSERT_TRUE(loop_subdivide(0, idx, 3, P, 3, &level0, &error));
  EXPECT_NEAR(level0.P[0], 0.2, 1e-6);
  EXPECT_NEAR(level0.P[1], 0.2, 1e-6);
}

TEST(LoopSubdiv, InvalidInputIsReportedAtTheShape) {
  EXPECT_NE(error_of("Shape \"loopsubdiv\" \"point P\" [0 0 0 1 0 0 0 1 0] "
                     "\"integer indices\" [0 1 3]\n")
                .find("scene.pbrt:2:1: error: loopsubdiv index 3 (entry 2) is out of range: "
                      "3 vertices"),
            std::string::npos);
  EXPECT_NE(error_of("Shape \"loopsubdiv\" \"point P\" [0 0 0 1 0 0 0 1 0] "
                     "\"integer indices\" [0 1 2 0]\n")
                .find("loopsubdiv has 4 indices, not a multiple of 3"),
            std::string::npos);
  EXPECT_NE(error_of("Shape \"loopsubdiv\" \"point P\" [0 0 0 1 0 0 0 1 0 5 5 5] "
                     "\"integer indices\" [0 1 2]\n")
                .find("loopsubdiv vertex 3 is not used by any triangle"),
            std::string::npos);
  EXPECT_NE(error_of("Shape \"loopsubdiv\" \"point P\" [0 0 0 1 0 0 0 1 0 1 1 0] "
                     "\"integer indices\" [0 1 2  0 1 3  0 2 3  1 3 2]\n")
                .find("loopsubdiv triangles 0 and 1 run edge 0-1 in the same direction"),
            std::string::npos);
  EXPECT_NE(error_of("Shape \"loopsubdiv\" \"point P\" [0 0 0 1 0 0 0 1 0 0 -1 0 0 0 1] "
                     "\"integer indices\" [0 1 2  1 0 3  0 1 4]\n")
                .find("loopsubdiv edge 0-1 is shared by more than two triangles"),
            std::string::npos);
  EXPECT_NE(error_of("Shape \"loopsubdiv\" \"point P\" [0 0 0 1 0 0 0 1 0] "
                     "\"integer indices\" [0 1 1]\n")
                .find("loopsubdiv triangle 0 uses vertex 1 twice"),
            std::string::npos);
  EXPECT_NE(error_of("Shape \"loopsubdiv\" \"integer levels\" [-1] \"point P\" [0 0 0 1 0 0 0 1 0] "
                     "\"integer indices\" [0 1 2]\n")
                .find("loopsubdiv \"levels\" is -1"),
            std::string::npos);
  EXPECT_NE(error_of("Shape \"loopsubdiv\" \"integer levels\" [20] \"point P\" [0 0 0 1 0 0 0 1 0] "
                     "\"integer indices\" [0 1 2]\n")
                .find("loopsubdiv with 20 levels would make more than"),
            std::string::npos);
}

// ---- nurbs -----------------------------------------------------------------------------------

std::string grid_param(const char* name, float t0, float t1) {
  return "\"float " + std::string(name) + "0\" [" + std::to_string(t0) + "] \"float " +
         std::string(name) + "1\" [" + std::to_string(t1) + "] ";
}

TEST(Nurbs, BilinearPatchIsThePlane) {
  Build b(
      "Shape \"nurbs\" \"integer nu\" [2] \"integer nv\" [2] \"integer uorder\" [2] "
      "\"integer vorder\" [2] \"float uknots\" [0 0 1 1] \"float vknots\" [0 0 1 1] "
      "\"point P\" [0 0 0  2 0 0  0 3 0  2 3 0]\n");
  ASSERT_TRUE(b.ok) << b.report();
  const TriangleMesh& m = b.mesh();
  const size_t n = size_t(kNurbsDice);
  ASSERT_EQ(m.num_vertices(), n * n);
  ASSERT_EQ(m.num_triangles(), 2 * (n - 1) * (n - 1));
  ASSERT_EQ(m.uv.size(), 2 * n * n);
  ASSERT_EQ(m.N.size(), 3 * n * n);
  EXPECT_EQ(m.refine_level, uint32_t(kNurbsDice));
  for (size_t v = 0; v < n; ++v) {
    for (size_t u = 0; u < n; ++u) {
      size_t i = v * n + u;
      float fu = float(u) / float(n - 1), fv = float(v) / float(n - 1);
      EXPECT_FLOAT_EQ(m.uv[2 * i], (1 - fu) * 0 + fu * 1);
      EXPECT_FLOAT_EQ(m.uv[2 * i + 1], fv);
      EXPECT_NEAR(m.P[3 * i], 2 * m.uv[2 * i], 1e-6);
      EXPECT_NEAR(m.P[3 * i + 1], 3 * m.uv[2 * i + 1], 1e-6);
      EXPECT_EQ(m.P[3 * i + 2], 0.f);
      EXPECT_EQ(m.N[3 * i], 0.f);
      EXPECT_EQ(m.N[3 * i + 1], 0.f);
      EXPECT_FLOAT_EQ(m.N[3 * i + 2], 1.f);
    }
  }
  // pbrt-v3's triangles per cell: (u,v) (u+1,v) (u+1,v+1) and (u,v) (u+1,v+1) (u,v+1), which
  // wind counter-clockwise in (u, v), along dp/du x dp/dv.
  EXPECT_EQ(m.indices[0], 0u);
  EXPECT_EQ(m.indices[1], 1u);
  EXPECT_EQ(m.indices[2], uint32_t(n + 1));
  EXPECT_EQ(m.indices[3], 0u);
  EXPECT_EQ(m.indices[4], uint32_t(n + 1));
  EXPECT_EQ(m.indices[5], uint32_t(n));
  for (size_t t = 0; t < m.num_triangles(); ++t) EXPECT_GT(winding_normal(m, t).z, 0);
}

// A quadratic B-spline patch over the clamped uniform knots 0 0 0 .5 1 1 1. The x and y control
// values are the Greville abscissae (0, .25, .75, 1), so x = u and y = v, and z = A(u) B(v) with
// A, B the splines of the values a, b below. On [0, .5] the basis is (1-2u)^2, 4u - 6u^2, 2u^2;
// at u = .25 that is .25, .625, .125 (and mirrored at v = .75).
TEST(Nurbs, QuadraticPatchMatchesTheSplineAtAChosenPoint) {
  const float g[] = {0, .25f, .75f, 1};
  const float a[] = {1, 3, 0, 2}, bv[] = {0, 1, 4, 2};
  std::string P;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i)
      P += std::to_string(g[i]) + " " + std::to_string(g[j]) + " " + std::to_string(a[i] * bv[j]) +
           "  ";
  Build b(
      "Shape \"nurbs\" \"integer nu\" [4] \"integer nv\" [4] \"integer uorder\" [3] "
      "\"integer vorder\" [3] \"float uknots\" [0 0 0 .5 1 1 1] "
      "\"float vknots\" [0 0 0 .5 1 1 1] " +
      grid_param("u", .25f, 1) + grid_param("v", .75f, 1) + "\"point P\" [" + P + "]\n");
  ASSERT_TRUE(b.ok) << b.report();
  const TriangleMesh& m = b.mesh();
  // Vertex 0 is (u0, v0) = (.25, .75): A = .25*1 + .625*3 + .125*0 = 2.125, A' = 1;
  // B = .125*1 + .625*4 + .25*2 = 3.125, B' = -1.
  EXPECT_FLOAT_EQ(m.uv[0], .25f);
  EXPECT_FLOAT_EQ(m.uv[1], .75f);
  EXPECT_NEAR(m.P[0], .25, 1e-6);
  EXPECT_NEAR(m.P[1], .75, 1e-6);
  EXPECT_NEAR(m.P[2], 2.125 * 3.125, 1e-5);
  // dp/du = (1, 0, A'B), dp/dv = (0, 1, AB'): the normal is (-A'B, -AB', 1) normalized.
  Vec want{-3.125, 2.125, 1};
  double len = length(want);
  EXPECT_NEAR(m.N[0], want.x / len, 1e-5);
  EXPECT_NEAR(m.N[1], want.y / len, 1e-5);
  EXPECT_NEAR(m.N[2], want.z / len, 1e-5);
  // The last vertex is the corner (1, 1): the corner control point.
  size_t last = m.num_vertices() - 1;
  EXPECT_NEAR(m.P[3 * last], 1, 1e-6);
  EXPECT_NEAR(m.P[3 * last + 1], 1, 1e-6);
  EXPECT_NEAR(m.P[3 * last + 2], 4, 1e-5);
  // Every point lies on the surface x = u, y = v.
  for (size_t i = 0; i < m.num_vertices(); ++i) {
    EXPECT_NEAR(m.P[3 * i], m.uv[2 * i], 1e-6);
    EXPECT_NEAR(m.P[3 * i + 1], m.uv[2 * i + 1], 1e-6);
  }
}

TEST(Nurbs, HomogeneousControlPointsMakeACircle) {
  // A quarter circle in u (weights 1, 1/sqrt2, 1; "Pw" holds x w, y w, z w, w), extruded
  // linearly in v.
  const double w = std::sqrt(0.5);
  std::string Pw;
  for (int z = 0; z < 2; ++z) {
    Pw += "1 0 " + std::to_string(z) + " 1  ";
    Pw += std::to_string(w) + " " + std::to_string(w) + " " + std::to_string(z * w) + " " +
          std::to_string(w) + "  ";
    Pw += "0 1 " + std::to_string(z) + " 1  ";
  }
  Build b(
      "Shape \"nurbs\" \"integer nu\" [3] \"integer nv\" [2] \"integer uorder\" [3] "
      "\"integer vorder\" [2] \"float uknots\" [0 0 0 1 1 1] \"float vknots\" [0 0 1 1] "
      "\"float Pw\" [" +
      Pw + "]\n");
  ASSERT_TRUE(b.ok) << b.report();
  const TriangleMesh& m = b.mesh();
  ASSERT_EQ(m.num_vertices(), size_t(kNurbsDice * kNurbsDice));
  for (size_t i = 0; i < m.num_vertices(); ++i) {
    double x = m.P[3 * i], y = m.P[3 * i + 1];
    EXPECT_NEAR(x * x + y * y, 1, 1e-5) << "vertex " << i;
    EXPECT_NEAR(m.P[3 * i + 2], m.uv[2 * i + 1], 1e-6);
    // The normal is horizontal and radial (dp/du turns towards +y, dp/dv is +z).
    EXPECT_NEAR(m.N[3 * i] * x + m.N[3 * i + 1] * y, 1, 1e-4) << "vertex " << i;
  }
}

TEST(Nurbs, InvalidInputIsReportedAtTheShape) {
  const std::string head = "Shape \"nurbs\" \"integer nu\" [2] \"integer nv\" [2] ";
  const std::string orders = "\"integer uorder\" [2] \"integer vorder\" [2] ";
  const std::string knots = "\"float uknots\" [0 0 1 1] \"float vknots\" [0 0 1 1] ";
  const std::string P = "\"point P\" [0 0 0  1 0 0  0 1 0  1 1 0]\n";
  EXPECT_NE(error_of(head + orders + "\"float uknots\" [0 0 1] \"float vknots\" [0 0 1 1] " + P)
                .find("scene.pbrt:2:1: error: nurbs \"uknots\" has 3 knots; it needs nu + uorder "
                      "= 4"),
            std::string::npos);
  EXPECT_NE(error_of(head + "\"integer uorder\" [1] \"integer vorder\" [2] " +
                     "\"float uknots\" [0 0 1] " + "\"float vknots\" [0 0 1 1] " + P)
                .find("nurbs \"uorder\" is 1; it must be at least 2"),
            std::string::npos);
  EXPECT_NE(error_of(head + "\"integer uorder\" [3] \"integer vorder\" [2] " +
                     "\"float uknots\" [0 0 0 1 1] \"float vknots\" [0 0 1 1] " + P)
                .find("nurbs \"nu\" is 2; it must be at least \"uorder\" (3)"),
            std::string::npos);
  EXPECT_NE(error_of(head + orders + "\"float uknots\" [0 1 0 1] \"float vknots\" [0 0 1 1] " + P)
                .find("nurbs \"uknots\" decreases at entry 2"),
            std::string::npos);
  EXPECT_NE(error_of(head + orders + knots + "\"float v1\" [2] " + P)
                .find("nurbs \"v1\" is 2, outside the knot range [0, 1]"),
            std::string::npos);
  EXPECT_NE(error_of(head + orders + knots + "\"point P\" [0 0 0  1 0 0  0 1 0]\n")
                .find("nurbs \"point P\" has 3 control points; nu * nv = 4"),
            std::string::npos);
  EXPECT_NE(error_of(head + orders + knots + "\"float Pw\" [0 0 0 1  1 0 0 1  0 1 0 1  1 1 0]\n")
                .find("nurbs \"float Pw\" has 15 numbers, not a multiple of 4"),
            std::string::npos);
  EXPECT_NE(error_of(head + orders + knots + "\n")
                .find("nurbs needs control points \"point P\" or \"float Pw\""),
            std::string::npos);
  EXPECT_NE(error_of(head + orders + knots + "\"float Pw\" [0 0 0 0  1 0 0 1  0 1 0 1  1 1 0 1]\n")
                .find("nurbs evaluates to a non-finite point"),
            std::string::npos);
}

// ---- heightfield -----------------------------------------------------------------------------

TEST(Heightfield, GridPositionsUvAndTriangles) {
  Build b(
      "Shape \"heightfield\" \"integer nu\" [3] \"integer nv\" [2] "
      "\"float Pz\" [0 1 2 3 4 5]\n");
  ASSERT_TRUE(b.ok) << b.report();
  const TriangleMesh& m = b.mesh();
  ASSERT_EQ(m.num_vertices(), 6u);
  const std::vector<float> P = {0, 0, 0, .5f, 0, 1, 1, 0, 2, 0, 1, 3, .5f, 1, 4, 1, 1, 5};
  const std::vector<float> uv = {0, 0, .5f, 0, 1, 0, 0, 1, .5f, 1, 1, 1};
  const std::vector<uint32_t> indices = {0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4};
  EXPECT_EQ(m.P, P);
  EXPECT_EQ(m.uv, uv);
  EXPECT_EQ(m.indices, indices);
  EXPECT_TRUE(m.N.empty());
  EXPECT_EQ(m.refine_level, 0u);
}

TEST(Heightfield, InvalidInputIsReportedAtTheShape) {
  EXPECT_NE(error_of("Shape \"heightfield\" \"integer nu\" [1] \"integer nv\" [2] "
                     "\"float Pz\" [0 1]\n")
                .find("scene.pbrt:2:1: error: heightfield needs at least 2 x 2 points; \"nu\" is "
                      "1 and \"nv\" 2"),
            std::string::npos);
  EXPECT_NE(error_of("Shape \"heightfield\" \"integer nu\" [2] \"integer nv\" [2] "
                     "\"float Pz\" [0 1 2]\n")
                .find("heightfield \"float Pz\" has 3 heights; nu * nv = 4"),
            std::string::npos);
}

// ---- shared scenes and the archive -----------------------------------------------------------

struct SharedScene {
  SourceFiles files;
  Diagnostics diag{&files};
  SceneDesc scene;
  bool ok = false;
  explicit SharedScene(const std::string& relative) {
    ok = build_scene(testing_support::shared_dir() + "/scenes/" + relative, &files, &diag, &scene);
  }
  std::vector<size_t> shapes_of(std::string_view type) const {
    std::vector<size_t> out;
    for (size_t i = 0; i < scene.shapes.size(); ++i)
      if (scene.shapes[i].params.type_name() == type) out.push_back(i);
    return out;
  }
};

void expect_finite(const std::vector<float>& v) {
  for (float f : v) ASSERT_TRUE(std::isfinite(f));
}

TEST(RefineSharedScenes, LoopsubdivKilleroos) {
  for (const char* path : {"hm-shapes/pbrt-v3-rs/scenes/shapes/loopsubdiv.pbrt",
                           "v3-killeroo-simple/killeroo-simple.pbrt"}) {
    SCOPED_TRACE(path);
    SharedScene s(path);
    ASSERT_TRUE(s.ok);
    std::vector<size_t> shapes = s.shapes_of("loopsubdiv");
    ASSERT_FALSE(shapes.empty());
    for (size_t i : shapes) {
      const ShapeDesc& sh = s.scene.shapes[i];
      ASSERT_NE(sh.mesh, kNone);
      const TriangleMesh& m = s.scene.meshes[size_t(sh.mesh)];
      int levels = sh.params.get_int("levels");
      EXPECT_EQ(levels, 1);  // the killeroo says "integer nlevels" [1]
      EXPECT_EQ(m.refine_level, uint32_t(levels));
      uint32_t num_indices = 0, num_points = 0;
      ASSERT_NE(sh.params.get_floats("P", &num_points), nullptr);
      num_indices = sh.params.values[size_t(sh.params.slot("indices"))].count;
      EXPECT_EQ(m.num_triangles(), size_t(num_indices / 3) << (2 * levels));
      EXPECT_GT(m.num_vertices(), num_points);
      EXPECT_LT(m.num_vertices(), size_t(num_points) + 3 * num_indices / 2);
      EXPECT_EQ(m.N.size(), m.P.size());
      expect_finite(m.P);
      expect_finite(m.N);
      for (size_t v = 0; v < m.num_vertices(); ++v) ASSERT_GT(length(normal(m, v)), 0);
    }
  }
}

TEST(RefineSharedScenes, NurbsPatches) {
  for (auto [path, count] :
       {std::pair{"rs-nurbs/nurbs_3x3.pbrt", 1}, {"rs-blurred/blurred.pbrt", 4}}) {
    SCOPED_TRACE(path);
    SharedScene s(path);
    ASSERT_TRUE(s.ok);
    std::vector<size_t> shapes = s.shapes_of("nurbs");
    ASSERT_EQ(shapes.size(), size_t(count));
    for (size_t i : shapes) {
      const TriangleMesh& m = s.scene.meshes.at(size_t(s.scene.shapes[i].mesh));
      EXPECT_EQ(m.num_vertices(), size_t(kNurbsDice * kNurbsDice));
      EXPECT_EQ(m.num_triangles(), size_t(2 * (kNurbsDice - 1) * (kNurbsDice - 1)));
      EXPECT_EQ(m.refine_level, uint32_t(kNurbsDice));
      expect_finite(m.P);
      for (size_t v = 0; v < m.num_vertices(); ++v)
        EXPECT_NEAR(length(normal(m, v)), 1, 1e-5) << "vertex " << v;
      // Bicubic patches over [0, 1]: the corners of the grid are the corner control points.
      uint32_t np = 0;
      const float* P = s.scene.shapes[i].params.get_floats("P", &np);
      ASSERT_EQ(np, 16u);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(m.P[size_t(c)], P[c], 1e-5);
        EXPECT_NEAR(m.P[3 * (m.num_vertices() - 1) + size_t(c)], P[3 * 15 + c], 1e-5);
      }
    }
  }
}

TEST(RefineSharedScenes, ArchiveRecordsTheSourceShapeAndLevel) {
  const std::string path = testing_support::shared_dir() + "/scenes/rs-nurbs/nurbs_3x3.pbrt";
  SharedScene s("rs-nurbs/nurbs_3x3.pbrt");
  ASSERT_TRUE(s.ok);
  const std::string out = testing_support::scratch_dir("RefineArchive") + "/nurbs_3x3.pbrta";
  std::string error;
  ASSERT_TRUE(
      write_archive(s.scene, s.files, directory_of(path), out, ArchiveOptions{}, nullptr, &error))
      << error;
  pbrta::SceneArchive a;
  ASSERT_TRUE(a.load(out, 1, &error)) << error;
  ASSERT_EQ(a.scene().num_meshes, s.scene.meshes.size());
  int refined = 0;
  for (size_t i = 0; i < s.scene.shapes.size(); ++i) {
    const ShapeDesc& sh = s.scene.shapes[i];
    if (sh.mesh == kNone) continue;
    const pbrta::MeshRecord& r = a.meshes[uint32_t(sh.mesh)];
    if (sh.params.type_name() == "nurbs") {
      ++refined;
      EXPECT_EQ(r.source_shape, uint32_t(i));
      EXPECT_EQ(r.refine_level, uint32_t(kNurbsDice));
    } else {
      EXPECT_EQ(r.source_shape, pbrta::kNoIndex);
      EXPECT_EQ(r.refine_level, 0u);
    }
  }
  EXPECT_EQ(refined, 1);
}

}  // namespace
}  // namespace pbrtc
