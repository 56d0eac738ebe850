// runtime/texture/mapping.cpp — see mapping.h.
#include "runtime/texture/mapping.h"

#include <cmath>

namespace rt {

namespace {

Vec2 sphere_st(const Transform& texture_from_world, Vec3 p) {
  Vec3 v = normalize(texture_from_world.point(p));
  return {spherical_theta(v) * kInvPi, spherical_phi(v) * kInv2Pi};
}

Vec2 cylinder_st(const Transform& texture_from_world, Vec3 p) {
  Vec3 v = normalize(texture_from_world.point(p));
  return {(kPi + std::atan2(v.y, v.x)) * kInv2Pi, v.z};
}

// A forward difference across the seam (phi wrapping from 1 to 0) would be
// nearly +-1: pbrt-v3 folds it back. It does so on the second coordinate for
// both mappings, although the seam is in the first; we keep that.
void fold_seam(Vec2* d) {
  if (d->y > .5f)
    d->y = 1 - d->y;
  else if (d->y < -.5f)
    d->y = -(d->y + 1);
}

}  // namespace

Vec2 Mapping2D::map(const SurfaceInteraction& si, Vec2* dstdx, Vec2* dstdy) const {
  switch (kind) {
    case Mapping2DKind::kUV:
      *dstdx = {su * si.dudx, sv * si.dvdx};
      *dstdy = {su * si.dudy, sv * si.dvdy};
      return {su * si.uv.x + du, sv * si.uv.y + dv};
    case Mapping2DKind::kSpherical:
    case Mapping2DKind::kCylindrical: {
      bool sphere = kind == Mapping2DKind::kSpherical;
      const float delta = sphere ? .1f : .01f;
      auto st_of = [&](Vec3 p) {
        return sphere ? sphere_st(texture_from_world, p) : cylinder_st(texture_from_world, p);
      };
      Vec2 st = st_of(si.p);
      Vec2 stx = st_of(si.p + delta * si.dpdx);
      Vec2 sty = st_of(si.p + delta * si.dpdy);
      const float inv = 1 / delta;  // pbrt-v3 divides a vector by multiplying
      *dstdx = (stx - st) * inv;
      *dstdy = (sty - st) * inv;
      fold_seam(dstdx);
      fold_seam(dstdy);
      return st;
    }
    case Mapping2DKind::kPlanar:
      *dstdx = {dot(si.dpdx, vs), dot(si.dpdx, vt)};
      *dstdy = {dot(si.dpdy, vs), dot(si.dpdy, vt)};
      return {du + dot(si.p, vs), dv + dot(si.p, vt)};
  }
  *dstdx = *dstdy = Vec2{};
  return {};
}

}  // namespace rt
