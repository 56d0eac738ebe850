// format/ply_writer.h — writes triangle meshes as binary little-endian PLY.
//
// The counterpart of ply_reader.h, for pbrtc --dump and the mesh tools: what
// it writes, read_ply reads back bit for bit (positions, normals, uv as u/v,
// triangles as vertex_indices, and pbrt-v3's per-face face_indices). Written
// to a temporary file and renamed, so a failure leaves no partial file.
#pragma once

#include <cstdint>
#include <string>

namespace pbrta {

struct PlyView {
  const float* positions = nullptr;  // 3 per vertex
  const float* normals = nullptr;    // 3 per vertex, or null
  const float* uvs = nullptr;        // 2 per vertex, or null
  const uint32_t* indices = nullptr; // 3 per triangle
  const int32_t* face_indices = nullptr;  // 1 per triangle, or null
  uint64_t num_vertices = 0;
  uint64_t num_triangles = 0;
};

[[nodiscard]] bool write_ply(const std::string& path, const PlyView& mesh, std::string* error);

}  // namespace pbrta
