// runtime/core/fast_trig.h — arccosine and atan2 in float, inline, within 3 float ulps
// (5e-7 absolute) of the exact values: for an environment map's coordinates of a direction,
// taken for every light sample's density and every escaping ray, where libm's acosf and
// atan2f (with its wrapper) cost about three times the polynomials below (callgrind). Values
// differ from libm's by rounding only; also for a quadric hit's (u, v) where no cut compares
// the angle (a whole turn's phi, a sphere's theta). Angles pbrt-v3's intersection tests
// compare against limits (a cut quadric's phi, curve frames) keep libm. Sine and cosine stay
// libm's (its sincosf took fewer instructions than a reduction and two series here) but for
// angles within pi/4 of 0, which need no reduction: the concentric disk mapping's, for every
// cosine-weighted direction and lens sample (libm's sincosf was 2.5% of a bdpt render, perf).
#pragma once

#include <algorithm>
#include <cmath>

#include "runtime/core/math.h"

namespace rt {

// acos z for z in [-1, 1] (clamped): Abramowitz and Stegun, Handbook of Mathematical
// Functions, 4.4.46 (sqrt(1 - z) times a degree-7 polynomial, |error| <= 2e-8 on [0, 1]),
// mirrored for negative z: exactly 0 at 1 and pi (as a float) at -1.
inline float fast_acos(float z) {
  const float a = std::min(std::fabs(z), 1.f);
  const float p =
      1.5707963050f +
      a * (-0.2145988016f +
           a * (0.0889789874f +
                a * (-0.0501743046f +
                     a * (0.0308918810f +
                          a * (-0.0170881256f + a * (0.0066700901f + a * -0.0012624911f))))));
  const float t = std::sqrt(1 - a) * p;
  return z < 0 ? kPi - t : t;
}

// atan2(y, x) in [-pi, pi], 0 when both are 0: atan of min/max of |x| and |y| (in [0, 1]) by
// Abramowitz and Stegun 4.4.49 (x times a degree-16 even polynomial, |error| <= 2e-8 on
// [0, 1]), unfolded by octant.
inline float fast_atan2(float y, float x) {
  const float ax = std::fabs(x), ay = std::fabs(y), hi = std::max(ax, ay);
  const float a = hi > 0 ? std::min(ax, ay) / hi : 0, a2 = a * a;
  float p =
      a * (1 + a2 * (-0.3333314528f +
                     a2 * (0.1999355085f +
                           a2 * (-0.1420889944f +
                                 a2 * (0.1065626393f +
                                       a2 * (-0.0752896400f +
                                             a2 * (0.0429096138f + a2 * (-0.0161657367f +
                                                                         a2 * 0.0028662257f))))))));
  if (ay > ax) p = kPiOver2 - p;
  if (x < 0) p = kPi - p;
  return y < 0 ? -p : p;
}

// sin and cos of phi for |phi| <= pi/4, within 2 float ulps of the exact values: their Taylor
// series to phi^9 and phi^10 (the first terms left out are below 2e-9 there), by Horner's rule
// in phi^2.
inline void sin_cos_quarter(float phi, float* s, float* c) {
  const float p2 = phi * phi;
  *s = phi * (1 + p2 * (-1.f / 6 + p2 * (1.f / 120 + p2 * (-1.f / 5040 + p2 * (1.f / 362880)))));
  *c = 1 + p2 * (-0.5f +
                 p2 * (1.f / 24 + p2 * (-1.f / 720 + p2 * (1.f / 40320 + p2 * (-1.f / 3628800)))));
}

}  // namespace rt
