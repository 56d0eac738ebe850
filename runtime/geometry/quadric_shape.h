// runtime/geometry/quadric_shape.h — a quadric's parameters as pbrt-v3's
// constructors normalise them.
//
// ShapeInfo holds the archive's values; pbrt-v3's shape constructors then
// sort and clamp z ranges, derive the sphere's theta range, and solve for the
// hyperboloid's implicit coefficients. Intersection and sampling both start
// from this, so they agree on the shape. Internal to runtime/geometry.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>

#include "runtime/geometry/shape_table.h"

namespace rt {

struct QuadricShape {
  ShapeKind kind = ShapeKind::kSphere;
  float radius = 1, zmin = -1, zmax = 1, phimax = 2 * kPi;
  float height = 0, inner_radius = 0;
  float theta_zmin = kPi, theta_zmax = 0;  // sphere
  Vec3 p1, p2;                             // hyperboloid, possibly swapped
  float ah = 0, ch = 0, rmax = 0;          // hyperboloid: ah (x^2 + y^2) - ch z^2 = 1
  bool valid = true;  // false: no finite implicit form (never hit, not sampled)
};

inline QuadricShape make_quadric_shape(const ShapeInfo& s) {
  QuadricShape q;
  const QuadricParams& in = s.q;
  q.kind = s.kind;
  q.radius = in.radius;
  q.phimax = in.phimax;
  q.height = in.height;
  q.inner_radius = in.inner_radius;
  q.zmin = std::min(in.zmin, in.zmax);
  q.zmax = std::max(in.zmin, in.zmax);
  switch (s.kind) {
    case ShapeKind::kSphere:
      q.zmin = clamp(q.zmin, -q.radius, q.radius);
      q.zmax = clamp(q.zmax, -q.radius, q.radius);
      q.theta_zmin = std::acos(clamp(q.zmin / q.radius, -1.f, 1.f));
      q.theta_zmax = std::acos(clamp(q.zmax / q.radius, -1.f, 1.f));
      break;
    case ShapeKind::kHyperboloid: {
      q.p1 = in.p1;
      q.p2 = in.p2;
      float r1 = std::sqrt(q.p1.x * q.p1.x + q.p1.y * q.p1.y);
      float r2 = std::sqrt(q.p2.x * q.p2.x + q.p2.y * q.p2.y);
      q.rmax = std::max(r1, r2);
      q.zmin = std::min(q.p1.z, q.p2.z);
      q.zmax = std::max(q.p1.z, q.p2.z);
      if (q.p2.z == 0) std::swap(q.p1, q.p2);
      // pbrt-v3 walks a helper point along the p1-p2 line until the two
      // conditions give finite coefficients; for some inputs (the default
      // p1 = 0, p2 = 1 1 1 among them) it never does and pbrt-v3 hangs, so
      // the walk is bounded and such a hyperboloid is marked invalid.
      Vec3 pp = q.p1;
      q.valid = false;
      for (int i = 0; i < 64 && !q.valid; ++i) {
        pp += 2.f * (q.p2 - q.p1);
        float xy1 = pp.x * pp.x + pp.y * pp.y;
        float xy2 = q.p2.x * q.p2.x + q.p2.y * q.p2.y;
        q.ah = (1.f / xy1 - (pp.z * pp.z) / (xy1 * q.p2.z * q.p2.z)) /
               (1 - (xy2 * pp.z * pp.z) / (xy1 * q.p2.z * q.p2.z));
        q.ch = (q.ah * xy2 - 1) / (q.p2.z * q.p2.z);
        q.valid = std::isfinite(q.ah) && std::isfinite(q.ch);
      }
      break;
    }
    default:
      break;
  }
  return q;
}

}  // namespace rt
