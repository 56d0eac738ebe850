// runtime/geometry/curve_hit.h — a world ray against one piece of a curve shape, as a
// SurfaceInteraction.
//
// The ray goes to object space through world_to_object, is tested with
// intersect_curve_piece (curve.h), and the hit comes back through to_world the
// way pbrt-v3 transforms a curve's interaction: the normal is dp/du x dp/dv
// (flipped by the shape's orientation flags), the shading frame is the
// geometric one, dn/du and dn/dv are zero. The caller picks the transforms
// (the shape's own, its motion at the ray's time, or composed with an
// instance's) and sets shape and instance. si may be null (any hit).
#pragma once

#include "runtime/core/interaction.h"
#include "runtime/core/transform.h"
#include "runtime/geometry/shape_table.h"

namespace rt {

bool world_curve_hit(const ShapeInfo& s, const Transform& to_world,
                     const Transform& world_to_object, uint32_t piece, const Ray& ray_world,
                     float* t_hit, SurfaceInteraction* si);

}  // namespace rt
