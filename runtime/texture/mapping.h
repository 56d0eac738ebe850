// runtime/texture/mapping.h — pbrt-v3's texture mappings (book section 10.2).
//
// A 2-D mapping turns a surface point into texture coordinates st and their
// screen-space derivatives dst/dx, dst/dy (for filtering): "uv" scales and
// offsets the surface's (u, v) and its du/dx...; "spherical" and
// "cylindrical" project the point, in texture space, about the origin, with
// derivatives by forward differences along dp/dx, dp/dy; "planar" projects
// the world point onto two vectors. A 3-D mapping gives a point and its
// derivatives in texture space for solid textures.
//
// pbrt-v3 fidelity: spherical and cylindrical use texture-from-world (the
// inverse of the texture's CTM); planar ignores the CTM entirely; and the
// 3-D mapping applies the CTM itself (world-from-texture) to world points,
// because pbrt-v3 passes tex2world where IdentityMapping3D expects
// world-to-texture. We reproduce that so solid textures match pbrt-v3's images.
#pragma once

#include <cstdint>

#include "runtime/core/interaction.h"
#include "runtime/core/transform.h"
#include "runtime/core/vec.h"

namespace rt {

enum class Mapping2DKind : uint8_t { kUV, kSpherical, kCylindrical, kPlanar };

struct Mapping2D {
  Mapping2DKind kind = Mapping2DKind::kUV;
  float su = 1, sv = 1, du = 0, dv = 0;  // uv: scales and offsets; planar: du, dv offsets
  Vec3 vs{1, 0, 0}, vt{0, 1, 0};         // planar: the projection vectors
  Transform texture_from_world;          // spherical, cylindrical

  Vec2 map(const SurfaceInteraction& si, Vec2* dstdx, Vec2* dstdy) const;
};

struct Mapping3D {
  Transform transform;  // applied to world points and differentials (see above)

  Vec3 map(const SurfaceInteraction& si, Vec3* dpdx, Vec3* dpdy) const {
    *dpdx = transform.vector(si.dpdx);
    *dpdy = transform.vector(si.dpdy);
    return transform.point(si.p);
  }
};

}  // namespace rt
