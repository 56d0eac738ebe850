// format/draco_codec.h — the project's one wrapper around Google's Draco mesh codec.
//
// Draco compresses a triangle mesh lossily: positions, normals and texture coordinates are
// quantized to a grid of 2^bits - 1 steps over their bounding box, and the default (edgebreaker)
// encoding reorders vertices and faces. pbrtc uses it for draco geometry sections
// (format/ARCHIVE.md section 5), the archive reader to decode them, and `plymesh` shapes may name
// a .drc file; future mesh tools share it.
//
// What goes through Draco: positions (POSITION, float x3), optional normals (NORMAL, x3),
// optional uv (TEX_COORD, x2), optional per-face int32 face indices (a GENERIC attribute of one
// int32 component, lossless) and the triangles. Tangents do not: a mesh that has them is the
// caller's to keep lossless. Draco stores attribute values per point, so a vertex shared by
// faces of different face indices is split into one point per face index; the decoder welds
// them back (see draco_decode).
//
// Ownership: MeshArrays only views the caller's arrays during the call; DecodedMesh owns its
// vectors. Thread safety: every function is reentrant and keeps no state; distinct calls may
// run concurrently. Encoding and decoding are deterministic: the same input gives the same
// bytes and the same mesh on any machine and whatever the thread count.
//
// Failure: functions return false with one message in *error ("position 12 is not finite",
// "draco: Failed to decode connectivity") and leave *out empty. The decoder treats its input as
// untrusted: it accepts only what a mesh encoder of this Draco bitstream version (2.2) writes,
// checks the counts in the stream's header against limits before Draco allocates anything for
// them, catches every exception Draco or the allocator throws, and checks every decoded index,
// count, type and value. What it cannot bound is Draco's own work on a stream crafted to pass
// those checks: parameters deeper in the stream (attribute and entropy-coder settings) are
// Draco's to check, and one flipped bit there has been seen to cost Draco 5 s and 220 MB on a
// 1.2 KB stream before it failed (fuzzing found a 5.5 KB archive costing 10 s: a texture
// coordinate predictor's orientation count, read from the stream, that Draco decodes bit by
// bit, and in this process accepts the stream after 6 s). The archive reader only hands Draco
// bytes whose checksum matched, only once every other section has decoded, and only in child
// processes with a budget of time and memory (format/isolated_jobs.h), so a forged file costs at
// most that budget and a crash in Draco is the child's; .drc files a user names (plymesh,
// pbrt-mesh) go through draco_decode_isolated, the same way.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "format/archive.h"
#include "format/mesh_arrays.h"

namespace pbrta {

// A triangle mesh as views of flat arrays owned by the caller.

inline constexpr int kDracoMinPositionBits = 8;
inline constexpr int kDracoMaxPositionBits = 30;

struct DracoOptions {
  // Positions: quantized over the bounding box's largest extent E to 2^bits - 1 steps, so each
  // coordinate moves by at most E / (2^bits - 1) / 2 (draco_position_bound).
  int position_bits = 14;
  // Fixed, whatever position_bits: normals to 10 bits of octahedral coordinates (well under a
  // degree), uv to 12 bits over the uv bounding box's largest extent (1/4095 of a [0,1] tile).
  int normal_bits = 10;
  int uv_bits = 12;
  // true: Draco's sequential encoding, which keeps the order of vertices and faces (indices
  // are stored almost as they are: larger output); false: edgebreaker, which reorders both.
  bool sequential = false;
  // Draco's compression level, 0 (fastest) to 10 (smallest); Draco's speed is 10 - level.
  int compression_level = 7;
};

// A decoded mesh, in the layout MeshArrays views.
struct DecodedMesh {
  std::vector<float> positions;
  std::vector<float> normals;  // empty or 3 per vertex
  std::vector<float> uv;       // empty or 2 per vertex
  std::vector<uint32_t> indices;
  std::vector<int32_t> face_indices;  // empty or 1 per triangle

