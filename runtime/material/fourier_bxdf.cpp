#include "runtime/material/fourier_bxdf.h"

#include <algorithm>
#include <cmath>

#include "runtime/core/math.h"
#include "runtime/material/fourier_interpolation.h"

namespace rt {

namespace {

// cos of the azimuth between two directions; 1 when either is along the normal.
float cos_delta_phi(Vec3 a, Vec3 b) {
  float a_xy = a.x * a.x + a.y * a.y, b_xy = b.x * b.x + b.y * b.y;
  if (a_xy == 0 || b_xy == 0) return 1;
  return clamp((a.x * b.x + a.y * b.y) / std::sqrt(a_xy * b_xy), -1.f, 1.f);
}

// The series coefficients at (mu_i, mu_o), Catmull-Rom weighted over the 4 x 4 nearest node
// pairs: channel c's term k at ak[c * m_max + k], for `channels` channels (1: luminance only).
// Returns the longest series that contributed (0: none, or a cosine outside the table).
int interpolate_series(const FourierTable& t, float mu_i, float mu_o, int channels, float* ak,
                       int* offset_o = nullptr, float* weights_o = nullptr) {
  int off_i, off_o;
  float w_i[4], w_o[4];
  if (!catmull_rom_weights(t.n_mu, t.mu, mu_i, &off_i, w_i) ||
      !catmull_rom_weights(t.n_mu, t.mu, mu_o, &off_o, w_o))
    return 0;
  std::fill(ak, ak + size_t(t.m_max) * size_t(channels), 0.f);
  int m_max = 0;
  for (int b = 0; b < 4; ++b)
    for (int a = 0; a < 4; ++a) {
      float w = w_i[a] * w_o[b];
      if (w == 0) continue;  // also every node outside the table
      int m;
      const float* s = t.series(off_i + a, off_o + b, &m);
      m_max = std::max(m_max, m);
      for (int c = 0; c < channels; ++c)
        for (int k = 0; k < m; ++k) ak[c * t.m_max + k] += w * s[c * m + k];
    }
  if (offset_o) {
    *offset_o = off_o;
    std::copy(w_o, w_o + 4, weights_o);
  }
  return m_max;
}

// 1 / |mu_i|, with pbrt-v3's non-symmetric scaling of radiance that crosses the surface.
float series_scale(const FourierTable& t, TransportMode mode, float mu_i, float mu_o) {
  float scale = mu_i != 0 ? 1 / std::fabs(mu_i) : 0;
  if (mode == TransportMode::kRadiance && mu_i * mu_o > 0) {
    float eta = mu_i > 0 ? 1 / t.eta : t.eta;
    scale *= eta * eta;
  }
  return scale;
}

// The value from the luminance y and, for RGB tables, the red and blue series at cos_phi:
// green is what luminance leaves after red and blue (Rgb::luminance()'s weights).
Rgb series_value(const FourierTable& t, const float* ak, int m, float y, double cos_phi,
                 float scale) {
  if (t.channels == 1) return Rgb(y * scale);
  float r = fourier_series(ak + t.m_max, m, cos_phi);
  float b = fourier_series(ak + 2 * t.m_max, m, cos_phi);
  float g = (y - 0.212671f * r - 0.072169f * b) / 0.715160f;
  return {std::max(0.f, r * scale), std::max(0.f, g * scale), std::max(0.f, b * scale)};
}

}  // namespace

void make_fourier_table(const pbrta::FourierTableView& v, FourierTable* t) {
  static_cast<pbrta::FourierTableView&>(*t) = v;
  size_t pairs = size_t(v.n_mu) * v.n_mu;
  t->a0.assign(pairs, 0.f);
  for (size_t p = 0; p < pairs; ++p)
    if (v.offsets[2 * p + 1] > 0) t->a0[p] = v.coeffs[v.offsets[2 * p]];
  t->recip.assign(size_t(std::max(v.m_max, 1)), 0.f);
  for (int k = 1; k < v.m_max; ++k) t->recip[size_t(k)] = 1.f / float(k);
}

bool build_fourier_table(const pbrta::SceneArchive& archive, uint32_t entity, FourierTable* t,
                         std::string* error) {
  pbrta::FourierTableView view;
  std::string why;
  if (!pbrta::fourier_table_of(archive, entity, &view, &why)) {
    *error = "fourier material (" + archive.where(entity) + "): " + why;
    return false;
  }
  make_fourier_table(view, t);
  return true;
}

Rgb FourierLobe::f(Vec3 wo, Vec3 wi) const {
  const FourierTable& t = *table;
  float mu_i = -wi.z, mu_o = wo.z;
  float ak[3 * pbrta::kMaxFourierOrder];
  int m = interpolate_series(t, mu_i, mu_o, t.channels, ak);
  if (m == 0) return Rgb(0);
  double cos_phi = cos_delta_phi(-wi, wo);
  float y = std::max(0.f, fourier_series(ak, m, cos_phi));
  return series_value(t, ak, m, y, cos_phi, series_scale(t, mode, mu_i, mu_o));
}

Rgb FourierLobe::sample_f(Vec3 wo, Vec3* wi, Vec2 u, float* pdf) const {
  const FourierTable& t = *table;
  *pdf = 0;
  // mu_i from the spline of a0 over mu_i at mu_o (its integral is the cdf table) ...
  float mu_o = wo.z, pdf_mu;
  float mu_i = sample_catmull_rom_2d(t.n_mu, t.n_mu, t.mu, t.mu, t.a0.data(), t.cdf, mu_o, u.y,
                                     nullptr, &pdf_mu);
  if (!(pdf_mu > 0)) return Rgb(0);
  float ak[3 * pbrta::kMaxFourierOrder];
  int m = interpolate_series(t, mu_i, mu_o, t.channels, ak);
  if (m == 0) return Rgb(0);
  // ... then phi from the luminance series at (mu_i, mu_o).
  float phi, pdf_phi;
  float y = sample_fourier(ak, t.recip.data(), m, u.x, &pdf_phi, &phi);
  *pdf = std::max(0.f, pdf_phi * pdf_mu);
  // -wi has zenith cosine mu_i and lies phi around the normal from wo.
  float sin2_i = std::max(0.f, 1 - mu_i * mu_i);
  float sin2_o = wo.x * wo.x + wo.y * wo.y;
  float sin_phi = std::sin(phi), cos_phi = std::cos(phi);
  Vec3 minus_wi;
  if (sin2_o > 0) {
    float norm = std::sqrt(sin2_i / sin2_o);
    minus_wi = {norm * (cos_phi * wo.x - sin_phi * wo.y), norm * (sin_phi * wo.x + cos_phi * wo.y),
                mu_i};
  } else {
    // wo along the normal has no azimuth: measure phi from +x.
    float sin_i = std::sqrt(sin2_i);
    minus_wi = {sin_i * cos_phi, sin_i * sin_phi, mu_i};
  }
  // Renormalised: round-off here compounds over bounces (pbrt-v3 does the same).
  *wi = -normalize(minus_wi);
  return series_value(t, ak, m, y, cos_phi, series_scale(t, mode, mu_i, mu_o));
}

float FourierLobe::pdf(Vec3 wo, Vec3 wi) const {
  const FourierTable& t = *table;
  float mu_i = -wi.z, mu_o = wo.z;
  float ak[pbrta::kMaxFourierOrder];
  int offset_o;
  float w_o[4];
  int m = interpolate_series(t, mu_i, mu_o, 1, ak, &offset_o, w_o);
  if (m == 0) return 0;
  // The luminance's integral over the sphere at mu_o: 2 pi times the a0 spline's over mu_i.
  float rho = 0;
  for (int o = 0; o < 4; ++o)
    if (w_o[o] != 0)
      rho += w_o[o] * t.cdf[(offset_o + o) * int(t.n_mu) + int(t.n_mu) - 1] * (2 * kPi);
  float y = fourier_series(ak, m, cos_delta_phi(-wi, wo));
  return rho > 0 && y > 0 ? y / rho : 0;
}

}  // namespace rt
