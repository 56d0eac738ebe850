// format/mesh_arrays.h — a triangle mesh as views of flat arrays owned by the caller.
//
// The one way meshes are handed to the PLY writer and the Draco wrapper. arrays_of() views any
// mesh type whose vectors are named positions, normals, uvs, indices and face_indices (the PLY
// reader's PlyMesh, the mesh tools' Mesh); empty vectors become null pointers. A view lives no
// longer than the mesh it points into.
#pragma once

#include <cstddef>
#include <cstdint>

namespace pbrta {

struct MeshArrays {
  const float* positions = nullptr;       // 3 floats per vertex
  const float* normals = nullptr;         // nullptr, or 3 floats per vertex
  const float* uv = nullptr;              // nullptr, or 2 floats per vertex
  const uint32_t* indices = nullptr;      // 3 per triangle, each < num_vertices
  const int32_t* face_indices = nullptr;  // nullptr, or 1 per triangle
  size_t num_vertices = 0;
  size_t num_triangles = 0;
};

template <class M>
MeshArrays arrays_of(const M& m) {
  MeshArrays a;
  a.positions = m.positions.data();
  a.normals = m.normals.empty() ? nullptr : m.normals.data();
  a.uv = m.uvs.empty() ? nullptr : m.uvs.data();
  a.indices = m.indices.data();
  a.face_indices = m.face_indices.empty() ? nullptr : m.face_indices.data();
  a.num_vertices = m.positions.size() / 3;
  a.num_triangles = m.indices.size() / 3;
  return a;
}

}  // namespace pbrta
