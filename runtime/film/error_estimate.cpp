// runtime/film/error_estimate.cpp — see error_estimate.h.
#include "runtime/film/error_estimate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rt {

ErrorEstimate estimate_error(const Film& film, std::vector<float>* per_pixel) {
  const Bounds2i b = film.cropped_pixel_bounds();
  ErrorEstimate out;
  out.valid = film.sample_count() >= 2;
  if (per_pixel) per_pixel->assign(size_t(b.area()) * 3, 0.f);
  if (!out.valid || b.empty()) return out;
  double sum = 0;
  size_t k = 0;
  for (int y = b.min.y; y < b.max.y; ++y) {
    double row = 0;  // per row, so a long sum keeps its precision
    for (int x = b.min.x; x < b.max.x; ++x) {
      const Rgb e = film.half_pixel({x, y}, 0), o = film.half_pixel({x, y}, 1);
      for (int c = 0; c < 3; ++c, ++k) {
        const double d = double(e[c]) - double(o[c]);
        const double m = 0.5 * (double(e[c]) + double(o[c]));
        const double ref2 = std::max(double(e[c]) * double(o[c]), 0.25 * m * m);
        const double r = 0.25 * d * d / (ref2 + 0.01);
        row += r;
        if (per_pixel) (*per_pixel)[k] = float(std::sqrt(r));
      }
    }
    sum += row;
  }
  out.rel_error = std::sqrt(sum / (3.0 * double(b.area())));
  return out;
}

std::string error_percent(double fraction) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g%%", 100 * fraction);
  return buf;
}

}  // namespace rt
