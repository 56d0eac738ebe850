// compiler/refine.h — loopsubdiv, nurbs and heightfield shapes to triangle meshes.
//
// pbrt-v3 turns these three shape types into triangle meshes when it builds the
// scene; pbrtc does the same work at compile time, so the archive holds the
// triangles the renderer would have made and the runtime never refines. Each
// function reads the shape's resolved parameters (the bulk arrays stay in the
// Entity for these types) and reproduces pbrt-v3's refinement: the same
// subdivision rules and limit normals for loopsubdiv, the same 30 x 30
// evaluation grid for nurbs, the same grid for heightfield, with vertices and
// triangles in pbrt-v3's order and its float arithmetic.
//
// Input that pbrt-v3 would crash on, hang on or turn into NaNs (indices out of
// range, a mesh that is not an oriented manifold, knot vectors of the wrong
// length, parameter ranges outside the knots, too few grid points) is rejected:
// the function returns false and sets *error to a message that names the
// problem; the caller reports it at the shape's location. out is then
// unspecified.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "compiler/scene_desc.h"

namespace pbrtc {

// pbrt-v3's fixed NURBS dicing rate: every patch becomes this many points in u and in v.
inline constexpr int kNurbsDice = 30;

// True for the shape types refined here.
bool is_refined_shape(std::string_view type);

// Refines a shape of one of those types (dispatching on its type name) and
// sets out->refine_level.
bool refine_shape(const Entity& shape, TriangleMesh* out, std::string* error);

bool refine_loopsubdiv(const Entity& shape, TriangleMesh* out, std::string* error);
bool refine_nurbs(const Entity& shape, TriangleMesh* out, std::string* error);
bool refine_heightfield(const Entity& shape, TriangleMesh* out, std::string* error);

// The Loop subdivision itself, on raw arrays: levels rounds over the triangles
// of indices (3 per triangle) on num_vertices points P (3 floats each), then
// every vertex moved to the limit surface, with pbrt-v3's limit normals in
// out->N (not normalized, as pbrt-v3 leaves them).
bool loop_subdivide(int levels, const int32_t* indices, size_t num_indices, const float* P,
                    size_t num_vertices, TriangleMesh* out, std::string* error);

}  // namespace pbrtc
