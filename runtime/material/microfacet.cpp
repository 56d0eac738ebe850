// runtime/material/microfacet.cpp — D, Smith lambda and visible-normal sampling
// for the Trowbridge-Reitz and Beckmann distributions.
//
// Sampling follows Heitz and d'Eon, "Importance Sampling Microfacet-Based
// BSDFs using the Distribution of Visible Normals" (EGSR 2014) as the pbrt
// book presents it: stretch wo to the alpha = 1 configuration, sample a slope
// of the visible-slope distribution there, rotate, unstretch, and turn the
// slope into a normal.
#include "runtime/material/microfacet.h"

#include "runtime/material/local_frame.h"

namespace rt {

float roughness_to_alpha(float roughness) {
  roughness = std::max(roughness, 1e-3f);
  float x = std::log(roughness);
  // pbrt-v3's fit (microfacet.h, RoughnessToAlpha).
  return 1.62142f + 0.819955f * x + 0.1734f * x * x + 0.0171201f * x * x * x +
         0.000640711f * x * x * x * x;
}

// D and lambda from the direction's components instead of its angles: in the book's
// (cos^2 phi / ax^2 + sin^2 phi / ay^2) tan^2 theta and alpha(phi)^2 tan^2 theta, cos phi and
// sin phi are x and y over sin theta, which the tangent's sin theta cancels, leaving
// (x^2 / ax^2 + y^2 / ay^2) / z^2 and (ax^2 x^2 + ay^2 y^2) / z^2. The same values up to
// rounding (and without 1 - z^2's cancellation near the normal), with no square root and
// fewer divisions. z = 0 (tan theta infinite) gives 0 in both, as in pbrt-v3.
float MicrofacetDistribution::d(Vec3 wh) const {
  const float cos2 = wh.z * wh.z;
  if (cos2 == 0) return 0;
  const float slope2 = wh.x * wh.x / (alpha_x * alpha_x) + wh.y * wh.y / (alpha_y * alpha_y);
  if (kind == MicrofacetKind::kBeckmann)
    return std::exp(-slope2 / cos2) / (kPi * alpha_x * alpha_y * cos2 * cos2);
  // cos^4 theta (1 + e)^2 is (cos^2 theta + slope2)^2.
  const float s = cos2 + slope2;
  return 1 / (kPi * alpha_x * alpha_y * s * s);
}

float MicrofacetDistribution::lambda(Vec3 w) const {
  const float cos2 = w.z * w.z;
  if (cos2 == 0) return 0;
  // (alpha tan theta)^2, alpha the roughness seen in w's azimuth.
  const float alpha2_tan2 = (alpha_x * alpha_x * w.x * w.x + alpha_y * alpha_y * w.y * w.y) / cos2;
  if (kind == MicrofacetKind::kBeckmann) {
    // Walter et al. 2007's rational approximation of the Beckmann lambda.
    const float a = 1 / std::sqrt(alpha2_tan2);
    if (a >= 1.6f) return 0;
    return (1 - 1.259f * a + 0.396f * a * a) / (3.535f * a + 2.181f * a * a);
  }
  return (-1 + std::sqrt(1 + alpha2_tan2)) / 2;
}

float MicrofacetDistribution::pdf(Vec3 wo, Vec3 wh) const {
  return pdf_given(d(wh), g1(wo), wo, wh);
}

namespace {

// Visible slopes for alpha = 1 Trowbridge-Reitz, seen from a direction with the given cos and
// sin theta (cos > 0). Slope x inverts the CDF in closed form; slope y uses Heitz and d'Eon's
// rational fit of the inverse (constants from their paper). Their G1 for the direction,
// 2 / (1 + sqrt(1 + tan^2)), is 2 cos / (1 + cos): the sampled slopes are theirs up to rounding,
// with fewer divisions and square roots on the way.
void trowbridge_reitz_sample11(float cos_theta_i, float sin_theta_i, float u1, float u2,
                               float* slope_x, float* slope_y) {
  if (cos_theta_i > .9999f) {  // normal incidence: the plain slope distribution
    float r = std::sqrt(u1 / (1 - u1));
    float phi = 2 * kPi * u2;
    *slope_x = r * std::cos(phi);
    *slope_y = r * std::sin(phi);
    return;
  }
  float tan_theta_i = sin_theta_i / cos_theta_i;
  float A = u1 * (1 + cos_theta_i) / cos_theta_i - 1;  // 2 u1 / G1 - 1
  float tmp = 1.f / (A * A - 1.f);
  if (tmp > 1e10f) tmp = 1e10f;
  float B = tan_theta_i;
  float D = std::sqrt(std::max(B * B * tmp * tmp - (A * A - B * B) * tmp, 0.f));
  float sx1 = B * tmp - D, sx2 = B * tmp + D;
  *slope_x = (A < 0 || sx2 * tan_theta_i > 1.f) ? sx1 : sx2;

  float s;
  if (u2 > 0.5f) {
    s = 1;
    u2 = 2 * (u2 - .5f);
  } else {
    s = -1;
    u2 = 2 * (.5f - u2);
  }
  float z = (u2 * (u2 * (u2 * 0.27385f - 0.73369f) + 0.46341f)) /
            (u2 * (u2 * (u2 * 0.093073f + 0.309420f) - 1.000000f) + 0.597999f);
  *slope_y = s * z * std::sqrt(1 + *slope_x * *slope_x);
}

// Visible slopes for alpha = 1 Beckmann: slope x by Newton-bisection on the
// CDF (started from a fitted guess), slope y from the Gaussian marginal.
void beckmann_sample11(float cos_theta_i, float u1, float u2, float* slope_x, float* slope_y) {
  if (cos_theta_i > .9999f) {
    float r = std::sqrt(-std::log(1 - u1));
    float phi = 2 * kPi * u2;
    *slope_x = r * std::cos(phi);
    *slope_y = r * std::sin(phi);
    return;
  }
  float sin_theta_i = std::sqrt(std::max(0.f, 1 - cos_theta_i * cos_theta_i));
  float tan_theta_i = sin_theta_i / cos_theta_i;
  float cot_theta_i = 1 / tan_theta_i;

  // The CDF's range is [-1, c]; search there.
  float a = -1, c = std::erf(cot_theta_i);
  float sample_x = std::max(u1, 1e-6f);
  float theta_i = std::acos(cos_theta_i);
  float fit = 1 + theta_i * (-0.876f + theta_i * (0.4265f - 0.0594f * theta_i));
  float b = c - (1 + c) * std::pow(1 - sample_x, fit);

  const float kInvSqrtPi = 0.56418958354775628695f;
  float normalization =
      1 / (1 + c + kInvSqrtPi * tan_theta_i * std::exp(-cot_theta_i * cot_theta_i));
  for (int it = 1; it < 10; ++it) {
    if (!(b >= a && b <= c)) b = 0.5f * (a + c);  // Newton left the bracket: bisect
    float inv_erf = erf_inv(b);
    float value =
        normalization * (1 + b + kInvSqrtPi * tan_theta_i * std::exp(-inv_erf * inv_erf)) -
        sample_x;
    float derivative = normalization * (1 - inv_erf * tan_theta_i);
    if (std::fabs(value) < 1e-5f) break;
    if (value > 0)
      c = b;
    else
      a = b;
    b -= value / derivative;
  }
  *slope_x = erf_inv(b);
  *slope_y = erf_inv(2 * std::max(u2, 1e-6f) - 1);
}

}  // namespace

Vec3 MicrofacetDistribution::sample_wh(Vec3 wo, Vec2 u) const {
  bool flip = wo.z < 0;
  Vec3 wi = flip ? -wo : wo;
  Vec3 stretched = normalize(Vec3{alpha_x * wi.x, alpha_y * wi.y, wi.z});
  // sin theta once, for the slopes and for cos phi and sin phi.
  const float sin_t = sin_theta(stretched);
  float sx, sy;
  if (kind == MicrofacetKind::kBeckmann)
    beckmann_sample11(cos_theta(stretched), u.x, u.y, &sx, &sy);
  else
    trowbridge_reitz_sample11(cos_theta(stretched), sin_t, u.x, u.y, &sx, &sy);
  const float cp = cos_phi(stretched, sin_t), sp = sin_phi(stretched, sin_t);
  float rx = cp * sx - sp * sy;
  float ry = sp * sx + cp * sy;
  rx *= alpha_x;
  ry *= alpha_y;
  Vec3 wh = normalize(Vec3{-rx, -ry, 1});
  return flip ? -wh : wh;
}

}  // namespace rt
