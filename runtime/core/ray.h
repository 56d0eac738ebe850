// runtime/core/ray.h — rays, ray differentials, and pbrt-style origin offsets.
//
// offset_ray_origin() moves a surface point out along its normal by the
// point's conservative floating-point error bound (then one more ulp away),
// so a ray leaving a surface never hits it again and never starts beyond the
// other side of a thin object: the pbrt book's "no acne, no leaks" scheme.
// Shadow rays to a point stop at 1 - shadow_epsilon of the way.
#pragma once

#include "runtime/core/vec.h"

namespace rt {

inline constexpr float kShadowEpsilon = 0.0001f;

struct Ray {
  Vec3 o, d;
  float tmax = kInfinity;
  float time = 0;
  Vec3 at(float t) const { return o + d * t; }
};

struct RayDifferential : Ray {
  bool has_differentials = false;
  Vec3 rx_o, rx_d, ry_o, ry_d;
  RayDifferential() = default;
  explicit RayDifferential(const Ray& r) : Ray(r) {}
  // A differential origin or direction moved toward the ray's own by the factor s.
  static Vec3 scaled(Vec3 own, Vec3 differential, float s) {
    return own + (differential - own) * s;
  }
  void scale_differentials(float s) {
    if (!has_differentials) return;
    rx_o = scaled(o, rx_o, s);
    ry_o = scaled(o, ry_o, s);
    rx_d = scaled(d, rx_d, s);
    ry_d = scaled(d, ry_d, s);
  }
};

// How far along d (in units of t) an origin off by up to o_err must move to pass that error.
inline float past_error_distance(Vec3 d, Vec3 o_err) {
  const float len2 = length_squared(d);
  return len2 > 0 ? dot(abs(d), o_err) / len2 : 0.f;
}

// A transformed ray's origin o, off by up to o_err, moved forward along its direction d past
// that error (pbrt-v3's ray transform): what lies at t > 0 is then in front of the true origin.
inline Vec3 origin_past_error(Vec3 o, Vec3 d, Vec3 o_err) {
  return o + d * past_error_distance(d, o_err);
}

inline Vec3 offset_ray_origin(Vec3 p, Vec3 p_error, Vec3 n, Vec3 w) {
  float d = dot(abs(n), p_error);
  Vec3 offset = n * d;
  if (dot(w, n) < 0) offset = -offset;
  Vec3 po = p + offset;
  for (int i = 0; i < 3; ++i) {
    if (offset[i] > 0)
      po[i] = next_float_up(po[i]);
    else if (offset[i] < 0)
      po[i] = next_float_down(po[i]);
  }
  return po;
}

}  // namespace rt
