// tools/mesh/mesh_ops.h — vertex normals, quadric simplification, measured Hausdorff distance.
//
// compute_normals rebuilds per-vertex normals from the triangles, weighted by face area or by the
// face's angle at the vertex. Vertices with the same position are treated as one surface point
// while gathering (so uv seams, which duplicate vertices, do not become shading seams), and with
// a crease angle below 180 degrees a point is split into one vertex per smooth group so that hard
// edges stay hard. Degenerate faces contribute nothing; a vertex with no usable face gets a finite
// fallback normal, never NaN.
//
// simplify runs OpenMesh's quadric decimater (halfedge collapses, so every surviving vertex is an
// input vertex with its own position and uv) and then measures what it did with
// hausdorff_distance, rather than trusting the quadric bound.
//
// hausdorff_distance samples both surfaces (every vertex used by a triangle plus area-weighted
// uniform points from a fixed-seed generator, so results are reproducible across runs and
// platforms) and finds each sample's exact closest point on the other mesh's triangles through a
// BVH. Sampling can only miss the worst point, so the max is a lower bound that converges to the
// true symmetric Hausdorff distance as samples grow.
//
// All functions are reentrant and keep no state; distinct calls may run concurrently.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tools/mesh/mesh.h"

namespace meshtools {

enum class NormalWeighting {
  kArea,   // each face counts by its area: large faces dominate
  kAngle,  // each face counts by its corner angle at the vertex: independent of tessellation
};

struct NormalsOptions {
  NormalWeighting weighting = NormalWeighting::kAngle;
  // Faces meeting across an edge at more than this angle (between their normals) are shaded
  // separately at that edge. 180 or more never splits.
  double crease_angle_degrees = 180.0;
};

// Replaces mesh->normals with unit normals computed from the triangles. Vertices may be split
// (appended at the end; vertex i keeps index i for its first smooth group) and triangles then
// re-pointed at the copies; triangle order, face_indices and uvs are preserved. When
// source_vertex is given it receives, for every output vertex, the input vertex it copies.
void compute_normals(Mesh* mesh, const NormalsOptions& options,
                     std::vector<uint32_t>* source_vertex = nullptr);

struct HausdorffOptions {
  size_t samples = 100000;  // area-weighted surface samples per mesh, on top of its vertices
  uint64_t seed = 0x5eed;
};

struct HausdorffResult {
  double max = 0;         // symmetric: the larger of the two directed maxima
  double rms = 0;         // over all samples of both directions together
  double max_a_to_b = 0;  // farthest sample of a from b
  double max_b_to_a = 0;
  size_t samples = 0;  // distance queries made, both directions
};

// Symmetric Hausdorff distance between the surfaces of a and b. If exactly one of them has no
// triangles the distance is infinite; if neither has, it is 0.
HausdorffResult hausdorff_distance(const Mesh& a, const Mesh& b,
                                   const HausdorffOptions& options = HausdorffOptions{});

struct SimplifyOptions {
  double ratio = 0.5;  // target faces = ratio * input faces, ratio in (0, 1]
  // OpenMesh's quadric error: the sum over the original faces around a collapse of
  // area * squared distance, so in length^4 units. Collapses above it are refused, so the
  // result may keep more faces than the ratio asks for.
  std::optional<double> max_quadric_error;
  bool prevent_normal_flips = true;  // ModNormalFlippingT: refuse collapses that fold a face over
  // An open border vertex may be removed only where the border turns by at most this angle, so
  // borders keep their shape (quadrics alone would let flat borders erode). 0 keeps straight
  // runs only; 180 lets borders go freely.
  double boundary_max_turn_degrees = 15.0;
  NormalsOptions normals;  // used to recompute normals when the input had them
  bool measure = true;     // measure the Hausdorff distance into the report
  HausdorffOptions hausdorff;
};

struct SimplifyReport {
  size_t faces_before = 0, faces_after = 0;
  size_t vertices_before = 0, vertices_after = 0;
  size_t degenerate_faces_dropped = 0;  // repeated vertex index: no area, no topology
  size_t locked_vertices = 0;  // seam vertices kept fixed so the two sides cannot drift apart
  bool normals_recomputed = false;
  bool measured = false;
  HausdorffResult hausdorff;  // output against input, when measured
  double bbox_diagonal = 0;   // of the input
};

// Decimates mesh to about ratio * its faces into *out. Returns false with a message in *error
// (and *out untouched) on bad options or when OpenMesh's halfedge structure rejects faces
// (non-manifold edges or vertices): it says how many faces could not be added instead of silently
// dropping them.
bool simplify(const Mesh& mesh, const SimplifyOptions& options, Mesh* out, SimplifyReport* report,
              std::string* error);

// Length of the diagonal of the axis-aligned bounding box of the vertices (0 if none).
double bbox_diagonal(const Mesh& mesh);

}  // namespace meshtools
