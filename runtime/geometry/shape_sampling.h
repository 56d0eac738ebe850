// runtime/geometry/shape_sampling.h — points on shapes, for area lights.
//
// pbrt-v3's Shape::Area / Sample / Pdf for one triangle of a mesh or for a
// quadric, in world space. Triangles sample uniform barycentrics; spheres
// sample by area, or, seen from outside, the cone of directions they subtend;
// disks concentrically; cylinders uniform in z and phi. Cones, paraboloids
// and hyperboloids cannot be sampled in pbrt-v3 either: their pdfs are 0 and
// the lights code reports them as not supported. Every pdf is 0 when a sample
// is unusable (degenerate geometry, the reference point on the shape).
#pragma once

#include <cstdint>

#include "runtime/core/interaction.h"
#include "runtime/geometry/shape_table.h"

namespace rt {

// One mesh triangle in world space, with its area and unit geometric normal (not flipped by
// the shape's orientation). Emitting triangles have theirs made once (LightSet): every function
// below takes one as `t`, and makes it itself when given none.
struct WorldTriangle {
  Vec3 p0, p1, p2, n;
  float area = 0;
};
WorldTriangle world_triangle(const ShapeInfo& s, uint32_t prim);

// World-space area (triangle prim of a mesh, or the quadric; prim ignored for quadrics).
float shape_area(const ShapeInfo& s, uint32_t prim, const WorldTriangle* t = nullptr);
// Uniform by area: p, p_error, n; *pdf_area = 1/area (0 if unsupported).
Interaction sample_shape_area(const ShapeInfo& s, uint32_t prim, Vec2 u, float* pdf_area,
                              const WorldTriangle* t = nullptr);
// As pbrt-v3's Shape::Sample(ref, u): a sphere samples the visible cone when ref
// is outside; others convert the area sample (dist^2 / |cos|); pdf 0 if unusable.
Interaction sample_shape_from(const ShapeInfo& s, uint32_t prim, const Interaction& ref, Vec2 u,
                              float* pdf_solid_angle, const WorldTriangle* t = nullptr);
// The solid-angle pdf sample_shape_from would have for the point on_shape
// (found by tracing from ref along wi).
float shape_pdf_from(const ShapeInfo& s, uint32_t prim, const Interaction& ref, Vec3 wi,
                     const Interaction& on_shape, const WorldTriangle* t = nullptr);

}  // namespace rt
