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

#include <cmath>
#include <cstdint>

#include "runtime/core/interaction.h"
#include "runtime/core/sampling.h"
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

// Triangle prim's vertex normals interpolated at barycentrics b (world space, unnormalised).
Vec3 interpolated_mesh_normal(const ShapeInfo& s, uint32_t prim, float b0, float b1, float b2);

// sample_shape_area for triangle prim of mesh s, whose world triangle is t. Inline, with the
// conversion below: an emitting triangle is sampled at every light sample of a path, and the
// calls and copies around these few lines cost as much as they do.
inline Interaction sample_triangle_area(const ShapeInfo& s, uint32_t prim, const WorldTriangle& t,
                                        Vec2 u, float* pdf_area) {
  Interaction it;
  const Vec2 b = uniform_sample_triangle(u);
  const float b0 = b.x, b1 = b.y, b2 = 1 - b0 - b1;
  it.p = b0 * t.p0 + b1 * t.p1 + b2 * t.p2;
  it.p_error = gamma_bound(6) * (abs(b0 * t.p0) + abs(b1 * t.p1) + abs(b2 * t.p2));
  it.n = t.n;
  if (s.mesh.normals)
    it.n = face_forward(it.n, interpolated_mesh_normal(s, prim, b0, b1, b2));
  else if (s.flip_normals())
    it.n = -it.n;
  *pdf_area = t.area > 0 && !it.n.has_nan() ? 1 / t.area : 0;
  return it;
}

// pbrt-v3's Shape::Sample(ref, u) for shapes sampled by area: the area pdf of the point `it`
// turned into a solid-angle pdf seen from ref_p (0 when unusable).
inline float area_pdf_as_solid_angle(const Interaction& it, Vec3 ref_p, float pdf_area) {
  Vec3 wi = it.p - ref_p;
  const float d2 = length_squared(wi);
  if (pdf_area == 0 || d2 == 0) return 0;
  wi = normalize(wi);
  const float pdf = pdf_area * (d2 / abs_dot(it.n, -wi));
  return std::isfinite(pdf) ? pdf : 0;
}

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
