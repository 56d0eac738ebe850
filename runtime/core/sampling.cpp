// runtime/core/sampling.cpp — see sampling.h.
#include "runtime/core/sampling.h"

#include <algorithm>

#include "runtime/core/fast_trig.h"

namespace rt {

Vec2 concentric_sample_disk(Vec2 u) {
  float ox = 2 * u.x - 1, oy = 2 * u.y - 1;
  if (ox == 0 && oy == 0) return {0, 0};
  // pbrt's angle is pi/4 (oy / ox), or pi/2 - pi/4 (ox / oy), whose cosine and sine are the
  // sine and cosine of pi/4 (ox / oy): either way an angle within pi/4 of 0.
  float s, c;
  if (std::fabs(ox) > std::fabs(oy)) {
    sin_cos_quarter(kPiOver4 * (oy / ox), &s, &c);
    return {ox * c, ox * s};
  }
  sin_cos_quarter(kPiOver4 * (ox / oy), &s, &c);
  return {oy * s, oy * c};
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

namespace {

// cdf entries a coarse table entry stands for: one 64-byte line.
constexpr int kLine = 16;

// cdf[0..n] of f's n values (|f|, normalised; uniform when they sum to 0); returns their
// integral over [0,1].
float build_cdf(const float* f, int n, float* cdf) {
  cdf[0] = 0;
  for (int i = 1; i <= n; ++i) cdf[i] = cdf[i - 1] + std::fabs(f[i - 1]) / n;
  const float integral = cdf[n];
  if (integral == 0) {
    for (int i = 1; i <= n; ++i) cdf[i] = float(i) / n;
  } else {
    for (int i = 1; i <= n; ++i) cdf[i] /= integral;
  }
  return integral;
}

int coarse_count(int n) {
  return n / kLine + 1;
}

void build_coarse(const float* cdf, int n, float* coarse) {
  for (int k = 0; k < coarse_count(n); ++k) coarse[k] = cdf[k * kLine];
}

// A cdf with a coarse table is stored as whole lines, cdf[n] followed by +inf (above every u)
// to the end of the last: whichever line the coarse table names is counted whole.
size_t padded_cdf_size(int n) {
  return size_t(coarse_count(n)) * kLine;
}
void pad_cdf(float* cdf, int n) {
  std::fill(cdf + n + 1, cdf + padded_cdf_size(n), kInfinity);
}

// How many of a sorted run's m entries are <= u, without branches: a binary search over a
// random u mispredicts about every other step, and a short run is cheaper to count whole
// (the compiler vectorises the loop). Sorted, so the count is upper_bound's offset.
int count_at_most(const float* a, int m, float u) {
  int c = 0;
  for (int j = 0; j < m; ++j) c += a[j] <= u;
  return c;
}

// Coarse tables up to this length are counted, longer ones binary-searched.
constexpr int kCountedCoarse = 64;

// Where the line of the cdf that holds u's bucket starts (-1: before the first entry).
// Sorted, so the entries <= u are a prefix: the last coarse entry <= u, cdf[16 k], and the
// next, cdf[16 k + 16] > u, bound the answer to 16 k .. 16 k + 15.
int line_start(const float* coarse, int n, float u) {
  const int m = coarse_count(n);
  const int k = m <= kCountedCoarse ? count_at_most(coarse, m, u)
                                    : int(std::upper_bound(coarse, coarse + m, u) - coarse);
  return (k - 1) * kLine;
}

// The last i with cdf[i] <= u, clamped to a bucket. A sorted (finite) cdf is counted: within
// the line its coarse table (every 16th entry) names (the cdf padded by pad_cdf), or whole
// when it has none (16 buckets or fewer). One that is not finite, hence maybe not sorted, has
// no coarse table and is binary-searched in full. With func, the line of values beside the
// answer's cdf line is fetched too.
int find_interval(const float* cdf, const float* coarse, int n, float u, bool sorted,
                  const float* func = nullptr) {
  if (!coarse) {
    if (sorted) return clamp(count_at_most(cdf, n + 1, u) - 1, 0, n - 1);
    const float* it = std::upper_bound(cdf, cdf + n + 1, u);
    return clamp(int(it - cdf) - 1, 0, n - 1);
  }
  const int lo = line_start(coarse, n, u);
  if (lo < 0) return 0;
  if (func) {
    __builtin_prefetch(func + lo);
    __builtin_prefetch(func + std::min(lo + kLine - 1, n - 1));
  }
  // cdf[lo] <= u, so the answer is lo plus the count of the line's other entries <= u.
  return clamp(lo + count_at_most(cdf + lo, kLine, u) - 1, 0, n - 1);
}

// A continuous sample in [0,1) of one tabulated function, its pdf and bucket.
float sample_table(const float* func, const float* cdf, const float* coarse, int n, float integral,
                   float u, float* pdf, int* offset) {
  const int i = find_interval(cdf, coarse, n, u, std::isfinite(integral), pdf ? func : nullptr);
  if (offset) *offset = i;
  float du = u - cdf[i];
  if (cdf[i + 1] - cdf[i] > 0) du /= cdf[i + 1] - cdf[i];
  if (pdf) *pdf = integral > 0 ? func[i] / integral : 0;
  return (i + du) / n;
}

}  // namespace

Distribution1D::Distribution1D(const float* f, int n)
    : func_(f, f + n), n_(n), cdf_(size_t(n) + 1) {
  integral_ = build_cdf(f, n, cdf_.data());
  // Small distributions (a light choice per voxel, thousands of them) skip the coarse table.
  if (!std::isfinite(integral_) || n <= kLine) return;
  cdf_.resize(padded_cdf_size(n));
  pad_cdf(cdf_.data(), n);
  coarse_.resize(size_t(coarse_count(n)));
  build_coarse(cdf_.data(), n, coarse_.data());
}

int Distribution1D::find_interval(float u) const {
  return rt::find_interval(cdf_.data(), coarse_.empty() ? nullptr : coarse_.data(), n_, u,
                           std::isfinite(integral_));
}

float Distribution1D::sample_continuous(float u, float* pdf, int* offset) const {
  return sample_table(func_.data(), cdf_.data(), coarse_.empty() ? nullptr : coarse_.data(), n_,
                      integral_, u, pdf, offset);
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
  return integral_ > 0 ? func_[size_t(i)] / (integral_ * count()) : 0;
}

Distribution2D::Distribution2D(const float* f, int nu, int nv, bool view)
    : own_(f, view ? f : f + size_t(nu) * nv),
      func_(view ? f : own_.data()),
      nu_(nu),
      nv_(nv),
      cdf_stride_(padded_cdf_size(nu)),
      coarse_stride_(size_t(coarse_count(nu))),
      cdf_(size_t(nv) * cdf_stride_),
      coarse_(size_t(nv) * coarse_stride_) {
  std::vector<float> integrals(nv);
  for (int v = 0; v < nv; ++v) {
    float* cdf = &cdf_[size_t(v) * cdf_stride_];
    integrals[v] = build_cdf(func_ + size_t(v) * nu, nu, cdf);
    pad_cdf(cdf, nu);
    // A row whose integral is not finite is searched in full; the marginal says which.
    if (std::isfinite(integrals[v])) build_coarse(cdf, nu, &coarse_[size_t(v) * coarse_stride_]);
  }
  marginal_ = Distribution1D(integrals.data(), nv);
}

Distribution2D& Distribution2D::operator=(const Distribution2D& o) {
  if (this == &o) return *this;
  own_ = o.own_;
  func_ = o.func_ == o.own_.data() ? own_.data() : o.func_;
  nu_ = o.nu_;
  nv_ = o.nv_;
  cdf_stride_ = o.cdf_stride_;
  coarse_stride_ = o.coarse_stride_;
  cdf_ = o.cdf_;
  coarse_ = o.coarse_;
  marginal_ = o.marginal_;
  return *this;
}

Vec2 Distribution2D::sample_continuous(Vec2 u, float* pdf) const {
  float pdf_v;
  int v;
  const float d1 = marginal_.sample_continuous(u.y, &pdf_v, &v);
  const float integral = marginal_.value(v);
  const size_t row = size_t(v);
  const float* coarse = std::isfinite(integral) ? &coarse_[row * coarse_stride_] : nullptr;
  float pdf_u;
  const float d0 = sample_table(func_ + row * nu_, &cdf_[row * cdf_stride_], coarse, nu_, integral,
                                u.x, &pdf_u, nullptr);
  *pdf = pdf_u * pdf_v;
  return {d0, d1};
}

void Distribution2D::prefetch_sample(Vec2 u) const {
  const int v = marginal_.sample_discrete(u.y);
  const size_t row = size_t(v);
  if (!std::isfinite(marginal_.value(v))) return;
  const int lo = std::max(0, line_start(&coarse_[row * coarse_stride_], nu_, u.x));
  __builtin_prefetch(&cdf_[row * cdf_stride_ + size_t(lo)]);
  __builtin_prefetch(func_ + row * nu_ + size_t(lo));
  __builtin_prefetch(func_ + row * nu_ + size_t(std::min(lo + kLine - 1, nu_ - 1)));
}

const float* Distribution2D::cell_value(Vec2 p) const {
  int iu = clamp(int(p.x * nu_), 0, nu_ - 1);
  int iv = clamp(int(p.y * nv_), 0, nv_ - 1);
  return func_ + size_t(iv) * nu_ + iu;
}

float Distribution2D::pdf(Vec2 p) const {
  const float* value = cell_value(p);
  if (marginal_.integral() == 0) return 0;
  return *value / marginal_.integral();
}

void Distribution2D::prefetch_value(Vec2 p) const {
  if (func_) __builtin_prefetch(cell_value(p));
}

}  // namespace rt