  size_t num_vertices() const { return positions.size() / 3; }
  size_t num_triangles() const { return indices.size() / 3; }
  MeshArrays view() const;
};

// Bounds on what a stream may decode to, checked before Draco allocates for it.
struct DracoLimits {
  uint64_t max_vertices = uint64_t{1} << 28;
  uint64_t max_triangles = uint64_t{1} << 28;
};

// The limits for a stream of this many bytes when nothing else is known (a .drc file): what
// the archive's bound on a compressed section (format/archive_reader.h: 32768 times its size
// plus 1 MiB) can hold at 12 bytes per vertex and per triangle, at most 2^28 of either.
DracoLimits draco_limits_for(uint64_t stream_bytes);

// Whether a mesh is one Draco can carry: at least one triangle, at most 2^30 vertices and
// triangles, positions and indices present, every value finite, every index below the vertex
// count. False with the first problem in *error ("position of vertex 12 is not finite").
[[nodiscard]] bool draco_check_mesh(const MeshArrays& in, std::string* error);

// Encodes in (which must pass draco_check_mesh) with opt into *out.
[[nodiscard]] bool draco_encode(const MeshArrays& in, const DracoOptions& opt,
                                std::vector<uint8_t>* out, std::string* error);

// Decodes a Draco mesh stream into *out, within limits (the first form: draco_limits_for(size)).
// Attributes other than the four above are ignored (a .drc file from another tool may carry
// colours). When the stream has any attribute that is not kept per vertex (face indices,
// ignored ones), points whose positions, normals and uv are bitwise equal are welded into one
// vertex, in order of first appearance: that undoes the encoder's face-index splits, and also
// merges distinct vertices the quantization made equal. Otherwise every Draco point is a
// vertex, in Draco's order (sequential: the encoder's order). Edgebreaker may also split a
// non-manifold vertex or drop a degenerate triangle (one naming a vertex twice), so counts can
// change; the caller takes them from the result.
[[nodiscard]] bool draco_decode(const uint8_t* data, size_t size, DecodedMesh* out,
                                std::string* error);
[[nodiscard]] bool draco_decode(const uint8_t* data, size_t size, const DracoLimits& limits,
                                DecodedMesh* out, std::string* error);

// draco_decode (first form) in a child process with a budget of time and memory
// (format/isolated_jobs.h), for a .drc file a user names: a forged stream then costs at most
// the budget (about 1 s plus 5 us per byte), and a crash in Draco fails the call instead of
// the caller. Costs a fork (about a millisecond) over draco_decode.
[[nodiscard]] bool draco_decode_isolated(const uint8_t* data, size_t size, DecodedMesh* out,
                                         std::string* error);

// The most one coordinate of a vertex moves when positions are quantized to `bits`: half a
// quantization step, the bounding box's largest extent / (2^bits - 1) / 2 (0 for no vertices).
// The position quantization bits a stream was encoded with (0 when positions are not
// quantized). Checks the stream as draco_decode does.
[[nodiscard]] bool draco_position_bits(const uint8_t* data, size_t size, int* bits,
                                       std::string* error);

double draco_position_bound(const float* positions, size_t num_vertices, int bits);

// What float rounding in Draco's (de)quantization may add to that bound: it subtracts the
// minimum, scales, rounds, scales back and adds the minimum in float, each step within half an
// ulp of the coordinates' or the extent's magnitude; 4 ulps of the larger covers them all.
double draco_position_slack(const float* positions, size_t num_vertices);

// The displacement Draco caused: the largest per-axis (L-infinity) distance from a vertex of
// `decoded` to the nearest vertex of `original`. same_order says decoded vertex v came from
// original vertex v (sequential encoding, same vertex count): they are then compared directly.
// Otherwise each decoded vertex is looked up in a spatial hash of the originals with cells of
// twice `bound` (draco_position_bound: where its source must lie), and by brute force if no
// original is that close. nearest, when given, receives the matched original of each vertex.
double draco_max_displacement(const MeshArrays& original, const MeshArrays& decoded, double bound,
                              bool same_order, std::vector<uint32_t>* nearest = nullptr);

// The layout of a geometry section holding one mesh (ARCHIVE.md section 8): from r's
// num_vertices, num_triangles and flags, sets r's array offsets (positions at 0, then normals,
// tangents, uv, indices and face indices as present, each 16-byte aligned) and returns the
// section's raw size. A draco section decodes to exactly this layout.
uint64_t single_mesh_layout(MeshRecord* r);

// A decoded mesh's MeshRecord fields (counts, flags, offsets by single_mesh_layout) and its
// section bytes: the arrays at those offsets, zeros between them. raw holds exactly the
// section's raw size.
void draco_geometry_section(const DecodedMesh& mesh, MeshRecord* r, std::vector<uint8_t>* raw);

// Decodes a draco geometry section's stored bytes into dst, which has room for raw_size
// bytes: the layout single_mesh_layout gives for the decoded mesh, which must be raw_size bytes
// long. The vertex and triangle limits follow from raw_size. counts[0] and counts[1] receive the
// decoded vertex and triangle counts, for the reader to hold the mesh's record to.
[[nodiscard]] bool draco_decode_section(const uint8_t* data, size_t size, uint64_t raw_size,
                                        uint8_t* dst, uint32_t counts[2], std::string* error);

}  // namespace pbrta
