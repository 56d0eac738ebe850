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
// Barycentrics (b0, b1) uniform over a triangle (inline: every area light sample on a mesh).
inline Vec2 uniform_sample_triangle(Vec2 u) {
  const float su0 = std::sqrt(u.x);
  return {1 - su0, u.y * su0};
}

inline float power_heuristic(int nf, float f_pdf, int ng, float g_pdf) {
  float f = nf * f_pdf, g = ng * g_pdf;
  if (std::isinf(f * f)) return 1;
  return (f * f) / (f * f + g * g);
}
inline float balance_heuristic(int nf, float f_pdf, int ng, float g_pdf) {
  return (nf * f_pdf) / (nf * f_pdf + ng * g_pdf);
}

// find_interval() starts from a guide table (the cutpoint method): guide_[j]
// is the search result at u = j/m (m = n/8), so a lookup searches only the entries
// between two neighbouring cutpoints instead of the whole cdf (large
// environment-map tables otherwise miss the cache at every step). The result
// is checked against the cdf and is the same as a full binary search.
class Distribution1D {
 public:
  Distribution1D() = default;
  // Copies f's n values, or with view uses them in place: f must then outlive this object
  // and its copies (an environment map's table in the archive, 32 MB for a 2048x1024 map).
  Distribution1D(const float* f, int n, bool view = false);
  Distribution1D(const Distribution1D& o) { *this = o; }
  Distribution1D& operator=(const Distribution1D& o);
  Distribution1D(Distribution1D&&) noexcept = default;  // a moved vector keeps its buffer
  Distribution1D& operator=(Distribution1D&&) noexcept = default;

  int count() const { return n_; }
  float integral() const { return integral_; }
  float value(int i) const { return func_[i]; }
  // A continuous sample in [0,1), its pdf, and the bucket it fell in.
  float sample_continuous(float u, float* pdf, int* offset = nullptr) const;
  // A bucket, with probability value / sum; *remapped is u rescaled within it.
  int sample_discrete(float u, float* pmf = nullptr, float* remapped = nullptr) const;
  float discrete_pdf(int i) const;
  const float* func_data() const { return func_; }
  const float* cdf_data() const { return cdf_.data(); }

 private:
  int find_interval(float u) const;
  std::vector<float> own_;       // the values, when copied
  const float* func_ = nullptr;  // own_'s or the viewed ones
  int n_ = 0;
  std::vector<float> cdf_;
  std::vector<int> guide_;  // n/8 + 1 cutpoints
  float integral_ = 0;
};

class Distribution2D {
 public:
  Distribution2D() = default;
  // f is nv rows of nu values, copied or (view) used in place as Distribution1D does.
  Distribution2D(const float* f, int nu, int nv, bool view = false);
  Vec2 sample_continuous(Vec2 u, float* pdf) const;
  float pdf(Vec2 p) const;
  // A hint: starts loading the value pdf(p) reads.
  void prefetch_value(Vec2 p) const;

 private:
  const float* cell_value(Vec2 p) const;  // the function value of p's cell
  std::vector<Distribution1D> conditional_;
  Distribution1D marginal_;
};

}  // namespace rt
