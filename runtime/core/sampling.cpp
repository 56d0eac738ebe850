// runtime/core/sampling.cpp — see sampling.h.
#include "runtime/core/sampling.h"

#include <algorithm>

namespace rt {

// Entries of a Distribution1D's cdf per cutpoint of its guide table.
constexpr int kGuideStep = 8;

Vec2 concentric_sample_disk(Vec2 u) {
  float ox = 2 * u.x - 1, oy = 2 * u.y - 1;
  if (ox == 0 && oy == 0) return {0, 0};
  float r, theta;
  if (std::fabs(ox) > std::fabs(oy)) {
    r = ox;
    theta = kPiOver4 * (oy / ox);
  } else {
    r = oy;
    theta = kPiOver2 - kPiOver4 * (ox / oy);
  }
  return {r * std::cos(theta), r * std::sin(theta)};
}

Vec2 uniform_sample_disk(Vec2 u) {
  float r = std::sqrt(u.x), theta = 2 * kPi * u.y;
  return {r * std::cos(theta), r * std::sin(theta)};
}

Vec3 uniform_sample_hemisphere(Vec2 u) {
  float z = u.x, r = safe_sqrt(1 - z * z), phi = 2 * kPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

Vec3 uniform_sample_sphere(Vec2 u) {
  float z = 1 - 2 * u.x, r = safe_sqrt(1 - z * z), phi = 2 * kPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

Vec3 uniform_sample_cone(Vec2 u, float cos_max) {
  float cos_theta = (1 - u.x) + u.x * cos_max;
  float sin_theta = safe_sqrt(1 - cos_theta * cos_theta);
  float phi = u.y * 2 * kPi;
  return {std::cos(phi) * sin_theta, std::sin(phi) * sin_theta, cos_theta};
}

Distribution1D::Distribution1D(const float* f, int n, bool view)
    : own_(view ? f + n : f, f + n), func_(view ? f : own_.data()), n_(n), cdf_(n + 1) {
  cdf_[0] = 0;
  for (int i = 1; i <= n; ++i) cdf_[i] = cdf_[i - 1] + std::fabs(func_[i - 1]) / n;
  integral_ = cdf_[n];
  if (integral_ == 0) {
    for (int i = 1; i <= n; ++i) cdf_[i] = float(i) / n;
  } else {
    for (int i = 1; i <= n; ++i) cdf_[i] /= integral_;
  }
  // guide_[j]: how many cdf entries are <= j / m (what upper_bound returns), m = n / 8
  // rounded up: a search between two cutpoints covers about 8 entries, one cache line, and
  // the guide takes an eighth of the cdf's memory (an environment map's distribution has
  // 4096 x 2048 entries). Only for a finite, hence sorted, cdf.
  if (!std::isfinite(integral_)) return;
  const int m = (n + kGuideStep - 1) / kGuideStep;
  guide_.resize(size_t(m) + 1);
  int i = 0;
  for (int j = 0; j <= m; ++j) {
    float t = float(j) / float(m);
    while (i <= n && cdf_[i] <= t) ++i;
    guide_[j] = i;
  }
}

Distribution1D& Distribution1D::operator=(const Distribution1D& o) {
  if (this == &o) return *this;
  own_ = o.own_;
  func_ = o.func_ == o.own_.data() ? own_.data() : o.func_;
  n_ = o.n_;
  cdf_ = o.cdf_;
  guide_ = o.guide_;
  integral_ = o.integral_;
  return *this;
}

namespace {

// The last i with cdf[i] <= u, clamped to a valid bucket.
int cdf_interval(const float* cdf, int n, float u) {
  const float* it = std::upper_bound(cdf, cdf + n + 1, u);
  return clamp(int(it - cdf) - 1, 0, n - 1);
}

}  // namespace

int Distribution1D::find_interval(float u) const {
  const int n = count();
  const float* cdf = cdf_.data();
  if (n > 8 && !guide_.empty() && u >= 0 && u < 1) {
    const int m = int(guide_.size()) - 1;
    int j = std::min(int(u * float(m)), m - 1);
    int lo = guide_[j], hi = guide_[j + 1];
    // The answer (the count of entries <= u) lies in [lo, hi] when cdf[lo-1]
    // <= u < cdf[hi]; float rounding of u * n could break that at a cutpoint,
    // so check and fall back to the full search.
    if ((lo == 0 || cdf[lo - 1] <= u) && (hi > n || cdf[hi] > u)) {
      const float* it = std::upper_bound(cdf + lo, cdf + std::min(hi, n + 1), u);
      return clamp(int(it - cdf) - 1, 0, n - 1);
    }
  }
  return cdf_interval(cdf, n, u);
}

float Distribution1D::sample_continuous(float u, float* pdf, int* offset) const {
  int i = find_interval(u);
  if (offset) *offset = i;
  float du = u - cdf_[i];
  if (cdf_[i + 1] - cdf_[i] > 0) du /= cdf_[i + 1] - cdf_[i];
  if (pdf) *pdf = integral_ > 0 ? func_[i] / integral_ : 0;
  return (i + du) / count();
}

int Distribution1D::sample_discrete(float u, float* pmf, float* remapped) const {
  const int i = find_interval(u);
  if (pmf) *pmf = discrete_pdf(i);
  if (remapped) {
    const float w = cdf_[i + 1] - cdf_[i];
    *remapped = w > 0 ? std::min((u - cdf_[i]) / w, kOneMinusEpsilon) : 0;
  }
  return i;
}

float Distribution1D::discrete_pdf(int i) const {
  return integral_ > 0 ? func_[i] / (integral_ * count()) : 0;
}

Distribution2D::Distribution2D(const float* f, int nu, int nv, bool view) {
  conditional_.reserve(nv);
  std::vector<float> marginal(nv);
  for (int v = 0; v < nv; ++v) {
    conditional_.emplace_back(f + size_t(v) * nu, nu, view);
    marginal[v] = conditional_.back().integral();
  }
  marginal_ = Distribution1D(marginal.data(), nv);
}

Vec2 Distribution2D::sample_continuous(Vec2 u, float* pdf) const {
  float pdfs[2];
  int v;
  float d1 = marginal_.sample_continuous(u.y, &pdfs[1], &v);
  float d0 = conditional_[v].sample_continuous(u.x, &pdfs[0]);
  *pdf = pdfs[0] * pdfs[1];
  return {d0, d1};
}

const float* Distribution2D::cell_value(Vec2 p) const {
  int nu = conditional_[0].count(), nv = marginal_.count();
  int iu = clamp(int(p.x * nu), 0, nu - 1);
  int iv = clamp(int(p.y * nv), 0, nv - 1);
  return conditional_[iv].func_data() + iu;
}

float Distribution2D::pdf(Vec2 p) const {
  const float* value = cell_value(p);
  if (marginal_.integral() == 0) return 0;
  return *value / marginal_.integral();
}

void Distribution2D::prefetch_value(Vec2 p) const {
  if (!conditional_.empty()) __builtin_prefetch(cell_value(p));
}

}  // namespace rt
