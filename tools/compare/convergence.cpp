// tools/compare/convergence.cpp — see convergence.h.
#include "tools/compare/convergence.h"

#include <algorithm>
#include <cmath>

namespace compare {

namespace {

bool same_layout(const rt::ImageRgb& x, const rt::ImageRgb& y) {
  return x.width() == y.width() && x.height() == y.height() && x.rgb.size() == y.rgb.size();
}

}  // namespace

ConvergenceResult check_convergence(const rt::ImageRgb& a, const rt::ImageRgb& b,
                                    const rt::ImageRgb& ref, double spp_ratio) {
  ConvergenceResult r;
  if (!same_layout(a, ref) || !same_layout(b, ref)) {
    r.error = "image sizes differ: ours " + std::to_string(a.width()) + "x" +
              std::to_string(a.height()) + ", reference " + std::to_string(ref.width()) + "x" +
              std::to_string(ref.height());
    return r;
  }
  const int w = ref.width(), h = ref.height();
  const size_t n = size_t(w) * h;
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      r.mean_ours[c] += 0.5 * (double(a.rgb[3 * i + c]) + b.rgb[3 * i + c]);
      r.mean_ref[c] += ref.rgb[3 * i + c];
    }
  bool means_ok = true;
  for (int c = 0; c < 3; ++c) {
    r.mean_ours[c] /= double(n);
    r.mean_ref[c] /= double(n);
    double denom = std::max(std::fabs(r.mean_ref[c]), 1e-12);
    r.mean_rel_error[c] = (r.mean_ours[c] - r.mean_ref[c]) / denom;
    // A black channel in the reference must be black in ours too.
    if (std::fabs(r.mean_ours[c] - r.mean_ref[c]) > 0.01 * std::fabs(r.mean_ref[c]) + 1e-9)
      means_ok = false;
  }
  for (int by = 0; by + 8 <= h; by += 8)
    for (int bx = 0; bx + 8 <= w; bx += 8) {
      bool pass = true;
      for (int c = 0; c < 3; ++c) {
        double sum_ours = 0, sum_ref = 0, var = 0, sum_d2 = 0;
        for (int y = by; y < by + 8; ++y)
          for (int x = bx; x < bx + 8; ++x) {
            size_t i = 3 * (size_t(y) * w + x) + c;
            double va = a.rgb[i], vb = b.rgb[i];
            sum_ours += 0.5 * (va + vb);
            sum_ref += ref.rgb[i];
            var += 0.25 * (va - vb) * (va - vb);
            const double di = 0.5 * (va + vb) - ref.rgb[i];
            sum_d2 += di * di;
          }
        double d = (sum_ours - sum_ref) / 64;
        var /= 64.0 * 64.0;
        // The scatter of the 64 pixel differences about their mean d: both images' noise.
        const double paired = std::max(0.0, (sum_d2 - 64 * d * d) / 63) / 64;
        double ref_mean = sum_ref / 64;
        double z = d / std::sqrt(std::max((1 + spp_ratio) * var, paired) +
                                 0.005 * ref_mean * 0.005 * ref_mean + 1e-8);
        if (!std::isfinite(z)) z = 1e30;
        r.worst_z = std::max(r.worst_z, std::fabs(z));
        if (!(std::fabs(z) < 4)) pass = false;
      }
      ++r.blocks;
      if (pass) ++r.blocks_passed;
    }
  r.ok = means_ok && r.blocks > 0 && r.blocks_passed >= 0.99 * r.blocks;
  return r;
}

namespace {

// The regularized incomplete beta function I_x(a, b), by the continued fraction (modified
// Lentz), using the symmetry I_x(a, b) = 1 - I_{1-x}(b, a) where it converges slowly.
double incomplete_beta(double a, double b, double x) {
  if (x <= 0) return 0;
  if (x >= 1) return 1;
  if (x > (a + 1) / (a + b + 2)) return 1 - incomplete_beta(b, a, 1 - x);
  const double log_front =
      std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x);
  const double tiny = 1e-300;
  double c = 1, d = 1 - (a + b) * x / (a + 1);
  if (std::fabs(d) < tiny) d = tiny;
  d = 1 / d;
  double f = d;
  for (int m = 1; m < 500; ++m) {
    for (int pass = 0; pass < 2; ++pass) {
      double num = pass == 0 ? m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m))
                             : -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1));
      d = 1 + num * d;
      if (std::fabs(d) < tiny) d = tiny;
      c = 1 + num / c;
      if (std::fabs(c) < tiny) c = tiny;
      d = 1 / d;
      f *= c * d;
    }
    if (std::fabs(c * d - 1) < 1e-14) break;
  }
  return std::exp(log_front) * f / a;
}

// P(|T| > t) for Student's t with dof degrees of freedom.
double student_t_tail(double t, int dof) {
  return incomplete_beta(0.5 * dof, 0.5, dof / (dof + t * t));
}

}  // namespace

