// tests/tools/mesh_topology_test.cpp — count_topology on small meshes made by hand.
#include <gtest/gtest.h>

#include "test_support.h"
#include "tools/mesh/mesh.h"
#include "tools/mesh/mesh_topology.h"

namespace meshtools {
namespace {

Mesh make(std::vector<float> p, std::vector<uint32_t> i) {
  Mesh m;
  m.positions = std::move(p);
  m.indices = std::move(i);
  return m;
}

// A consistently oriented closed tetrahedron.
Mesh tetrahedron() {
  return make({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2});
}

TEST(MeshTopology, ClosedTetrahedronHasNoBoundary) {
  const TopologyCounts c = count_topology(tetrahedron());
  EXPECT_EQ(c.edges, 6u);
  EXPECT_EQ(c.boundary_edges, 0u);
  EXPECT_EQ(c.boundary_loops, 0u);
  EXPECT_EQ(c.non_manifold_edges, 0u);
  EXPECT_EQ(c.non_manifold_vertices, 0u);
  EXPECT_EQ(c.degenerate_faces, 0u);
  EXPECT_EQ(c.duplicate_faces, 0u);
}

TEST(MeshTopology, FlippedFaceMakesInconsistentEdges) {
  Mesh m = tetrahedron();
  std::swap(m.indices[1], m.indices[2]);  // reverse the first face
  const TopologyCounts c = count_topology(m);
  EXPECT_EQ(c.non_manifold_edges, 3u);  // its three edges are traversed the same way twice
  EXPECT_EQ(c.boundary_loops, 0u);
}

TEST(MeshTopology, OpenQuadStripHasOneLoop) {
  // Three quads in a row (2x4 vertices), as six triangles.
  Mesh m;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 4; ++i) m.positions.insert(m.positions.end(), {float(i), float(j), 0});
  for (uint32_t i = 0; i < 3; ++i)
    m.indices.insert(m.indices.end(), {i, i + 1, i + 5, i, i + 5, i + 4});
  const TopologyCounts c = count_topology(m);
  EXPECT_EQ(c.boundary_edges, 8u);
  EXPECT_EQ(c.boundary_loops, 1u);
  EXPECT_EQ(c.non_manifold_edges, 0u);
  EXPECT_EQ(c.non_manifold_vertices, 0u);
}

TEST(MeshTopology, BowtieVertexHasTwoFans) {
  // Two triangles touching only at vertex 0.
  const Mesh m = make({0, 0, 0, 1, 0, 0, 1, 1, 0, -1, 0, 0, -1, -1, 0}, {0, 1, 2, 0, 3, 4});
  const TopologyCounts c = count_topology(m);
  EXPECT_EQ(c.non_manifold_vertices, 1u);
  EXPECT_EQ(c.non_manifold_edges, 0u);
  EXPECT_EQ(c.boundary_edges, 6u);
}

TEST(MeshTopology, EdgeSharedByThreeFaces) {
  const Mesh m = make({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1}, {0, 1, 2, 1, 0, 3, 0, 1, 4});
  const TopologyCounts c = count_topology(m);
  EXPECT_EQ(c.non_manifold_edges, 1u);
  EXPECT_EQ(c.non_manifold_vertices, 0u);  // the faces around 0 and 1 are linked by the edge
  EXPECT_EQ(c.boundary_edges, 6u);
}

TEST(MeshTopology, DegenerateAndDuplicateFaces) {
  Mesh m = tetrahedron();
  m.positions.insert(m.positions.end(), {2, 0, 0});  // vertex 4, on the line through 0 and 1
  m.indices.insert(m.indices.end(), {0, 0, 1});      // repeated index
  m.indices.insert(m.indices.end(), {0, 1, 4});      // zero area
  m.indices.insert(m.indices.end(), {2, 1, 0});      // same vertex set as face 0
  const TopologyCounts c = count_topology(m);
  EXPECT_EQ(c.degenerate_faces, 2u);
  EXPECT_EQ(c.duplicate_faces, 1u);
  EXPECT_EQ(c.unreferenced_vertices, 0u);
}

TEST(MeshTopology, UnreferencedVertices) {
  Mesh m = tetrahedron();
  m.positions.insert(m.positions.end(), {5, 5, 5, 6, 6, 6});
  EXPECT_EQ(count_topology(m).unreferenced_vertices, 2u);
}

}  // namespace
}  // namespace meshtools
