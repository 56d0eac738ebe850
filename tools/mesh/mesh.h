// tools/mesh/mesh.h — the plain indexed triangle mesh the mesh tools pass around, and its I/O.
//
// One struct for every format: positions (3 floats per vertex), optional normals (3) and uv (2),
// triangles as uint32 index triples, optional per-triangle pbrt face indices. Polygons are
// triangulated on reading. Readers pick the format by file extension (case-insensitive):
// .ply (the project's one hardened PLY reader in format/), .drc (the one Draco wrapper in
// format/), .obj, .off, .stl, and .pbrt (a file of trianglemesh/plymesh shapes, through
// pbrtc's own front end: all shapes merged). Writers write the same set; .pbrt output is either
// an inline trianglemesh or a plymesh shape naming a .ply written beside it. Every function is
// reentrant; failures return false with a message naming the file and the reason, and no
// output file is left behind (files are written to a temporary name and renamed).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace meshtools {

struct Mesh {
  std::vector<float> positions;       // 3 per vertex
  std::vector<float> normals;         // empty or 3 per vertex
  std::vector<float> uvs;             // empty or 2 per vertex
  std::vector<uint32_t> indices;      // 3 per triangle
  std::vector<int32_t> face_indices;  // empty or 1 per triangle
  size_t num_vertices() const { return positions.size() / 3; }
  size_t num_triangles() const { return indices.size() / 3; }
};

enum class PbrtStyle { kInline, kPlymesh };

struct WriteOptions {
  bool ply_ascii = false;               // .ply: ASCII instead of binary little-endian
  PbrtStyle pbrt = PbrtStyle::kInline;  // .pbrt: inline trianglemesh or plymesh + .ply beside it
  int draco_bits = 14;            // .drc: position quantization bits (the flag pbrtc uses too)
  bool draco_sequential = false;  // .drc: keep vertex and face order
};

// Reads path by its extension. Reports progress on large meshes to stderr unless quiet. What
// the reader skipped but could read past (a PLY header line that is no keyword) is appended to
// *warnings, if given, as "path: what".
bool read_mesh(const std::string& path, Mesh* mesh, std::string* error, bool quiet = true,
               std::vector<std::string>* warnings = nullptr);
bool write_mesh(const std::string& path, const Mesh& mesh, const WriteOptions& options,
                std::string* error);

// Lower-case extension without the dot ("ply"), or "".
std::string extension_of(const std::string& path);

}  // namespace meshtools
