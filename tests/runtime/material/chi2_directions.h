// tests/runtime/material/chi2_directions.h — chi-square goodness of fit for
// direction sampling against a claimed pdf.
//
// Samples are histogrammed over (theta in [0, pi], phi in [0, 2 pi)); the
// expected count of a bin is n times the pdf integrated over it (midpoint rule
// on a sub-grid, with the sin theta Jacobian: theta bins, unlike cos theta
// bins, keep lobes peaked at the poles resolvable). Bins expecting fewer than
// 5 samples are pooled, as the test's validity requires. A sample falling in
// bins the pdf says are (numerically) empty fail the test when more than a
// handful. Samples
// the sampler rejected (returned false) should match the mass the pdf misses;
// pbrt-v3's Beckmann masking is a rational approximation, so its visible-normal
// pdf integrates to 1 only within about 0.5%: the rejected fraction is
// therefore checked with a tolerance (total_mass_error, total_mass_sigma), and the histogram
// compares the shape of the accepted samples with the normalised pdf.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "runtime/core/rng.h"
#include "runtime/core/vec.h"

namespace material_test {

// Regularised upper incomplete gamma Q(a, x): the chi-square survival function
// is Q(dof / 2, chi2 / 2). Series below a + 1, Lentz continued fraction above.
inline double upper_incomplete_gamma(double a, double x) {
  if (x <= 0) return 1;
  double log_prefix = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1) {
    double term = 1 / a, sum = term;
    for (int n = 1; n < 1000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::fabs(term) < std::fabs(sum) * 1e-15) break;
    }
    return 1 - sum * std::exp(log_prefix);
  }
  double tiny = 1e-300;
  double b = x + 1 - a, c = 1 / tiny, d = 1 / b, h = d;
  for (int i = 1; i < 1000; ++i) {
    double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::fabs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1 / d;
    double del = d * c;
    h *= del;
    if (std::fabs(del - 1) < 1e-15) break;
  }
  return std::exp(log_prefix) * h;
}

struct Chi2Result {
  double p_value = 0;
  double chi2 = 0;
  int dof = 0;
  double total_mass_error = 0;  // |integral of pdf - accepted fraction|
  double total_mass_sigma = 0;  // that fraction's standard deviation
  std::string message;          // why it failed outright, or a summary
};

using SampleFn = std::function<bool(rt::Vec2 u, rt::Vec3* wi)>;
using PdfFn = std::function<double(rt::Vec3 wi)>;

inline rt::Vec3 direction_of(double theta, double phi) {
  double s = std::sin(theta);
  return {float(s * std::cos(phi)), float(s * std::sin(phi)), float(std::cos(theta))};
}

inline Chi2Result chi2_directions(const SampleFn& sample, const PdfFn& pdf, int n, uint64_t seed,
                                  int theta_bins = 20, int phi_bins = 40, int sub = 12) {
  const double kTwoPi = 2 * M_PI;
  int nbins = theta_bins * phi_bins;
  std::vector<double> observed(nbins + 1, 0), expected(nbins + 1, 0);
  rt::Rng rng(seed);
  for (int i = 0; i < n; ++i) {
    rt::Vec2 u{rng.next_float(), rng.next_float()};
    rt::Vec3 wi;
    if (!sample(u, &wi)) {
      observed[nbins] += 1;
      continue;
    }
    double len = std::sqrt(double(rt::dot(wi, wi)));
    double theta = std::acos(std::clamp(wi.z / len, -1.0, 1.0));
    double phi = std::atan2(double(wi.y), double(wi.x));
    if (phi < 0) phi += kTwoPi;
    int ti = std::min(int(theta / M_PI * theta_bins), theta_bins - 1);
    int pi = std::min(int(phi / kTwoPi * phi_bins), phi_bins - 1);
    observed[ti * phi_bins + pi] += 1;
  }
  double dtheta = M_PI / theta_bins, dphi = kTwoPi / phi_bins, total = 0;
  for (int ti = 0; ti < theta_bins; ++ti)
    for (int pi = 0; pi < phi_bins; ++pi) {
      double sum = 0;
      for (int a = 0; a < sub; ++a)
        for (int b = 0; b < sub; ++b) {
          double theta = (ti + (a + 0.5) / sub) * dtheta;
          double phi = (pi + (b + 0.5) / sub) * dphi;
          sum += pdf(direction_of(theta, phi)) * std::sin(theta);
        }
      double e = sum / (sub * sub) * dtheta * dphi * n;
      expected[ti * phi_bins + pi] = e;
      total += e;
    }
  double accepted = n - observed[nbins];
  for (int i = 0; i < nbins; ++i) expected[i] *= total > 0 ? accepted / total : 0;

  Chi2Result r;
  std::ostringstream msg;
  // Samples where the pdf is numerically zero: a few are sub-grid misses of a
  // thin sliver of support (a tilted horizon crossing a bin); more is a
  // support mismatch. The few join the pool.
  double outside = 0;
  for (int i = 0; i < nbins; ++i)
    if (expected[i] == 0) outside += observed[i];
  if (outside > 5 + 1e-4 * n) {
    msg << outside << " samples where the pdf is zero";
    r.message = msg.str();
    return r;
  }
  // Pool low-expectation bins, in increasing order of expectation.
  std::vector<int> order(nbins);
  for (int i = 0; i < nbins; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](int a, int b) { return expected[a] < expected[b]; });
  double pool_obs = outside, pool_exp = 0, chi2 = 0;
  int dof = -1;
  for (int i : order) {
    if (expected[i] == 0) continue;
    if (expected[i] < 5 || (pool_exp > 0 && pool_exp < 5)) {
      pool_obs += observed[i];
      pool_exp += expected[i];
      continue;
    }
    chi2 += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
    ++dof;
  }
  if (pool_exp > 0) {
    chi2 += (pool_obs - pool_exp) * (pool_obs - pool_exp) / pool_exp;
    ++dof;
  }
  r.total_mass_error = std::fabs(total - accepted) / n;
  double f = accepted / n;
  r.total_mass_sigma = std::sqrt(f * (1 - f) / n);
  r.chi2 = chi2;
  r.dof = dof;
  r.p_value = dof > 0 ? upper_incomplete_gamma(dof / 2.0, chi2 / 2.0) : 0;
  msg << "chi2 " << chi2 << " dof " << dof << " p " << r.p_value << " (rejected samples "
      << observed[nbins] << ", pdf mass " << total / n << ")";
  r.message = msg.str();
  return r;
}

}  // namespace material_test
