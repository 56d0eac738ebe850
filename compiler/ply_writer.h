// compiler/ply_writer.h — writes triangle meshes as binary little-endian PLY.
//
// The counterpart of ply_reader.h, for pbrtc --dump and the mesh tools: what
// it writes, read_ply reads back bit for bit (positions, normals, uv as u/v,
// triangles as vertex_indices, and pbrt-v3's per-face face_indices). Written
// to a temporary file and renamed, so a failure leaves no partial file.
#pragma once

#include <cstdint>
#include <string>

#include "format/mesh_arrays.h"

namespace pbrtc {

[[nodiscard]] bool write_ply(const std::string& path, const pbrta::MeshArrays& mesh,
                             std::string* error);

}  // namespace pbrtc
