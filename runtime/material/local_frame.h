// runtime/material/local_frame.h — trigonometry of directions in the shading frame.
//
// BxDFs work in a local frame where the shading normal is +z (pbrt-v3's
// convention, book section 8.1): cos theta is w.z, phi is measured in the xy
// plane. Also reflection about a normal and Snell refraction, which every
// specular and microfacet lobe shares. Header-only: all of this is hot.
#pragma once

#include "runtime/core/vec.h"

namespace rt {

inline float cos_theta(Vec3 w) {
  return w.z;
}
inline float cos2_theta(Vec3 w) {
  return w.z * w.z;
}
inline float abs_cos_theta(Vec3 w) {
  return std::fabs(w.z);
}
inline float sin2_theta(Vec3 w) {
  return std::max(0.f, 1 - cos2_theta(w));
}
inline float sin_theta(Vec3 w) {
  return std::sqrt(sin2_theta(w));
}
inline float tan_theta(Vec3 w) {
  return sin_theta(w) / cos_theta(w);
}
inline float tan2_theta(Vec3 w) {
  return sin2_theta(w) / cos2_theta(w);
}
// cos phi and sin phi given w's sin theta (sin_theta(w)), for callers that have it already.
inline float cos_phi(Vec3 w, float sin_t) {
  return sin_t == 0 ? 1 : clamp(w.x / sin_t, -1.f, 1.f);
}
inline float sin_phi(Vec3 w, float sin_t) {
  return sin_t == 0 ? 0 : clamp(w.y / sin_t, -1.f, 1.f);
}
inline float cos_phi(Vec3 w) {
  return cos_phi(w, sin_theta(w));
}
inline float sin_phi(Vec3 w) {
  return sin_phi(w, sin_theta(w));
}
inline float cos2_phi(Vec3 w) {
  return sqr(cos_phi(w));
}
inline float sin2_phi(Vec3 w) {
  return sqr(sin_phi(w));
}
inline bool same_hemisphere(Vec3 a, Vec3 b) {
  return a.z * b.z > 0;
}

// wo mirrored about n (both unit; the result points away from the surface as wo does).
inline Vec3 reflect(Vec3 wo, Vec3 n) {
  return -wo + 2 * dot(wo, n) * n;
}

// Snell's law: wi (pointing away from the surface, on n's side) refracted into
// *wt, with eta = eta_i / eta_t. False on total internal reflection.
inline bool refract(Vec3 wi, Vec3 n, float eta, Vec3* wt) {
  float cos_i = dot(n, wi);
  float sin2_i = std::max(0.f, 1 - cos_i * cos_i);
  float sin2_t = eta * eta * sin2_i;
  if (sin2_t >= 1) return false;
  float cos_t = std::sqrt(1 - sin2_t);
  *wt = eta * -wi + (eta * cos_i - cos_t) * n;
  return true;
}

}  // namespace rt
