// runtime/geometry/triangle_hit.h — a triangle hit turned into pbrt-v3's SurfaceInteraction.
//
// Embree reports (primitive, u, v); everything else is rebuilt here in world
// space the way pbrt-v3's Triangle::Intersect computes it: the three
// vertices taken to world, the hit measured again on them in our own
// arithmetic (Embree's kernels differ by CPU, SSE to AVX-512, and so do their
// t, u and v; Embree's stand only where the ray is parallel to the plane),
// p = b0 p0 + b1 p1 + b2 p2 with the book's error
// bound gamma(7) sum |bi pi| (3.9.2), uv (default (0,0) (1,0) (1,1)), dp/du
// and dp/dv (a coordinate system around the normal when the uv mapping is
// degenerate), the geometric normal from the edges, the shading frame from N
// and S with dn/du, dn/dv, and pbrt-v3's orientation rules (including its
// SetShadingGeometry flip of the shading normal by ReverseOrientation XOR
// handedness). Pure function of its inputs: deterministic and thread-safe.
#pragma once

#include <cstdint>

#include "runtime/core/interaction.h"
#include "runtime/geometry/shape_table.h"

namespace rt {

// What a triangle's interaction needs that no hit changes: made from its world vertices and
// uv by triangle_frame, per hit or once for a scene's few listed triangles.
struct TriangleFrame {
  float area2 = 0;      // (twice the area)^2
  float edge2[3] = {};  // squared length of the edge opposite each vertex
  Vec3 n;               // the geometric normal from the edges (+z if degenerate)
  Vec3 dpdu, dpdv;      // pbrt-v3's, with its degenerate-uv rule
  float uv_det = 0;
  bool degenerate_uv = false;
};
// p: the world vertices of triangle prim of mesh m.
TriangleFrame triangle_frame(const MeshView& m, uint32_t prim, const Vec3 p[3]);

// How the vertex buffer Embree intersected maps to world space.
struct TriangleSpace {
  // The positions Embree was given: the archive's object-space array, or a
  // copy already through the shape's transform (meshes inside objects).
  const float* positions = nullptr;
  // The buffer's positions already include s.object_to_world: normals and
  // tangents must still go through it.
  bool buffer_has_shape_transform = false;
  // Buffer space to world (an object instance, or a moving mesh's motion at the ray's time),
  // or null: identity.
  const Transform* to_world = nullptr;
  // to_world is an instance's transform (pbrt-v3's TransformedPrimitive).
  bool instance = false;
  // The positions went through to_world too (an instance copied into the world): to_world
  // still takes normals and tangents there.
  bool positions_in_world = false;
  // ... and it mirrors: pbrt-v3 transforms the instance-space normal as a
  // normal, which is the world-edge cross product flipped.
  bool instance_mirrors = false;
  // t and the barycentrics come from our own test on these very world vertices (PrimList's
  // watertight test), not from Embree's CPU-dependent kernels: nothing to measure again.
  bool measured = false;
  // Per triangle of the mesh, triangle_frame of the vertices of `positions` (read when to_world
  // does not move them), or null: made per hit.
  const TriangleFrame* frames = nullptr;
};

// Fills si (p, p_error, n, wo, time, uv, dpdu, dpdv, dndu, dndv, shading,
// prim, face_index; not shape/instance, not differentials) for Embree's hit of
// triangle prim of mesh shape s at *t_hit with barycentrics (1-b1-b2, b1, b2),
// both measured again first (*t_hit is updated) unless space.measured. A mesh rays pass through
// (s.passes_through) without vertex normals or tangents gets only p, p_error, n (shading.n = n),
// wo, time, prim and face_index: nothing reads the rest of a surface that is only passed through.
void triangle_interaction(const ShapeInfo& s, const TriangleSpace& space, uint32_t prim, float b1,
                          float b2, const Ray& ray, float* t_hit, SurfaceInteraction* si);

}  // namespace rt
