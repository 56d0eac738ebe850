// runtime/geometry/quadric_intersect.h — pbrt-v3's quadrics, hit robustly.
//
// Sphere, cylinder, disk, cone, paraboloid and hyperboloid (ShapeKind) with
// their phimax / zmin / zmax / inner-radius cuts, intersected the way the pbrt
// book (3rd ed., ch. 3.2-3.6, 3.9) does it: the world ray is taken to object
// space with error bounds, the quadratic's coefficients and roots are carried
// as intervals (EFloat), t is tested conservatively against 0 and tmax, and
// the hit point comes back with an error bound, so offset_ray_origin() can
// spawn rays that never re-hit the surface. Called from Embree user-geometry
// callbacks: no allocation, no virtual calls. Degenerate parameters (e.g. a
// hyperboloid whose implicit form has no finite coefficients) never hit.
#pragma once

#include "runtime/core/interaction.h"
#include "runtime/core/ray.h"
#include "runtime/geometry/quadric_shape.h"
#include "runtime/geometry/shape_table.h"

namespace rt {

// The quadric's box in its own object space, as pbrt-v3's ObjectBound (phimax
// cuts do not shrink it). Empty for non-quadrics.
Bounds3 quadric_object_bounds(const ShapeInfo& s);
// That box through s.object_to_world (the space intersect_quadric's rays are
// in), padded outwards for the transform's rounding: the box to give Embree;
// for an animated shape, the box over its whole motion.
Bounds3 quadric_world_bounds(const ShapeInfo& s);

// Closest hit of a world-space ray with quadric s in (0, ray.tmax). The ray is
// taken to object space with s.object_to_world's inverse (with error bounds),
// intersected with pbrt-v3's error-bounded method, and the hit returned in
// world space: *t_hit, and when si != nullptr a full SurfaceInteraction (p,
// p_error, n, wo, time, uv, dpdu, dpdv, dndu, dndv, shading = geometric, shape
// index NOT set (the caller sets it)).
bool intersect_quadric(const ShapeInfo& s, const Ray& ray_world, float* t_hit,
                       SurfaceInteraction* si);

// What intersect_quadric derives from s before any ray: pbrt-v3's normalised
// parameters (two acos for a sphere) and the world-to-object transform. The
// scene computes it once per shape; the result of a test is the same.
struct PreparedQuadric {
  QuadricShape shape;
  Transform world_to_object;
};
PreparedQuadric prepare_quadric(const ShapeInfo& s);
// With the shape's prepared parameters and the world-to-object transform (the one in s is not
// read: a shape in a moving or instanced object is tested where it is at the ray's time). Of
// s only the kind and the orientation flags are read.
bool intersect_quadric(const ShapeInfo& s, const QuadricShape& q, const Transform& world_to_object,
                       const Ray& ray_world, float* t_hit, SurfaceInteraction* si);

}  // namespace rt
