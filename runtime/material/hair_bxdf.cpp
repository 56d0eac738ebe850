// runtime/material/hair_bxdf.cpp — see hair_bxdf.h.
#include "runtime/material/hair_bxdf.h"

#include <algorithm>
#include <cmath>

#include "runtime/material/disney_bxdf.h"
#include "runtime/material/fresnel.h"

namespace rt {

// Bxdf's union holds either; a larger hair lobe would grow every Bsdf.
static_assert(sizeof(HairLobe) <= sizeof(DisneyLobe));

namespace {

constexpr int kPMax = 3;  // R, TT, TRT, then everything after folded into one
constexpr float kSqrtPiOver8 = 0.626657069f;

// v^n by squaring the half power, in the multiplication order pbrt-v3's
// Pow<n> uses, so the fitted polynomials below round the same.
float pow_n(float v, int n) {
  if (n == 0) return 1;
  if (n == 1) return v;
  float half = pow_n(v, n / 2);
  return half * half * pow_n(v, n & 1);
}

// The power series of the modified Bessel function of the first kind,
// I0(x) = sum_i x^(2i) / (4^i (i!)^2), to ten terms. The denominators are
// exact 64-bit integers rounded once to float.
struct I0Denominators {
  float d[10];
  constexpr I0Denominators() : d() {
    uint64_t fact = 1, four = 1;
    for (int i = 0; i < 10; ++i) {
      if (i > 1) fact *= uint64_t(i);
      d[i] = float(four * fact * fact);
      four *= 4;
    }
  }
};
constexpr I0Denominators kI0;

float bessel_i0(float x) {
  float sum = 0, x2i = 1;
  for (int i = 0; i < 10; ++i) {
    sum += x2i / kI0.d[i];
    x2i *= x * x;
  }
  return sum;
}

// log I0 without overflow: past 12 the large-argument expansion
// log I0(x) ~ x - log(2 pi x) / 2 + 1 / (8 x).
float log_bessel_i0(float x) {
  if (x > 12) return x + 0.5f * (-std::log(2 * kPi) + std::log(1 / x) + 1 / (8 * x));
  return std::log(bessel_i0(x));
}

// M_p: d'Eon et al.'s normalized longitudinal scattering for variance v,
// csch(1/v) / (2 v) exp(-sin_i sin_o / v) I0(cos_i cos_o / v). The sign in
// the exponent centres the lobe on the mirror cone theta_i = -theta_o. Small
// variances go through logs: sinh(1/v) and I0 overflow long before the
// product does (csch(1/v) ~ 2 exp(-1/v), 0.6931 = log 2). The comparison
// with 0.1 is in double, as pbrt-v3's.
float longitudinal(float cos_i, float cos_o, float sin_i, float sin_o, float v) {
  float a = cos_i * cos_o / v, b = sin_i * sin_o / v;
  if (v <= 0.1) return std::exp(log_bessel_i0(a) - b - 1 / v + 0.6931f + std::log(1 / (2 * v)));
  return (std::exp(-b) * bessel_i0(a)) / (std::sinh(1 / v) * 2 * v);
}

float variance(float v0, int p) {
  if (p == 0) return v0;
  if (p == 1) return 0.25f * v0;  // TT is the narrowest lobe
  return 4 * v0;
}

// A_p: the fraction of light leaving after p internal paths. Fresnel at the
// entry point (incidence cos theta_o cos gamma_o), one chord's transmittance
// t per internal path, and for the last term the geometric series of all
// longer paths.
void attenuations(float cos_theta_o, float eta, float h, Rgb t, Rgb ap[kPMax + 1]) {
  float cos_gamma_o = safe_sqrt(1 - h * h);
  float f = fr_dielectric(cos_theta_o * cos_gamma_o, 1, eta);
  ap[0] = Rgb(f);
  ap[1] = sqr(1 - f) * t;
  ap[2] = ap[1] * t * f;
  // Where f t is 1 (a clear fiber hit at grazing incidence, f = 1) A_2 is 0
  // too: Rgb's quotient then gives 0 (pbrt-v3 would make a NaN).
  ap[3] = ap[2] * f * t / (Rgb(1) - t * f);
}

// The azimuth, relative to phi_o, at which lobe p leaves: each internal path
// turns by pi - 2 gamma_t, each crossing of the surface adds the deflection.
float exit_azimuth(int p, float gamma_o, float gamma_t) {
  return 2 * p * gamma_t - 2 * gamma_o + p * kPi;
}

float logistic(float x, float s) {
  x = std::fabs(x);
  float e = std::exp(-x / s);
  return e / (s * sqr(1 + e));
}

float logistic_cdf(float x, float s) {
  return 1 / (1 + std::exp(-x / s));
}

// The logistic renormalized to [a, b].
float trimmed_logistic(float x, float s, float a, float b) {
  return logistic(x, s) / (logistic_cdf(b, s) - logistic_cdf(a, s));
}

float sample_trimmed_logistic(float u, float s, float a, float b) {
  float k = logistic_cdf(b, s) - logistic_cdf(a, s);
  float x = -s * std::log(1 / (u * k + logistic_cdf(a, s)) - 1);
  return clamp(x, a, b);
}

// N_p: the azimuthal distribution of lobe p around its exit azimuth, with
// the difference wrapped to [-pi, pi].
float azimuthal(float phi, int p, float s, float gamma_o, float gamma_t) {
  float dphi = phi - exit_azimuth(p, gamma_o, gamma_t);
  if (!std::isfinite(dphi)) return 0;  // the wrapping loops would not end
  while (dphi > kPi) dphi -= 2 * kPi;
  while (dphi < -kPi) dphi += 2 * kPi;
  return trimmed_logistic(dphi, s, -kPi, kPi);
}

// Everything f, pdf and sample_f derive from wo: its angles in the fiber's
// frame, the refracted ray's azimuth gamma_t, and the lobes' attenuations.
struct Outgoing {
  float sin_o, cos_o, phi_o;
  float gamma_t;
  Rgb ap[kPMax + 1];
};

Outgoing outgoing(const HairLobe& l, Vec3 wo) {
  Outgoing o;
  o.sin_o = wo.x;
  o.cos_o = safe_sqrt(1 - sqr(o.sin_o));
  o.phi_o = std::atan2(wo.z, wo.y);
  // Inside, the longitudinal angle obeys Snell's law with eta; the projection
  // onto the normal plane refracts with Bravais' index eta' (the fiber seen
  // end-on). Along the fiber (cos_o 0) eta' is infinite and gamma_t 0.
  float sin_theta_t = o.sin_o / l.eta;
  float cos_theta_t = safe_sqrt(1 - sqr(sin_theta_t));
  float eta_p = o.cos_o > 0 ? safe_sqrt(l.eta * l.eta - sqr(o.sin_o)) / o.cos_o : kInfinity;
  float sin_gamma_t = l.h / eta_p;
  float cos_gamma_t = safe_sqrt(1 - sqr(sin_gamma_t));
  o.gamma_t = safe_asin(sin_gamma_t);
  // One chord through the fiber is 2 cos gamma_t long in the normal plane,
  // 1 / cos theta_t longer along the refracted direction.
  Rgb t = exp(l.sigma_a * -(2 * cos_gamma_t / cos_theta_t));
  attenuations(o.cos_o, l.eta, l.h, t, o.ap);
  return o;
}

// sin and cos of alpha, 2 alpha and 4 alpha.
struct ScaleTilt {
  float sin2k[3], cos2k[3];
};

ScaleTilt scale_tilt(const HairLobe& l) {
  ScaleTilt t;
  t.sin2k[0] = l.sin_alpha;
  t.cos2k[0] = l.cos_alpha;
  for (int k = 1; k < 3; ++k) {
    t.sin2k[k] = 2 * t.cos2k[k - 1] * t.sin2k[k - 1];
    t.cos2k[k] = sqr(t.cos2k[k - 1]) - sqr(t.sin2k[k - 1]);
  }
  return t;
}

// theta_o rotated by lobe p's tilt: R by -2 alpha, TT by +alpha, TRT by
// +4 alpha, the remainder not at all. The cosine may come out negative past
// the pole; callers evaluating M_p take its magnitude (I0 is even).
void tilt(const ScaleTilt& t, int p, float sin_o, float cos_o, float* sin_op, float* cos_op) {
  if (p == 0) {
    *sin_op = sin_o * t.cos2k[1] - cos_o * t.sin2k[1];
    *cos_op = cos_o * t.cos2k[1] + sin_o * t.sin2k[1];
  } else if (p == 1) {
    *sin_op = sin_o * t.cos2k[0] + cos_o * t.sin2k[0];
    *cos_op = cos_o * t.cos2k[0] - sin_o * t.sin2k[0];
  } else if (p == 2) {
    *sin_op = sin_o * t.cos2k[2] + cos_o * t.sin2k[2];
    *cos_op = cos_o * t.cos2k[2] - sin_o * t.sin2k[2];
  } else {
    *sin_op = sin_o;
    *cos_op = cos_o;
  }
}

// The probability of sampling each lobe: A_p's luminance, normalized. False
// when every A_p is black (nothing to sample).
bool lobe_pdfs(const Outgoing& o, float out[kPMax + 1]) {
  float sum = 0;
  for (int p = 0; p <= kPMax; ++p) sum += o.ap[p].luminance();
  if (!(sum > 0)) return false;
  for (int p = 0; p <= kPMax; ++p) out[p] = o.ap[p].luminance() / sum;
  return true;
}

// The density of directions (sin_i, cos_i, azimuth phi relative to phi_o):
// the lobes' M_p N_p mixed by their selection probabilities.
float density(const HairLobe& l, const Outgoing& o, const float lobe_pdf[kPMax + 1], float sin_i,
              float cos_i, float phi) {
  ScaleTilt t = scale_tilt(l);
  float sum = 0;
  for (int p = 0; p < kPMax; ++p) {
    float sin_op, cos_op;
    tilt(t, p, o.sin_o, o.cos_o, &sin_op, &cos_op);
    sum += longitudinal(cos_i, std::fabs(cos_op), sin_i, sin_op, variance(l.v0, p)) * lobe_pdf[p] *
           azimuthal(phi, p, l.s, l.gamma_o, o.gamma_t);
  }
  sum += longitudinal(cos_i, o.cos_o, sin_i, o.sin_o, variance(l.v0, kPMax)) * lobe_pdf[kPMax] *
         (1 / (2 * kPi));
  return sum;
}

// Morton decoding: the even bits of x packed into the low 16.
uint32_t compact_even_bits(uint32_t x) {
  x &= 0x55555555u;
  x = (x | (x >> 1)) & 0x33333333u;
  x = (x | (x >> 2)) & 0x0f0f0f0fu;
  x = (x | (x >> 4)) & 0x00ff00ffu;
  x = (x | (x >> 8)) & 0x0000ffffu;
  return x;
}

// Two 16-bit numbers from one in [0, 1): the even and the odd bits of its
// 32-bit fixed-point form (pbrt-v3's DemuxFloat).
Vec2 demux(float u) {
  uint32_t bits = uint32_t(uint64_t(std::min(u, kOneMinusEpsilon) * 0x1p32f));
  return {compact_even_bits(bits) / 65536.f, compact_even_bits(bits >> 1) / 65536.f};
}

}  // namespace

Rgb HairLobe::f(Vec3 wo, Vec3 wi) const {
  Outgoing o = outgoing(*this, wo);
  float sin_i = wi.x, cos_i = safe_sqrt(1 - sqr(sin_i));
  float phi = std::atan2(wi.z, wi.y) - o.phi_o;
  ScaleTilt t = scale_tilt(*this);
  Rgb sum;
  for (int p = 0; p < kPMax; ++p) {
    float sin_op, cos_op;
    tilt(t, p, o.sin_o, o.cos_o, &sin_op, &cos_op);
    sum += longitudinal(cos_i, std::fabs(cos_op), sin_i, sin_op, variance(v0, p)) * o.ap[p] *
           azimuthal(phi, p, s, gamma_o, o.gamma_t);
  }
  Rgb rest = longitudinal(cos_i, o.cos_o, sin_i, o.sin_o, variance(v0, kPMax)) * o.ap[kPMax];
  for (int c = 0; c < 3; ++c) sum[c] += rest[c] / (2 * kPi);
  // The integrator multiplies by |cos theta_i| about the shading normal;
  // the model's own cosine is already in M_p.
  float cos_n = std::fabs(wi.z);
  if (cos_n > 0)
    for (int c = 0; c < 3; ++c) sum[c] /= cos_n;
  return sum;
}

Rgb HairLobe::sample_f(Vec3 wo, Vec3* wi, Vec2 u2, float* pdf, uint8_t* sampled_flags) const {
  *pdf = 0;
  Outgoing o = outgoing(*this, wo);
  float lobe_pdf[kPMax + 1];
  if (!lobe_pdfs(o, lobe_pdf)) return Rgb(0);
  // u[0] picks the lobe and the azimuth, u[1] the longitudinal cone.
  Vec2 u[2] = {demux(u2.x), demux(u2.y)};

  int p = 0;
  for (; p < kPMax; ++p) {
    if (u[0].x < lobe_pdf[p]) break;
    u[0].x -= lobe_pdf[p];
  }

  // M_p: a von Mises-Fisher cone of concentration 1/v around the mirror
  // direction -theta_op (d'Eon et al. 2013): its polar angle's cosine by
  // inversion, then the point's angle around the cone.
  float sin_op, cos_op;
  tilt(scale_tilt(*this), p, o.sin_o, o.cos_o, &sin_op, &cos_op);
  float v = variance(v0, p);
  float um = std::max(u[1].x, 1e-5f);
  float cos_cone = 1 + v * std::log(um + (1 - um) * std::exp(-2 / v));
  float sin_cone = safe_sqrt(1 - sqr(cos_cone));
  float cos_around = std::cos(2 * kPi * u[1].y);
  float sin_i = -cos_cone * sin_op + sin_cone * cos_around * cos_op;
  float cos_i = safe_sqrt(1 - sqr(sin_i));

  // N_p: the trimmed logistic around the lobe's exit azimuth; the folded
  // remainder is uniform.
  float dphi = p < kPMax ? exit_azimuth(p, gamma_o, o.gamma_t) +
                               sample_trimmed_logistic(u[0].y, s, -kPi, kPi)
                         : 2 * kPi * u[0].y;
  float phi_i = o.phi_o + dphi;
  *wi = {sin_i, cos_i * std::cos(phi_i), cos_i * std::sin(phi_i)};
  *pdf = density(*this, o, lobe_pdf, sin_i, cos_i, dphi);
  if (sampled_flags) *sampled_flags = flags;
  return f(wo, *wi);
}

float HairLobe::pdf(Vec3 wo, Vec3 wi) const {
  Outgoing o = outgoing(*this, wo);
  float lobe_pdf[kPMax + 1];
  if (!lobe_pdfs(o, lobe_pdf)) return 0;
  float sin_i = wi.x, cos_i = safe_sqrt(1 - sqr(sin_i));
  return density(*this, o, lobe_pdf, sin_i, cos_i, std::atan2(wi.z, wi.y) - o.phi_o);
}

HairLobe make_hair_lobe(float h, float eta, Rgb sigma_a, float beta_m, float beta_n,
                        float alpha_degrees) {
  HairLobe l;
  l.h = clamp(h, -1.f, 1.f);
  l.gamma_o = safe_asin(l.h);
  l.eta = eta;
  l.sigma_a = sigma_a;
  // The paper's fits from the user-facing roughnesses to the lobes' variance
  // and the logistic's scale, chosen so roughness reads perceptually linear.
  l.v0 = sqr(0.726f * beta_m + 0.812f * sqr(beta_m) + 3.7f * pow_n(beta_m, 20));
  l.s = kSqrtPiOver8 * (0.265f * beta_n + 1.194f * sqr(beta_n) + 5.372f * pow_n(beta_n, 22));
  l.sin_alpha = std::sin(radians(alpha_degrees));
  l.cos_alpha = safe_sqrt(1 - sqr(l.sin_alpha));
  return l;
}

Rgb hair_sigma_a_from_concentration(float eumelanin, float pheomelanin) {
  // Absorption of the two melanins per unit concentration (RGB, from the paper).
  const Rgb eu(0.419f, 0.697f, 1.37f), pheo(0.187f, 0.4f, 1.05f);
  Rgb out;
  for (int c = 0; c < 3; ++c) out[c] = eumelanin * eu[c] + pheomelanin * pheo[c];
  return out;
}

Rgb hair_sigma_a_from_reflectance(Rgb c, float beta_n) {
  float d = 5.969f - 0.215f * beta_n + 2.532f * sqr(beta_n) - 10.73f * pow_n(beta_n, 3) +
            5.574f * pow_n(beta_n, 4) + 0.245f * pow_n(beta_n, 5);
  Rgb out;
  for (int i = 0; i < 3; ++i) out[i] = sqr(std::log(c[i]) / d);
  return out;
}

}  // namespace rt
