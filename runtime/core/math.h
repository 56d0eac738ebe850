// runtime/core/math.h — scalar helpers the whole renderer shares.
//
// Constants, clamping and interpolation, pbrt-style floating-point error
// bounds (gamma(n) bounds the relative error of n chained float operations,
// Higham's notation, as the pbrt book uses it), ulp stepping for ray-origin
// offsets, and a few special functions (erf inverse for Beckmann sampling).
// Header-only: everything here is on the hot path.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace rt {

// "No index": the archive's kNoIndex, for the runtime's own tables too.
inline constexpr uint32_t kNone = 0xFFFFFFFFu;

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 0.31830988618379067154f;
inline constexpr float kInv2Pi = 0.15915494309189533577f;
inline constexpr float kInv4Pi = 0.07957747154594766788f;
inline constexpr float kPiOver2 = 1.57079632679489661923f;
inline constexpr float kPiOver4 = 0.78539816339744830961f;
inline constexpr float kInfinity = std::numeric_limits<float>::infinity();
// The largest float below 1: samples in [0, 1) are clamped to it.
inline constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;
inline constexpr float kMachineEpsilon = std::numeric_limits<float>::epsilon() * 0.5f;

inline constexpr float gamma_bound(int n) {
  return (n * kMachineEpsilon) / (1 - n * kMachineEpsilon);
}

template <class T>
inline T clamp(T v, T lo, T hi) {
  return v < lo ? lo : (v > hi ? hi : v);
}
inline float lerp(float t, float a, float b) {
  return (1 - t) * a + t * b;
}
inline float radians(float deg) {
  return (kPi / 180) * deg;
}
inline float degrees(float rad) {
  return (180 / kPi) * rad;
}
inline float sqr(float x) {
  return x * x;
}
inline float safe_sqrt(float x) {
  return std::sqrt(std::max(0.f, x));
}
inline float safe_asin(float x) {
  return std::asin(clamp(x, -1.f, 1.f));
}
inline float safe_acos(float x) {
  return std::acos(clamp(x, -1.f, 1.f));
}

inline uint32_t float_to_bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}
inline float bits_to_float(uint32_t u) {
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}
// The next representable float above / below v (used to push ray origins and
// conservative bounds outwards). +inf and -inf stay; both zeros step to the
// smallest denormal of the direction. Branch-free: the interval arithmetic of
// quadric tests calls these a few dozen times per ray.
inline float next_float_up(float v) {
  // -0 + 0 is +0, so both zeros step to the smallest positive denormal.
  int32_t i = int32_t(float_to_bits(v + 0.f));
  i += (i >> 31) | 1;  // magnitude up for v >= 0, down for v < 0
  float r = bits_to_float(uint32_t(i));
  return v == kInfinity ? v : r;
}
inline float next_float_down(float v) {
  return -next_float_up(-v);
}

// Real roots of a t^2 + b t + c in double precision, t0 <= t1.
inline bool solve_quadratic(double a, double b, double c, double* t0, double* t1) {
  double disc = b * b - 4 * a * c;
  if (disc < 0) return false;
  double root = std::sqrt(disc);
  double q = b < 0 ? -0.5 * (b - root) : -0.5 * (b + root);
  if (a == 0) {
    if (b == 0) return false;
    *t0 = *t1 = -c / b;
    return true;
  }
  *t0 = q / a;
  *t1 = q != 0 ? c / q : *t0;
  if (*t0 > *t1) std::swap(*t0, *t1);
  return true;
}

// Inverse error function (Giles' single-precision approximation), for Beckmann sampling.
inline float erf_inv(float x) {
  x = clamp(x, -.99999f, .99999f);
  float w = -std::log((1 - x) * (1 + x)), p;
  if (w < 5) {
    w = w - 2.5f;
    p = 2.81022636e-08f;
    p = 3.43273939e-07f + p * w;
    p = -3.5233877e-06f + p * w;
    p = -4.39150654e-06f + p * w;
    p = 0.00021858087f + p * w;
    p = -0.00125372503f + p * w;
    p = -0.00417768164f + p * w;
    p = 0.246640727f + p * w;
    p = 1.50140941f + p * w;
  } else {
    w = std::sqrt(w) - 3;
    p = -0.000200214257f;
    p = 0.000100950558f + p * w;
    p = 0.00134934322f + p * w;
    p = -0.00367342844f + p * w;
    p = 0.00573950773f + p * w;
    p = -0.0076224613f + p * w;
    p = 0.00943887047f + p * w;
    p = 1.00167406f + p * w;
    p = 2.83297682f + p * w;
  }
  return p * x;
}

inline bool is_power_of_2(uint32_t v) {
  return v && !(v & (v - 1));
}
inline uint32_t round_up_pow2(uint32_t v) {
  v--;
  v |= v >> 1;
  v |= v >> 2;
  v |= v >> 4;
  v |= v >> 8;
  v |= v >> 16;
  return v + 1;
}
inline int log2_int(uint32_t v) {
  return 31 - __builtin_clz(v);
}

// A well-mixed 64-bit hash (splitmix64 finaliser): seeds per pixel, per tile.
inline uint64_t mix_bits(uint64_t v) {
  v ^= v >> 31;
  v *= 0x7fb5d329728ea185ull;
  v ^= v >> 27;
  v *= 0x81dadef4bc2dd44dull;
  v ^= v >> 33;
  return v;
}

}  // namespace rt
