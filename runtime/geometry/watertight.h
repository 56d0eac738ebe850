// runtime/geometry/watertight.h — a watertight triangle test, and vertex patches for Embree.
//
// Embree's ROBUST triangle test is watertight along shared edges but not at
// shared vertices (its maintainers say so: embree issues #181, #188): a ray
// aimed exactly at a vertex of a closed mesh can pass between the triangles
// (measured in tests/runtime/stability/watertight_test.cpp). The fix here:
// each mesh also gets an Embree user geometry of "vertex patches", one tiny
// box per vertex; a ray that passes through a box is re-tested against the
// triangles around that vertex with watertight_triangle() (pbrt-v3's test,
// book 3rd ed. 3.6.2: shear to ray space, edge functions with a double
// fallback when one is exactly zero, error-bounded t), and a hit is reported
// as a hit of the mesh's own triangle geometry (same geomID, primID = the
// triangle, u/v its barycentrics b1/b2), so callers never see the patches.
// Edges of near-degenerate triangles (height < 2^-10 of the longest edge)
// leak too (measured on slivers of aspect 1e5), so each such edge also gets
// a patch: its box, re-testing the triangles that share it. Ordinary edges
// are watertight in Embree and get none. Rays far from every patch never
// reach the callback. Meshes with alpha masks get no patches (their hits
// must go through the alpha filter).
#pragma once

#include <embree3/rtcore.h>

#include <cstdint>
#include <vector>

#include "runtime/core/vec.h"

namespace rt {

// Closest-hit test of the ray o + t d, t in (0, tmax), with triangle p0 p1 p2.
// On a hit: *t, and barycentrics b1, b2 (p = (1-b1-b2) p0 + b1 p1 + b2 p2).
bool watertight_triangle(Vec3 o, Vec3 d, float tmax, Vec3 p0, Vec3 p1, Vec3 p2, float* t, float* b1,
                         float* b2);

// One mesh's patches; must outlive the Embree scene it is attached to
// (Embree keeps a pointer to it as the geometry's user data).
struct VertexPatches {
  const float* positions = nullptr;  // 3 per vertex, the buffer Embree's triangles use
  const uint32_t* indices = nullptr;
  std::vector<Bounds3> boxes;       // per patch: vertices first, then sliver edges
  std::vector<uint32_t> first;      // per patch + 1: CSR offsets into triangles
  std::vector<uint32_t> triangles;  // the triangles each patch re-tests
  unsigned triangle_geom_id = 0;    // the mesh's geometry in the same Embree scene
};

// Fills *patches for the mesh and attaches its user geometry to scene.
void attach_vertex_patches(RTCDevice device, RTCScene scene, const float* positions,
                           const uint32_t* indices, uint32_t num_vertices, uint32_t num_triangles,
                           unsigned triangle_geom_id, VertexPatches* patches);

}  // namespace rt
