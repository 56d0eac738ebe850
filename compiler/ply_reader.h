// compiler/ply_reader.h — the one PLY triangle-mesh reader the project shares.
//
// Reads a PLY 1.0 file (ascii, binary_little_endian or binary_big_endian) into flat arrays, the
// way pbrt-v3's "plymesh" shape reads it: vertex positions x y z, optional normals nx ny nz,
// optional texture coordinates (u/v, s/t, texture_u/texture_v or texture_s/texture_t, first
// complete pair wins, as in pbrt-v3), the face list "vertex_indices" (or "vertex_index") and the
// optional per-face integer "face_indices". Triangles are kept as they are, quads are split into
// the same two triangles pbrt-v3 emits, and larger polygons are fan-triangulated (pbrt-v3 drops
// them with a warning; we keep them). Other elements and properties, lists included, are skipped.
//
// Ownership: the caller owns the PlyMesh; the reader fills it and keeps no reference to it or to
// the input bytes. Thread safety: the functions are stateless and reentrant; distinct calls may
// run concurrently on distinct meshes.
//
// Header lines that cannot change the layout (anything but format, element, property and
// end_header, such as Blender 2.4's bare "Created by ..." line) are skipped, each with a warning
// "header line N: skipped '<its first 40 bytes>' (not a PLY header keyword)"; comment and
// obj_info lines silently.
//
// Failure: the input is untrusted. Any problem (bad header, a count the file cannot hold,
// truncated data, a token that is not a number, a NaN or infinite value, an index out of range, a
// face with fewer than 3 vertices) makes the call return false, leave *mesh empty and put one
// message in *error naming what and where ("vertex 12: coordinate is NaN"). Messages do not
// repeat the file's path; the caller adds it. No count read from the file is used to allocate
// memory before it is checked against the bytes that remain, so a lying header fails fast.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace pbrtc {

// A triangle mesh as flat arrays, in the layout pbrt-v3's triangle mesh is built from.
struct PlyMesh {
  std::vector<float> positions;       // 3 floats per vertex: x, y, z
  std::vector<float> normals;         // empty, or 3 floats per vertex
  std::vector<float> uvs;             // empty, or 2 floats per vertex
  std::vector<uint32_t> indices;      // 3 vertex indices per triangle, each < num_vertices()
  std::vector<int32_t> face_indices;  // empty, or 1 per triangle (a polygon's value is repeated
                                      // for every triangle it is split into)

  size_t num_vertices() const;
  size_t num_triangles() const;
};

struct PlyError {
  std::string message;
};

// Reads the PLY file at path (in one block). Returns false and sets *error on any problem,
// including an unreadable file; *mesh is then empty. On success the warnings, if any, are
// appended to *warnings when it is given.
[[nodiscard]] bool read_ply(const std::string& path, PlyMesh* mesh, PlyError* error,
                            std::vector<std::string>* warnings = nullptr);

// Same as read_ply, from bytes in memory (for tests and fuzzers). bytes need not be
// NUL-terminated.
[[nodiscard]] bool parse_ply(std::string_view bytes, PlyMesh* mesh, PlyError* error,
                             std::vector<std::string>* warnings = nullptr);

}  // namespace pbrtc
