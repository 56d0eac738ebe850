// runtime/geometry/efloat.h — a float that carries a conservative interval.
//
// The pbrt book's running error analysis (3rd ed., ch. 3.9.2): every value is
// a float plus [lo, hi] bounds that are guaranteed to contain the exact real
// result of the same computation on the same inputs. Each operation computes
// the interval in float and widens it by one ulp on each side, which covers
// the rounding of that operation. Used for quadric coefficients and roots so
// t can be tested conservatively, and for the error of ray-parametric points.
#pragma once

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <utility>

#include "runtime/core/math.h"

namespace rt {

struct EFloat {
  float v = 0, lo = 0, hi = 0;

  EFloat() = default;
  // An exact value (err = 0) or one known to within +-err.
  EFloat(float value, float err = 0.f) : v(value), lo(value), hi(value) {
    if (err != 0) {
      lo = next_float_down(value - err);
      hi = next_float_up(value + err);
    }
  }
  static EFloat with_bounds(float value, float lower, float upper) {
    EFloat e;
    e.v = value;
    e.lo = lower;
    e.hi = upper;
    return e;
  }
  explicit operator float() const { return v; }
  float lower() const { return lo; }
  float upper() const { return hi; }
  // The largest distance from v to either bound, rounded up.
  float abs_error() const { return next_float_up(std::max(std::fabs(hi - v), std::fabs(v - lo))); }
};

[[gnu::always_inline]] inline EFloat operator+(EFloat a, EFloat b) {
  return EFloat::with_bounds(a.v + b.v, next_float_down(a.lo + b.lo), next_float_up(a.hi + b.hi));
}
[[gnu::always_inline]] inline EFloat operator-(EFloat a, EFloat b) {
  return EFloat::with_bounds(a.v - b.v, next_float_down(a.lo - b.hi), next_float_up(a.hi - b.lo));
}
[[gnu::always_inline]] inline EFloat operator-(EFloat a) {
  return EFloat::with_bounds(-a.v, -a.hi, -a.lo);
}
[[gnu::always_inline]] inline EFloat operator*(EFloat a, EFloat b) {
  float p0 = a.lo * b.lo, p1 = a.hi * b.lo, p2 = a.lo * b.hi, p3 = a.hi * b.hi;
  return EFloat::with_bounds(a.v * b.v,
                             next_float_down(std::min(std::min(p0, p1), std::min(p2, p3))),
                             next_float_up(std::max(std::max(p0, p1), std::max(p2, p3))));
}
[[gnu::always_inline]] inline EFloat operator/(EFloat a, EFloat b) {
  // A divisor interval touching zero bounds nothing.
  if (b.lo <= 0 && b.hi >= 0) return EFloat::with_bounds(a.v / b.v, -kInfinity, kInfinity);
  float q0 = a.lo / b.lo, q1 = a.hi / b.lo, q2 = a.lo / b.hi, q3 = a.hi / b.hi;
  return EFloat::with_bounds(a.v / b.v,
                             next_float_down(std::min(std::min(q0, q1), std::min(q2, q3))),
                             next_float_up(std::max(std::max(q0, q1), std::max(q2, q3))));
}
[[gnu::always_inline]] inline EFloat operator*(float a, EFloat b) {
  return EFloat(a) * b;
}
[[gnu::always_inline]] inline EFloat operator-(EFloat a, float b) {
  return a - EFloat(b);
}

[[gnu::always_inline]] inline EFloat sqrt(EFloat a) {
  return EFloat::with_bounds(std::sqrt(a.v), next_float_down(std::sqrt(std::max(0.f, a.lo))),
                             next_float_up(std::sqrt(std::max(0.f, a.hi))));
}

// The value an EFloat carries; a float is its own.
inline float value_of(float x) {
  return x;
}
inline float value_of(EFloat x) {
  return x.v;
}

// Roots of a t^2 + b t + c, t0 <= t1 by value, as pbrt-v3 (book 3rd ed.,
// 3.9.4) finds them: the discriminant from the values alone, in double, and
// its root given only its own rounding error. Propagating the discriminant's
// interval instead is more conservative but makes the roots' bounds, and so
// the hit's error box, some 30x wider than pbrt-v3's away from normal
// incidence: spawned rays then start visibly off the surface (brighter
// silhouettes on textures/2d-mappings.pbrt).
//
// T = EFloat, or T = float for the same values without the intervals (EFloat computes its
// values with exactly these float operations), which quadric tests use to reject a ray
// before building any interval.
//
// discriminant_root: the discriminant's square root from the coefficients' values (false when
// it is negative), which the EFloat and float instances share.
inline bool discriminant_root(float av, float bv, float cv, double* root) {
  const double disc = double(bv) * double(bv) - 4.0 * double(av) * double(cv);
  if (disc < 0) return false;
  *root = std::sqrt(disc);
  return true;
}

// The roots given discriminant_root's value for the same a, b, c.
template <class T>
[[gnu::always_inline]] inline void roots_from(T a, T b, T c, double root, T* t0, T* t1) {
  const float bv = value_of(b);
  T root_e;
  if constexpr (std::is_same_v<T, EFloat>)
    root_e = EFloat(float(root), float(kMachineEpsilon * root));
  else
    root_e = float(root);
  T q = bv < 0 ? -0.5f * (b - root_e) : -0.5f * (b + root_e);
  *t0 = q / a;
  *t1 = c / q;
  if (value_of(*t0) > value_of(*t1)) std::swap(*t0, *t1);
}

template <class T>
[[gnu::always_inline]] inline bool solve_quadratic(T a, T b, T c, T* t0, T* t1) {
  double root;
  if (!discriminant_root(value_of(a), value_of(b), value_of(c), &root)) return false;
  roots_from(a, b, c, root, t0, t1);
  return true;
}

}  // namespace rt
