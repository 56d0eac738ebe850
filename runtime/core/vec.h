// runtime/core/vec.h — small fixed-size vectors and boxes.
//
// One Vec3 type serves points, directions and normals (the renderer keeps the
// distinction in names, not types: fewer conversions in the hot loop). Vec2
// carries uv and 2-D samples, Point2i pixels, Bounds3 world boxes. Plain
// aggregates, header-only.
#pragma once

#include <cmath>
#include <cstdint>

#include "runtime/core/math.h"

namespace rt {

struct Vec2 {
  float x = 0, y = 0;
  float operator[](int i) const { return i == 0 ? x : y; }
  float& operator[](int i) { return i == 0 ? x : y; }
};
inline Vec2 operator+(Vec2 a, Vec2 b) {
  return {a.x + b.x, a.y + b.y};
}
inline Vec2 operator-(Vec2 a, Vec2 b) {
  return {a.x - b.x, a.y - b.y};
}
inline Vec2 operator*(Vec2 a, float s) {
  return {a.x * s, a.y * s};
}
inline Vec2 operator*(float s, Vec2 a) {
  return {a.x * s, a.y * s};
}

struct Point2i {
  int x = 0, y = 0;
};
inline bool operator==(Point2i a, Point2i b) {
  return a.x == b.x && a.y == b.y;
}

// Pixel rectangles: min inclusive, max exclusive (as pbrt's Bounds2i).
struct Bounds2i {
  Point2i min, max;
  int width() const { return max.x - min.x; }
  int height() const { return max.y - min.y; }
  int64_t area() const { return int64_t(width()) * height(); }
  bool empty() const { return max.x <= min.x || max.y <= min.y; }
  bool inside(Point2i p) const {
    return p.x >= min.x && p.x < max.x && p.y >= min.y && p.y < max.y;
  }
};
inline Bounds2i intersect(const Bounds2i& a, const Bounds2i& b) {
  return {{std::max(a.min.x, b.min.x), std::max(a.min.y, b.min.y)},
          {std::min(a.max.x, b.max.x), std::min(a.max.y, b.max.y)}};
}

struct Vec3 {
  float x = 0, y = 0, z = 0;
  float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  Vec3& operator+=(Vec3 b) {
    x += b.x;
    y += b.y;
    z += b.z;
    return *this;
  }
  Vec3& operator-=(Vec3 b) {
    x -= b.x;
    y -= b.y;
    z -= b.z;
    return *this;
  }
  Vec3& operator*=(float s) {
    x *= s;
    y *= s;
    z *= s;
    return *this;
  }
  bool has_nan() const { return std::isnan(x) || std::isnan(y) || std::isnan(z); }
};
inline Vec3 operator+(Vec3 a, Vec3 b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline Vec3 operator-(Vec3 a, Vec3 b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline Vec3 operator-(Vec3 a) {
  return {-a.x, -a.y, -a.z};
}
inline Vec3 operator*(Vec3 a, float s) {
  return {a.x * s, a.y * s, a.z * s};
}
inline Vec3 operator*(float s, Vec3 a) {
  return {a.x * s, a.y * s, a.z * s};
}
inline Vec3 operator/(Vec3 a, float s) {
  float inv = 1 / s;
  return a * inv;
}
inline bool operator==(Vec3 a, Vec3 b) {
  return a.x == b.x && a.y == b.y && a.z == b.z;
}
inline bool operator!=(Vec3 a, Vec3 b) {
  return !(a == b);
}

inline float dot(Vec3 a, Vec3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline float abs_dot(Vec3 a, Vec3 b) {
  return std::fabs(dot(a, b));
}
// Cross product in double precision: pbrt-v3 does the same, to avoid
// catastrophic cancellation when the inputs are nearly parallel.
inline Vec3 cross(Vec3 a, Vec3 b) {
  double ax = a.x, ay = a.y, az = a.z, bx = b.x, by = b.y, bz = b.z;
  return {float(ay * bz - az * by), float(az * bx - ax * bz), float(ax * by - ay * bx)};
}
inline float length_squared(Vec3 a) {
  return dot(a, a);
}
inline float length(Vec3 a) {
  return std::sqrt(dot(a, a));
}
inline Vec3 normalize(Vec3 a) {
  return a / length(a);
}
inline float distance(Vec3 a, Vec3 b) {
  return length(a - b);
}
inline float distance_squared(Vec3 a, Vec3 b) {
  return length_squared(a - b);
}
inline Vec3 abs(Vec3 a) {
  return {std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)};
}
inline Vec3 vmin(Vec3 a, Vec3 b) {
  return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
inline Vec3 vmax(Vec3 a, Vec3 b) {
  return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
inline float max_component(Vec3 a) {
  return std::max(a.x, std::max(a.y, a.z));
}
inline int max_dimension(Vec3 a) {
  return a.x > a.y ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
}
inline Vec3 permute(Vec3 a, int x, int y, int z) {
  return {a[x], a[y], a[z]};
}
// n flipped, if needed, to lie in the hemisphere of v.
inline Vec3 face_forward(Vec3 n, Vec3 v) {
  return dot(n, v) < 0.f ? -n : n;
}

// Two unit vectors completing v (unit) to an orthonormal basis.
inline void coordinate_system(Vec3 v1, Vec3* v2, Vec3* v3) {
  if (std::fabs(v1.x) > std::fabs(v1.y))
    *v2 = Vec3{-v1.z, 0, v1.x} / std::sqrt(v1.x * v1.x + v1.z * v1.z);
  else
    *v2 = Vec3{0, v1.z, -v1.y} / std::sqrt(v1.y * v1.y + v1.z * v1.z);
  *v3 = cross(v1, *v2);
}

inline Vec3 spherical_direction(float sin_theta, float cos_theta, float phi) {
  return {clamp(sin_theta, -1.f, 1.f) * std::cos(phi), clamp(sin_theta, -1.f, 1.f) * std::sin(phi),
          clamp(cos_theta, -1.f, 1.f)};
}
inline float spherical_theta(Vec3 v) {
  return safe_acos(v.z);
}
inline float spherical_phi(Vec3 v) {
  float p = std::atan2(v.y, v.x);
  return p < 0 ? p + 2 * kPi : p;
}

struct Bounds3 {
  Vec3 lo{kInfinity, kInfinity, kInfinity};
  Vec3 hi{-kInfinity, -kInfinity, -kInfinity};
  void extend(Vec3 p) {
    lo = vmin(lo, p);
    hi = vmax(hi, p);
  }
  void extend(const Bounds3& b) {
    lo = vmin(lo, b.lo);
    hi = vmax(hi, b.hi);
  }
  bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
  Vec3 diagonal() const { return hi - lo; }
  Vec3 center() const { return (lo + hi) * 0.5f; }
  // Offset of p inside the box, 0 at lo and 1 at hi per axis.
  Vec3 offset(Vec3 p) const {
    Vec3 o = p - lo;
    for (int i = 0; i < 3; ++i)
      if (hi[i] > lo[i]) o[i] /= hi[i] - lo[i];
    return o;
  }
  void bounding_sphere(Vec3* c, float* r) const {
    *c = center();
    *r = empty() ? 0 : distance(*c, hi);
  }
  // Whether the ray o + t d meets the box for some t in [0, tmax]: the slab test with the far
  // distances widened by their rounding (pbrt book 3rd ed. 3.9.2), so no box the ray meets is
  // missed. A NaN distance (0 times an infinite 1 / d: the origin on a face the ray runs
  // along) bounds nothing: only a definite comparison rejects.
  bool meets(Vec3 o, Vec3 d, float tmax) const {
    float t0 = 0, t1 = tmax;
    for (int a = 0; a < 3; ++a) {
      const float inv = 1 / d[a];
      float tn = (lo[a] - o[a]) * inv, tf = (hi[a] - o[a]) * inv;
      if (tn > tf) {
        const float swap = tn;
        tn = tf;
        tf = swap;
      }
      tf *= 1 + 2 * gamma_bound(3);
      if (tn > t0) t0 = tn;
      if (tf < t1) t1 = tf;
      if (t0 > t1) return false;
    }
    return true;
  }
};

}  // namespace rt
