// runtime/core/sampling.h — warping uniform samples to the distributions
// rendering needs, and tabulated 1-D/2-D distributions.
//
// Each warp has its pdf beside it (solid angle or area as named). Distribution1D
// samples a piecewise-constant function in proportion to its values;
// Distribution2D does so over [0,1]^2 (marginal over v, conditionals over u),
// for environment maps and the power light distribution.
#pragma once

#include <new>
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

// A vector whose buffer starts on a 64-byte cache line.
template <class T>
struct CacheLineAllocator {
  using value_type = T;
  CacheLineAllocator() = default;
  template <class U>
  CacheLineAllocator(const CacheLineAllocator<U>&) {}
  T* allocate(size_t n) {
    return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(64)));
  }
  void deallocate(T* p, size_t) { ::operator delete(p, std::align_val_t(64)); }
  bool operator==(const CacheLineAllocator&) const { return true; }
  bool operator!=(const CacheLineAllocator&) const { return false; }
};
using CacheLineFloats = std::vector<float, CacheLineAllocator<float>>;

// A cdf search in two steps: a coarse table of every 16th cdf entry (a sixteenth of the cdf,
// small enough to stay in cache) finds the 64-byte line of the cdf that holds the answer,
// and one search inside that line finishes it. A plain binary search over a large table (an
// environment map's rows) misses the cache at nearly every step; this misses once, and the
// function value the pdf needs can be fetched alongside. The result is the same as a full
// binary search's (std::upper_bound, less one, clamped to a bucket).
class Distribution1D {
 public:
  Distribution1D() = default;
  Distribution1D(const float* f, int n);  // copies f's n values

  int count() const { return n_; }
  float integral() const { return integral_; }
  float value(int i) const { return func_[size_t(i)]; }
  // A continuous sample in [0,1), its pdf, and the bucket it fell in.
  float sample_continuous(float u, float* pdf, int* offset = nullptr) const;
  // A bucket, with probability value / sum; *remapped is u rescaled within it.
  int sample_discrete(float u, float* pmf = nullptr, float* remapped = nullptr) const;
  float discrete_pdf(int i) const;
  const float* func_data() const { return func_.data(); }
  const float* cdf_data() const { return cdf_.data(); }

 private:
  int find_interval(float u) const;
  std::vector<float> func_;
  int n_ = 0;
  std::vector<float> cdf_;     // n + 1 entries, padded to whole lines with a coarse table
  std::vector<float> coarse_;  // cdf_[16 k], k = 0 .. n / 16; empty if the cdf is not finite,
                               // or fits a line or two anyway (n <= 16)
  float integral_ = 0;
};

// Rows are laid out flat: row v's values, cdf and coarse table start at v times their row
// length in three arrays (each cdf row on a cache line of its own start), so once the
// marginal has chosen v no per-row object or pointer is read. Every bucket and pdf equals a
// Distribution1D's over the row.
class Distribution2D {
 public:
  Distribution2D() = default;
  // f is nv rows of nu values, copied, or with view used in place: f must then outlive this
  // object and its copies (an environment map's table in the archive: a copy would be 32 MB
  // for a 2048x1024 map).
  Distribution2D(const float* f, int nu, int nv, bool view = false);
  Distribution2D(const Distribution2D& o) { *this = o; }
  Distribution2D& operator=(const Distribution2D& o);
  Distribution2D(Distribution2D&&) noexcept = default;
  Distribution2D& operator=(Distribution2D&&) noexcept = default;

  Vec2 sample_continuous(Vec2 u, float* pdf) const;
  float pdf(Vec2 p) const;
  // A hint: starts loading the value pdf(p) reads.
  void prefetch_value(Vec2 p) const;
  // A hint: starts loading the line of a row's cdf (and its values) that sample_continuous(u)
  // will read, a cache miss that work done between the two calls hides. The marginal and the
  // rows' coarse tables it reads to find that line are small enough to stay in cache.
  void prefetch_sample(Vec2 u) const;

 private:
  const float* cell_value(Vec2 p) const;  // the function value of p's cell
  std::vector<float> own_;                // the values, when copied
  const float* func_ = nullptr;           // own_'s or the viewed ones, nv rows of nu
  int nu_ = 0, nv_ = 0;
  size_t cdf_stride_ = 0, coarse_stride_ = 0;  // floats a row
  CacheLineFloats cdf_;                        // nv rows of nu + 1, padded to whole lines
  std::vector<float> coarse_;                  // nv rows of nu / 16 + 1
  Distribution1D marginal_;                    // over the rows' integrals
};

}  // namespace rt
