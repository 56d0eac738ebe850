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
        double sum_ours = 0, sum_ref = 0, var = 0;
        for (int y = by; y < by + 8; ++y)
          for (int x = bx; x < bx + 8; ++x) {
            size_t i = 3 * (size_t(y) * w + x) + c;
            double va = a.rgb[i], vb = b.rgb[i];
            sum_ours += 0.5 * (va + vb);
            sum_ref += ref.rgb[i];
            var += 0.25 * (va - vb) * (va - vb);
          }
        double d = (sum_ours - sum_ref) / 64;
        var /= 64.0 * 64.0;
        double ref_mean = sum_ref / 64;
        double z =
            d / std::sqrt((1 + spp_ratio) * var + 0.005 * ref_mean * 0.005 * ref_mean + 1e-8);
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
