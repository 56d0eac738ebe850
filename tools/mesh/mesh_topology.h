// tools/mesh/mesh_topology.h — topology problems of a plain indexed triangle mesh.
//
// Counted on Mesh's index triples, not on an OpenMesh halfedge mesh: a halfedge structure cannot
// hold an edge with three faces or a vertex with two fans (OpenMesh duplicates their vertices on
// import), and those are exactly what `pbrt-mesh info` has to find. Every count is exact and
// independent of vertex and face order. Thread safety: a pure function of its argument.
#pragma once

#include <cstddef>

#include "tools/mesh/mesh.h"

namespace meshtools {

struct TopologyCounts {
  size_t edges = 0;                  // distinct undirected edges of the non-degenerate faces
  size_t boundary_edges = 0;         // edges of exactly one face
  size_t boundary_loops = 0;         // connected components of the boundary edges
  size_t non_manifold_edges = 0;     // edges of more than two faces, or of two faces that
                                     // traverse it the same way (inconsistent orientation)
  size_t non_manifold_vertices = 0;  // vertices whose faces form more than one fan (faces
                                     // around the vertex linked through shared edges)
  size_t degenerate_faces = 0;       // a vertex index repeated, or zero area
  size_t duplicate_faces = 0;        // same vertex set as an earlier face (order ignored)
  size_t unreferenced_vertices = 0;  // in no face
};

// Indices must be in range (read_mesh guarantees it). Faces that repeat an index take no part
// in the edge, loop and fan counts (they have no proper edges); zero-area faces with three
// distinct indices do, since they still connect their vertices.
TopologyCounts count_topology(const Mesh& mesh);

}  // namespace meshtools
