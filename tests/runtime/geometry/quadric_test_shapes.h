// tests/runtime/geometry/quadric_test_shapes.h — quadrics built by hand, and
// a long-double reference intersector to check the float one against.
#pragma once

#include <cmath>
#include <optional>

#include "runtime/core/rng.h"
#include "runtime/geometry/quadric_shape.h"
#include "runtime/geometry/shape_table.h"

namespace rt::quadric_test {

using LD = long double;
struct V3L {
  LD x = 0, y = 0, z = 0;
};
inline V3L to_ld(Vec3 v) {
  return {v.x, v.y, v.z};
}

inline ShapeInfo make_shape(ShapeKind kind, QuadricParams q = {}, Transform m = {}) {
  ShapeInfo s;
  s.kind = kind;
  s.q = q;
  s.object_to_world = m;
  s.swaps_handedness = m.swaps_handedness();
  return s;
}

// Rotation by `deg` degrees about unit axis a (Rodrigues), as a Transform.
inline Transform rotate(float deg, Vec3 a) {
  a = normalize(a);
  double th = deg * M_PI / 180, c = std::cos(th), s = std::sin(th);
  double ax[3] = {a.x, a.y, a.z};
  Matrix4 m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m.m[i][j] = float(ax[i] * ax[j] * (1 - c) + (i == j ? c : 0));
  m.m[0][1] -= float(ax[2] * s);
  m.m[0][2] += float(ax[1] * s);
  m.m[1][0] += float(ax[2] * s);
  m.m[1][2] -= float(ax[0] * s);
  m.m[2][0] -= float(ax[1] * s);
  m.m[2][1] += float(ax[0] * s);
  return Transform(m);
}

// The implicit function (zero on the surface) and its gradient, in long double.
inline LD implicit(const QuadricShape& q, V3L p, V3L* grad = nullptr) {
  V3L g;
  LD f = 0;
  switch (q.kind) {
    case ShapeKind::kSphere:
      f = p.x * p.x + p.y * p.y + p.z * p.z - LD(q.radius) * q.radius;
      g = {2 * p.x, 2 * p.y, 2 * p.z};
      break;
    case ShapeKind::kCylinder:
      f = p.x * p.x + p.y * p.y - LD(q.radius) * q.radius;
      g = {2 * p.x, 2 * p.y, 0};
      break;
    case ShapeKind::kDisk:
      f = p.z - q.height;
      g = {0, 0, 1};
      break;
    case ShapeKind::kCone: {
      LD k = LD(q.radius) * q.radius / (LD(q.height) * q.height);
      f = p.x * p.x + p.y * p.y - k * (p.z - q.height) * (p.z - q.height);
      g = {2 * p.x, 2 * p.y, -2 * k * (p.z - q.height)};
      break;
    }
    case ShapeKind::kParaboloid: {
      LD k = LD(q.zmax) / (LD(q.radius) * q.radius);
      f = k * (p.x * p.x + p.y * p.y) - p.z;
      g = {2 * k * p.x, 2 * k * p.y, -1};
      break;
    }
    default:
      f = LD(q.ah) * (p.x * p.x + p.y * p.y) - LD(q.ch) * p.z * p.z - 1;
      g = {2 * LD(q.ah) * p.x, 2 * LD(q.ah) * p.y, -2 * LD(q.ch) * p.z};
      break;
  }
  if (grad) *grad = g;
  return f;
}

inline LD phi_ld(const QuadricShape& q, V3L p) {
  LD phi;
  if (q.kind == ShapeKind::kHyperboloid) {
    LD v = (p.z - q.p1.z) / (LD(q.p2.z) - q.p1.z);
    V3L pr{(1 - v) * q.p1.x + v * q.p2.x, (1 - v) * q.p1.y + v * q.p2.y, 0};
    phi = std::atan2(pr.x * p.y - p.x * pr.y, p.x * pr.x + p.y * pr.y);
  } else {
    phi = std::atan2(p.y, p.x);
  }
  return phi < 0 ? phi + 2 * M_PIl : phi;
}

// How far (in object units, roughly) p is from the nearest cut or rim; hits
// that close may legitimately go either way in float.
inline LD cut_distance(const QuadricShape& q, V3L p) {
  LD r = std::sqrt(p.x * p.x + p.y * p.y);
  LD phi = phi_ld(q, p);
  LD d =
      std::min(std::fabs(phi - q.phimax), std::min(phi, 2 * M_PIl - phi)) * std::max(r, LD(1e-3));
  switch (q.kind) {
    case ShapeKind::kDisk:
      return std::min({d, std::fabs(r - q.radius), std::fabs(r - q.inner_radius)});
    case ShapeKind::kCone:
      return std::min({d, std::fabs(p.z), std::fabs(p.z - q.height)});
    default:
      return std::min({d, std::fabs(p.z - q.zmin), std::fabs(p.z - q.zmax)});
  }
}

inline bool inside_cuts(const QuadricShape& q, V3L p) {
  LD phi = phi_ld(q, p);
  if (phi > q.phimax) return false;
  switch (q.kind) {
    case ShapeKind::kSphere:
      return !((q.zmin > -q.radius && p.z < q.zmin) || (q.zmax < q.radius && p.z > q.zmax));
    case ShapeKind::kDisk: {
      LD r2 = p.x * p.x + p.y * p.y;
      return r2 <= LD(q.radius) * q.radius && r2 >= LD(q.inner_radius) * q.inner_radius;
    }
    case ShapeKind::kCone:
      return p.z >= 0 && p.z <= q.height;
    default:
      return p.z >= q.zmin && p.z <= q.zmax;
  }
}

struct RefHit {
  LD t;
  V3L p;
  LD cos_incidence;  // |cos| between the ray and the surface normal
  LD cut_dist;
};

// Closest hit in (0, tmax) of the object-space ray o + t d, exactly enough.
inline std::optional<RefHit> reference_hit(const QuadricShape& q, V3L o, V3L d, LD tmax) {
  LD roots[2];
  int n = 0;
  if (q.kind == ShapeKind::kDisk) {
    if (d.z == 0) return std::nullopt;
    roots[n++] = (q.height - o.z) / d.z;
  } else {
    // Coefficients from three evaluations of the implicit function along the ray.
    auto f = [&](LD t) { return implicit(q, {o.x + t * d.x, o.y + t * d.y, o.z + t * d.z}); };
    LD f0 = f(0), f1 = f(1), fm = f(-1);
    LD a = (f1 + fm) / 2 - f0, b = (f1 - fm) / 2, c = f0;
    if (a == 0) {
      if (b == 0) return std::nullopt;
      roots[n++] = -c / b;
    } else {
      LD disc = b * b - 4 * a * c;
      if (disc < 0) return std::nullopt;
      LD sq = std::sqrt(disc), qq = b < 0 ? -(b - sq) / 2 : -(b + sq) / 2;
      roots[0] = qq / a;
      roots[1] = qq != 0 ? c / qq : roots[0];
      if (roots[0] > roots[1]) std::swap(roots[0], roots[1]);
      n = 2;
    }
  }
  for (int i = 0; i < n; ++i) {
    LD t = roots[i];
    if (!(t > 0 && t < tmax)) continue;
    V3L p{o.x + t * d.x, o.y + t * d.y, o.z + t * d.z};
    if (!inside_cuts(q, p)) continue;
    V3L g;
    implicit(q, p, &g);
    LD gl = std::sqrt(g.x * g.x + g.y * g.y + g.z * g.z),
       dl = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    LD cosi = std::fabs(g.x * d.x + g.y * d.y + g.z * d.z) / (gl * dl);
    return RefHit{t, p, cosi, cut_distance(q, p)};
  }
  return std::nullopt;
}

// Uniform in [-1, 1)^3 times `extent`, plus `center`.
inline Vec3 random_point(Rng& rng, Vec3 center, float extent) {
  return center + extent * Vec3{2 * rng.next_float() - 1, 2 * rng.next_float() - 1,
                                2 * rng.next_float() - 1};
}

}  // namespace rt::quadric_test