double student_t_matching_normal(double z, int dof) {
  const double p = std::erfc(z / std::sqrt(2.0));
  double lo = z, hi = 1e3;
  for (int i = 0; i < 200; ++i) {
    double mid = 0.5 * (lo + hi);
    (student_t_tail(mid, dof) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

ConvergenceResult check_convergence_spread(const std::vector<rt::ImageRgb>& renders,
                                           const rt::ImageRgb& ref, double spp_ratio) {
  ConvergenceResult r;
  const int n = int(renders.size());
  if (n < 4) {
    r.error = "the spread rule needs at least 4 renders, got " + std::to_string(n);
    return r;
  }
  for (const rt::ImageRgb& x : renders)
    if (!same_layout(x, ref)) {
      r.error = "image sizes differ: ours " + std::to_string(x.width()) + "x" +
                std::to_string(x.height()) + ", reference " + std::to_string(ref.width()) + "x" +
                std::to_string(ref.height());
      return r;
    }
  const double limit = student_t_matching_normal(4, n - 1);
  // The whole-image means are three tests, not hundreds: the normal's 3-sigma tail suffices.
  const double mean_limit = student_t_matching_normal(3, n - 1);
  const int w = ref.width(), h = ref.height();
  // The spread of n per-render means, as the variance of their mean.
  auto mean_and_var = [&](const std::vector<double>& m, double* mean, double* var) {
    *mean = 0;
    for (double v : m) *mean += v / n;
    double ss = 0;
    for (double v : m) ss += (v - *mean) * (v - *mean);
    *var = ss / (n - 1) / n;
  };
  bool means_ok = true;
  std::vector<double> m(size_t(n), 0.0);
  for (int c = 0; c < 3; ++c) {
    double ref_sum = 0;
    for (int k = 0; k < n; ++k) {
      double s = 0;
      for (size_t i = size_t(c); i < renders[k].rgb.size(); i += 3) s += renders[k].rgb[i];
      m[size_t(k)] = s / (double(w) * h);
    }
    for (size_t i = size_t(c); i < ref.rgb.size(); i += 3) ref_sum += ref.rgb[i];
    double var;
    mean_and_var(m, &r.mean_ours[c], &var);
    r.mean_ref[c] = ref_sum / (double(w) * h);
    const double d = r.mean_ours[c] - r.mean_ref[c];
    r.mean_rel_error[c] = d / std::max(std::fabs(r.mean_ref[c]), 1e-12);
    if (std::fabs(d) > 0.01 * std::fabs(r.mean_ref[c]) + 1e-9 &&
        !(std::fabs(d) < mean_limit * std::sqrt((1 + spp_ratio) * var)))
      means_ok = false;
  }
  for (int by = 0; by + 8 <= h; by += 8)
    for (int bx = 0; bx + 8 <= w; bx += 8) {
      bool pass = true;
      for (int c = 0; c < 3; ++c) {
        double sum_ref = 0;
        for (int k = 0; k < n; ++k) m[size_t(k)] = 0;
        for (int y = by; y < by + 8; ++y)
          for (int x = bx; x < bx + 8; ++x) {
            size_t i = 3 * (size_t(y) * w + x) + c;
            sum_ref += ref.rgb[i];
            for (int k = 0; k < n; ++k) m[size_t(k)] += renders[k].rgb[i] / 64.0;
          }
        double mean, var;
        mean_and_var(m, &mean, &var);
        const double ref_mean = sum_ref / 64;
        double z = (mean - ref_mean) /
                   std::sqrt((1 + spp_ratio) * var + 0.005 * ref_mean * 0.005 * ref_mean + 1e-8);
        if (!std::isfinite(z)) z = 1e30;
        // Reported on the normal's scale: 4 is the limit, as for the two-render rule.
        r.worst_z = std::max(r.worst_z, 4 * std::fabs(z) / limit);
        if (!(std::fabs(z) < limit)) pass = false;
      }
      ++r.blocks;
      if (pass) ++r.blocks_passed;
    }
  r.ok = means_ok && r.blocks > 0 && r.blocks_passed >= 0.99 * r.blocks;
  return r;
}

rt::ImageRgb side_by_side(const rt::ImageRgb& a, const rt::ImageRgb& b, const rt::ImageRgb& ref) {
  const int w = ref.width(), h = ref.height();
  rt::ImageRgb out;
  out.data_window = {{0, 0}, {3 * w, h}};
  out.display_window = out.data_window;
  out.rgb.assign(size_t(3) * w * h * 3, 0.f);
  double mean = 0;
  for (float v : ref.rgb) mean += v;
  mean /= std::max<size_t>(1, ref.rgb.size());
  const float diff_scale = float(1 / std::max(0.1 * mean, 1e-6));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      size_t i = 3 * (size_t(y) * w + x);
      float ours[3], lum_d = 0;
      for (int c = 0; c < 3; ++c) {
        ours[c] = 0.5f * (a.rgb[i + c] + b.rgb[i + c]);
        lum_d += (ours[c] - ref.rgb[i + c]) / 3;
      }
      for (int c = 0; c < 3; ++c) {
        out.rgb[3 * (size_t(y) * 3 * w + x) + c] = ours[c];
        out.rgb[3 * (size_t(y) * 3 * w + w + x) + c] = ref.rgb[i + c];
      }
      float d = std::clamp(lum_d * diff_scale, -1.f, 1.f);
      size_t o = 3 * (size_t(y) * 3 * w + 2 * w + x);
      out.rgb[o + 0] = d > 0 ? d : 0;
      out.rgb[o + 2] = d < 0 ? -d : 0;
    }
  return out;
}

}  // namespace compare
