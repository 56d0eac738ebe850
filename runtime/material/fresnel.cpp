// runtime/material/fresnel.cpp — the Fresnel equations (book section 8.2.1).
#include "runtime/material/fresnel.h"

#include <utility>

namespace rt {

float fr_dielectric(float cos_theta_i, float eta_i, float eta_t) {
  cos_theta_i = clamp(cos_theta_i, -1.f, 1.f);
  if (cos_theta_i <= 0) {  // arriving from the transmitted side
    std::swap(eta_i, eta_t);
    cos_theta_i = std::fabs(cos_theta_i);
  }
  float sin_i = std::sqrt(std::max(0.f, 1 - cos_theta_i * cos_theta_i));
  float sin_t = eta_i / eta_t * sin_i;
  if (sin_t >= 1) return 1;  // total internal reflection
  float cos_t = std::sqrt(std::max(0.f, 1 - sin_t * sin_t));
  float r_parl = (eta_t * cos_theta_i - eta_i * cos_t) / (eta_t * cos_theta_i + eta_i * cos_t);
  float r_perp = (eta_i * cos_theta_i - eta_t * cos_t) / (eta_i * cos_theta_i + eta_t * cos_t);
  return (r_parl * r_parl + r_perp * r_perp) / 2;
}

Rgb fr_conductor(float cos_theta_i, Rgb eta_i, Rgb eta_t, Rgb k) {
  cos_theta_i = clamp(cos_theta_i, -1.f, 1.f);
  Rgb result;
  for (int c = 0; c < 3; ++c) {
    // Relative complex index (eta + i k) / eta_i, per channel.
    float eta = eta_t[c] / eta_i[c], etak = k[c] / eta_i[c];
    float cos2 = cos_theta_i * cos_theta_i, sin2 = 1 - cos2;
    float eta2 = eta * eta, etak2 = etak * etak;
    float t0 = eta2 - etak2 - sin2;
    float a2_plus_b2 = std::sqrt(t0 * t0 + 4 * eta2 * etak2);
    float t1 = a2_plus_b2 + cos2;
    float a = std::sqrt(std::max(0.f, 0.5f * (a2_plus_b2 + t0)));
    float t2 = 2 * cos_theta_i * a;
    float rs = (t1 - t2) / (t1 + t2);
    float t3 = cos2 * a2_plus_b2 + sin2 * sin2;
    float t4 = t2 * sin2;
    float rp = rs * (t3 - t4) / (t3 + t4);
    result[c] = 0.5f * (rp + rs);
  }
  return result;
}

}  // namespace rt
