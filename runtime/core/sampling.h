// runtime/core/sampling.h — warping uniform samples to the distributions
// rendering needs, and tabulated 1-D/2-D distributions.
//
// Each warp has its pdf beside it (solid angle or area as named). Distribution1D
// samples a piecewise-constant function in proportion to its values;
// Distribution2D does so over [0,1]^2 (marginal over v, conditionals over u),
// for environment maps and the power light distribution.
#pragma once

#include <vector>

#include "runtime/core/vec.h"

namespace rt {

Vec2 concentric_sample_disk(Vec2 u);
Vec2 uniform_sample_disk(Vec2 u);
inline Vec3 cosine_sample_hemisphere(Vec2 u) {
  Vec2 d = concentric_sample_disk(u);
  float z = safe_sqrt(1 - d.x * d.x - d.y * d.y);
  return {d.x, d.y, z};
}
inline float cosine_hemisphere_pdf(float cos_theta) {
  return cos_theta * kInvPi;
}
Vec3 uniform_sample_hemisphere(Vec2 u);
inline float uniform_hemisphere_pdf() {
  return kInv2Pi;
}
Vec3 uniform_sample_sphere(Vec2 u);
inline float uniform_sphere_pdf() {
  return kInv4Pi;
}
Vec3 uniform_sample_cone(Vec2 u, float cos_theta_max);
inline float uniform_cone_pdf(float cos_theta_max) {
  return 1 / (2 * kPi * (1 - cos_theta_max));
}
// Barycentrics (b0, b1) uniform over a triangle.
Vec2 uniform_sample_triangle(Vec2 u);

inline float power_heuristic(int nf, float f_pdf, int ng, float g_pdf) {
  float f = nf * f_pdf, g = ng * g_pdf;
  if (std::isinf(f * f)) return 1;
  return (f * f) / (f * f + g * g);
}
inline float balance_heuristic(int nf, float f_pdf, int ng, float g_pdf) {
  return (nf * f_pdf) / (nf * f_pdf + ng * g_pdf);
}

class Distribution1D {
 public:
  Distribution1D() = default;
  Distribution1D(const float* f, int n);
  int count() const { return int(func_.size()); }
  float integral() const { return integral_; }
  float value(int i) const { return func_[i]; }
  // A continuous sample in [0,1), its pdf, and the bucket it fell in.
  float sample_continuous(float u, float* pdf, int* offset = nullptr) const;
  // A bucket, with probability value / sum; *remapped is u rescaled within it.
  int sample_discrete(float u, float* pmf = nullptr, float* remapped = nullptr) const;
  float discrete_pdf(int i) const;

 private:
  int find_interval(float u) const;
  std::vector<float> func_, cdf_;
  float integral_ = 0;
};

class Distribution2D {
 public:
  Distribution2D() = default;
  // f is nv rows of nu values.
  Distribution2D(const float* f, int nu, int nv);
  Vec2 sample_continuous(Vec2 u, float* pdf) const;
  float pdf(Vec2 p) const;

 private:
  std::vector<Distribution1D> conditional_;
  Distribution1D marginal_;
};

}  // namespace rt
