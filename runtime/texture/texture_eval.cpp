// runtime/texture/texture_eval.cpp — see textures.h: evaluating a node at a surface point,
// one switch over the kinds, in pbrt-v3's arithmetic (float textures in float,
// spectrum textures per RGB channel).
#include <cmath>
#include <type_traits>

#include "runtime/texture/noise.h"
#include "runtime/texture/textures.h"

namespace rt {

namespace {

template <class T>
T from_rgb(Rgb v) {
  if constexpr (std::is_same_v<T, float>)
    return v.r;
  else
    return v;
}

// pbrt-v3's marble colour spline: control points of a cubic Bezier through
// greys and a dark blue-grey vein, from pbrt-v3's textures/marble.h (the
// book's section 10.6.5).
constexpr float kMarbleColors[9][3] = {
    {.58f, .58f, .6f}, {.58f, .58f, .6f}, {.58f, .58f, .6f}, {.5f, .5f, .5f},   {.6f, .59f, .58f},
    {.58f, .58f, .6f}, {.58f, .58f, .6f}, {.2f, .2f, .33f},  {.58f, .58f, .6f},
};

Rgb marble(Vec3 p, Vec3 dpdx, Vec3 dpdy, const TextureNode& n) {
  p *= n.scale;
  float m = p.y + n.variation * fbm(p, n.scale * dpdx, n.scale * dpdy, n.omega, n.octaves);
  float t = .5f + .5f * std::sin(m);
  constexpr int kSegments = 9 - 3;
  // pbrt-v3 takes min(1, segment), so only the first two segments are used;
  // we keep that for identical images.
  int first = std::min(1, int(std::floor(t * kSegments)));
  t = t * kSegments - first;
  auto c = [&](int k) {
    const float* v = kMarbleColors[first + k];
    return Rgb(v[0], v[1], v[2]);
  };
  // De Casteljau evaluation of the cubic.
  Rgb s0 = (1.f - t) * c(0) + t * c(1);
  Rgb s1 = (1.f - t) * c(1) + t * c(2);
  Rgb s2 = (1.f - t) * c(2) + t * c(3);
  s0 = (1.f - t) * s0 + t * s1;
  s1 = (1.f - t) * s1 + t * s2;
  return 1.5f * ((1.f - t) * s0 + t * s1);  // pbrt-v3's extra 1.5 for more contrast
}

// pbrt-v3's closed-form box filter of the checkerboard: the fraction of the
// filter square [s0,s1]x[t0,t1] covered by tex2's checks.
float checker_tex2_fraction(Vec2 st, Vec2 dstdx, Vec2 dstdy, bool* single, bool* first_check) {
  float ds = std::max(std::fabs(dstdx.x), std::fabs(dstdy.x));
  float dt = std::max(std::fabs(dstdx.y), std::fabs(dstdy.y));
  float s0 = st.x - ds, s1 = st.x + ds;
  float t0 = st.y - dt, t1 = st.y + dt;
  *single = std::floor(s0) == std::floor(s1) && std::floor(t0) == std::floor(t1);
  *first_check = (int(std::floor(st.x)) + int(std::floor(st.y))) % 2 == 0;
  if (*single) return 0;
  // Integral of the 1-D square wave (0 on even cells, 1 on odd ones) from 0 to x.
  auto bump_int = [](float x) {
    return int(std::floor(x / 2)) + 2 * std::max(x / 2 - int(std::floor(x / 2)) - 0.5f, 0.f);
  };
  // A zero-width side (only one of s, t changes across the pixel) is pbrt-v3's
  // 0/0 = NaN; its limit is the square wave at the point: 1 in odd cells.
  auto odd = [](float x) { return float(int(std::floor(x)) & 1); };
  float s_int = ds > 0 ? (bump_int(s1) - bump_int(s0)) / (2 * ds) : odd(st.x);
  float t_int = dt > 0 ? (bump_int(t1) - bump_int(t0)) / (2 * dt) : odd(st.y);
  float area2 = s_int + t_int - 2 * s_int * t_int;
  if (ds > 1 || dt > 1) area2 = .5f;
  return area2;
}

}  // namespace

template <class T>
T TextureSet::evaluate(const TextureNode& n, const SurfaceInteraction& si) const {
  constexpr bool kFloat = std::is_same_v<T, float>;
  T* tag = nullptr;
  switch (n.kind) {
    case TextureKind::kConstant:
      return from_rgb<T>(n.v[0]);
    case TextureKind::kScale:
      return operand(n, 0, si, tag) * operand(n, 1, si, tag);
    case TextureKind::kMix: {
      float amount = eval(n.f[2], si);
      T t1 = T(0.f), t2 = T(0.f);
      // pbrt-v3 skips an operand whose weight is exactly 0.
      if (amount != 1) t1 = operand(n, 0, si, tag);
      if (amount != 0) t2 = operand(n, 1, si, tag);
      return (1 - amount) * t1 + amount * t2;
    }
    case TextureKind::kBilerp: {
      Vec2 dstdx, dstdy;
      Vec2 st = n.map2.map(si, &dstdx, &dstdy);
      return (1 - st.x) * (1 - st.y) * from_rgb<T>(n.v[0]) +
             (1 - st.x) * (st.y) * from_rgb<T>(n.v[1]) + (st.x) * (1 - st.y) * from_rgb<T>(n.v[2]) +
             (st.x) * (st.y) * from_rgb<T>(n.v[3]);
    }
    case TextureKind::kImage: {
      Vec2 dstdx, dstdy;
      Vec2 st = n.map2.map(si, &dstdx, &dstdy);
      const MipMap& m = mipmaps_[n.mipmap];
      if (n.trilinear) {
        float width = 2 * std::max(std::max(std::fabs(dstdx.x), std::fabs(dstdx.y)),
                                   std::max(std::fabs(dstdy.x), std::fabs(dstdy.y)));
        if constexpr (kFloat)
          return m.lookup_trilinear_float(st, width);
        else
          return m.lookup_trilinear(st, width);
      }
      if constexpr (kFloat)
        return m.lookup_ewa_float(st, dstdx, dstdy, n.max_anisotropy);
      else
        return m.lookup_ewa(st, dstdx, dstdy, n.max_anisotropy);
    }
    case TextureKind::kChecker2D: {
      Vec2 dstdx, dstdy;
      Vec2 st = n.map2.map(si, &dstdx, &dstdy);
      if (!n.closed_form) {
        bool first = (int(std::floor(st.x)) + int(std::floor(st.y))) % 2 == 0;
        return operand(n, first ? 0 : 1, si, tag);
      }
      bool single, first;
      float area2 = checker_tex2_fraction(st, dstdx, dstdy, &single, &first);
      if (single) return operand(n, first ? 0 : 1, si, tag);
      return (1 - area2) * operand(n, 0, si, tag) + area2 * operand(n, 1, si, tag);
    }
    case TextureKind::kChecker3D: {
      Vec3 dpdx, dpdy;
      Vec3 p = n.map3.map(si, &dpdx, &dpdy);
      bool first = (int(std::floor(p.x)) + int(std::floor(p.y)) + int(std::floor(p.z))) % 2 == 0;
      return operand(n, first ? 0 : 1, si, tag);
    }
    case TextureKind::kDots: {
      Vec2 dstdx, dstdy;
      Vec2 st = n.map2.map(si, &dstdx, &dstdy);
      int s_cell = int(std::floor(st.x + .5f)), t_cell = int(std::floor(st.y + .5f));
      // Each cell holds a dot or not, by the sign of noise at its centre; the
      // dot is jittered within the cell by two more noise values.
      if (noise(s_cell + .5f, t_cell + .5f) > 0) {
        const float radius = .35f;
        const float max_shift = 0.5f - radius;
        float s_center = s_cell + max_shift * noise(s_cell + 1.5f, t_cell + 2.8f);
        float t_center = t_cell + max_shift * noise(s_cell + 4.5f, t_cell + 9.8f);
        float ds = st.x - s_center, dt = st.y - t_center;
        if (ds * ds + dt * dt < radius * radius) return operand(n, 0, si, tag);
      }
      return operand(n, 1, si, tag);
    }
    case TextureKind::kFbm:
    case TextureKind::kWrinkled:
    case TextureKind::kWindy: {
      Vec3 dpdx, dpdy;
      Vec3 p = n.map3.map(si, &dpdx, &dpdy);
      float v;
      if (n.kind == TextureKind::kFbm) {
        v = fbm(p, dpdx, dpdy, n.omega, n.octaves);
      } else if (n.kind == TextureKind::kWrinkled) {
        v = turbulence(p, dpdx, dpdy, n.omega, n.octaves);
      } else {
        // Wind strength varies slowly (a tenth the frequency, 3 octaves) and
        // scales the wave height.
        float wind = fbm(.1f * p, .1f * dpdx, .1f * dpdy, .5f, 3);
        float wave = fbm(p, dpdx, dpdy, .5f, 6);
        v = std::fabs(wind) * wave;
      }
      return T(v);
    }
    case TextureKind::kMarble: {
      Vec3 dpdx, dpdy;
      Vec3 p = n.map3.map(si, &dpdx, &dpdy);
      return from_rgb<T>(marble(p, dpdx, dpdy, n));
    }
    case TextureKind::kUv: {
      Vec2 dstdx, dstdy;
      Vec2 st = n.map2.map(si, &dstdx, &dstdy);
      return from_rgb<T>(Rgb(st.x - std::floor(st.x), st.y - std::floor(st.y), 0));
    }
  }
  return T(0.f);
}

float TextureSet::eval_float(uint32_t texture, const SurfaceInteraction& si) const {
  return evaluate<float>(nodes_[texture], si);
}

Rgb TextureSet::eval_rgb(uint32_t texture, const SurfaceInteraction& si) const {
  return evaluate<Rgb>(nodes_[texture], si);
}

}  // namespace rt
