// runtime/core/rgb.h — the renderer's spectrum: linear RGB, as pbrt-v3's RGB build.
//
// pbrtc has already turned every spectrum (rgb, xyz, blackbody, .spd, named
// metals) into the RGB that pbrt-v3's RGBSpectrum would hold, so the runtime
// only ever multiplies triples. luminance() uses pbrt-v3's Y weights (sRGB
// primaries, D65), which maxsampleluminance, the power light distribution and
// Russian roulette depend on.
#pragma once

#include <cmath>

#include "runtime/core/math.h"

namespace rt {

struct Rgb {
  float r = 0, g = 0, b = 0;
  Rgb() = default;
  constexpr Rgb(float r_, float g_, float b_) : r(r_), g(g_), b(b_) {}
  explicit constexpr Rgb(float v) : r(v), g(v), b(v) {}
  float operator[](int i) const { return i == 0 ? r : (i == 1 ? g : b); }
  float& operator[](int i) { return i == 0 ? r : (i == 1 ? g : b); }
  Rgb& operator+=(Rgb o) {
    r += o.r;
    g += o.g;
    b += o.b;
    return *this;
  }
  Rgb& operator*=(Rgb o) {
    r *= o.r;
    g *= o.g;
    b *= o.b;
    return *this;
  }
  Rgb& operator*=(float s) {
    r *= s;
    g *= s;
    b *= s;
    return *this;
  }
  Rgb& operator/=(float s) {
    float i = 1 / s;
    return *this *= i;
  }
  bool is_black() const { return r == 0 && g == 0 && b == 0; }
  bool has_nan() const { return std::isnan(r) || std::isnan(g) || std::isnan(b); }
  bool is_finite() const { return std::isfinite(r) && std::isfinite(g) && std::isfinite(b); }
  float max_component() const { return std::max(r, std::max(g, b)); }
  float average() const { return (r + g + b) / 3; }
  float luminance() const { return 0.212671f * r + 0.715160f * g + 0.072169f * b; }
};
inline Rgb operator+(Rgb a, Rgb b) {
  return {a.r + b.r, a.g + b.g, a.b + b.b};
}
inline Rgb operator-(Rgb a, Rgb b) {
  return {a.r - b.r, a.g - b.g, a.b - b.b};
}
inline Rgb operator*(Rgb a, Rgb b) {
  return {a.r * b.r, a.g * b.g, a.b * b.b};
}
inline Rgb operator/(Rgb a, Rgb b) {
  return {b.r != 0 ? a.r / b.r : 0, b.g != 0 ? a.g / b.g : 0, b.b != 0 ? a.b / b.b : 0};
}
inline Rgb operator*(Rgb a, float s) {
  return {a.r * s, a.g * s, a.b * s};
}
inline Rgb operator*(float s, Rgb a) {
  return {a.r * s, a.g * s, a.b * s};
}
inline Rgb operator/(Rgb a, float s) {
  float i = 1 / s;
  return a * i;
}
inline bool operator==(Rgb a, Rgb b) {
  return a.r == b.r && a.g == b.g && a.b == b.b;
}
inline bool operator!=(Rgb a, Rgb b) {
  return !(a == b);
}
inline Rgb sqrt(Rgb a) {
  return {std::sqrt(a.r), std::sqrt(a.g), std::sqrt(a.b)};
}
inline Rgb exp(Rgb a) {
  return {std::exp(a.r), std::exp(a.g), std::exp(a.b)};
}
inline Rgb clamp(Rgb a, float lo = 0, float hi = kInfinity) {
  return {clamp(a.r, lo, hi), clamp(a.g, lo, hi), clamp(a.b, lo, hi)};
}
inline Rgb lerp(float t, Rgb a, Rgb b) {
  return (1 - t) * a + t * b;
}

}  // namespace rt
