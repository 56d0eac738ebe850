// runtime/medium/phase.h — the Henyey-Greenstein phase function, pbrt-v3's convention.
//
// wo points back along the incoming ray (as a BSDF's wo), so forward
// scattering (g > 0) favours wi close to -wo: p(wo, wi) depends on
// dot(wo, wi) through 1 + g^2 + 2 g cos. sample_hg() draws wi exactly in
// proportion to p and returns p (the pdf equals the value: a phase function
// integrates to 1 over the sphere). Callers keep |g| < 1 (pbrtc refuses
// media outside it).
#pragma once

#include <algorithm>
#include <cmath>

#include "runtime/core/math.h"
#include "runtime/core/vec.h"

namespace rt {

inline float phase_hg(float cos_wo_wi, float g) {
  float denom = 1 + g * g + 2 * g * cos_wo_wi;
  return (1 - g * g) / (4 * kPi * denom * std::sqrt(denom));
}

inline float sample_hg(Vec3 wo, float g, Vec2 u, Vec3* wi) {
  // cos of the angle between wi and the forward direction -wo, by inverting
  // the cdf of HG in that angle (Henyey and Greenstein 1941).
  float cos_theta;
  if (std::fabs(g) < 1e-3f) {
    cos_theta = 1 - 2 * u.x;
  } else {
    float s = (1 - g * g) / (1 - g + 2 * g * u.x);
    cos_theta = (1 + g * g - s * s) / (2 * g);
  }
  cos_theta = std::clamp(cos_theta, -1.f, 1.f);
  float sin_theta = std::sqrt(std::max(0.f, 1 - cos_theta * cos_theta));
  float phi = 2 * kPi * u.y;
  Vec3 fwd = -wo, t1, t2;
  coordinate_system(fwd, &t1, &t2);
  *wi = t1 * (sin_theta * std::cos(phi)) + t2 * (sin_theta * std::sin(phi)) + fwd * cos_theta;
  return phase_hg(-cos_theta, g);
}

}  // namespace rt
