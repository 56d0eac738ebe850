#include "runtime/material/fourier_interpolation.h"

#include <algorithm>
#include <cmath>

#include "runtime/core/math.h"

namespace rt {

float fourier_series(const float* a, int m, double cos_phi) {
  // cos((k + 1) phi) = 2 cos(phi) cos(k phi) - cos((k - 1) phi)
  double sum = 0, cos_prev = cos_phi, cos_k = 1;  // cos(-phi), cos(0)
  for (int k = 0; k < m; ++k) {
    sum += double(a[k]) * cos_k;
    double cos_next = 2 * cos_phi * cos_k - cos_prev;
    cos_prev = cos_k;
    cos_k = cos_next;
  }
  return float(sum);
}

float sample_fourier(const float* ak, const float* recip, int m, float u, float* pdf,
                     float* phi_out) {
  *pdf = 0;
  *phi_out = 0;
  if (!(m > 0 && ak[0] > 0)) return 0;
  // The series is even in phi: sample [0, pi] and mirror half of the samples.
  bool flip = u >= 0.5f;
  u = flip ? 1 - 2 * (u - .5f) : 2 * u;
  double a = 0, b = kPi, phi = 0.5 * kPi, big_f = 0, small_f = 0;
  for (int iteration = 0; iteration < 100; ++iteration) {
    // F(phi) = a0 phi + sum_{k>=1} a_k sin(k phi) / k and its derivative f(phi), with the
    // sine and cosine recurrences.
    double cos_phi = std::cos(phi);
    double sin_phi = std::sqrt(std::max(0.0, 1 - cos_phi * cos_phi));
    double cos_prev = cos_phi, cos_k = 1, sin_prev = -sin_phi, sin_k = 0;
    big_f = ak[0] * phi;
    small_f = ak[0];
    for (int k = 1; k < m; ++k) {
      double sin_next = 2 * cos_phi * sin_k - sin_prev;
      double cos_next = 2 * cos_phi * cos_k - cos_prev;
      sin_prev = sin_k;
      sin_k = sin_next;
      cos_prev = cos_k;
      cos_k = cos_next;
      big_f += ak[k] * recip[k] * sin_next;
      small_f += ak[k] * cos_next;
    }
    big_f -= u * ak[0] * kPi;
    if (big_f > 0)
      b = phi;
    else
      a = phi;
    if (std::fabs(big_f) < 1e-6 || b - a < 1e-6) break;
    phi -= big_f / small_f;
    if (!(phi > a && phi < b)) phi = 0.5 * (a + b);
  }
  if (flip) phi = 2 * double(kPi) - phi;
  *pdf = float(double(kInv2Pi) * small_f / ak[0]);
  *phi_out = float(phi);
  return float(small_f);
}

}  // namespace rt
