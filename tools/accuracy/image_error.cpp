#include "tools/accuracy/image_error.h"

#include <cmath>

namespace accuracy {

bool image_errors(const rt::ImageRgb& ours, const rt::ImageRgb& reference, ImageErrors* out,
                  std::string* error) {
  const rt::Bounds2i& a = ours.data_window;
  const rt::Bounds2i& b = reference.data_window;
  if (a.min.x != b.min.x || a.min.y != b.min.y || a.max.x != b.max.x || a.max.y != b.max.y ||
      ours.rgb.size() != reference.rgb.size()) {
    *error = "image is " + std::to_string(ours.width()) + "x" + std::to_string(ours.height()) +
             " at (" + std::to_string(a.min.x) + "," + std::to_string(a.min.y) +
             "), the reference " + std::to_string(reference.width()) + "x" +
             std::to_string(reference.height()) + " at (" + std::to_string(b.min.x) + "," +
             std::to_string(b.min.y) + "): render at the reference's --resdiv and crop";
    return false;
  }
  if (ours.rgb.empty()) {
    *error = "empty image";
    return false;
  }
  // Sums in double: a 1% error over a million values must not drown in rounding.
  double rel = 0, sq = 0, abs_rel = 0;
  for (size_t i = 0; i < ours.rgb.size(); ++i) {
    double x = ours.rgb[i], r = reference.rgb[i];
    double d = x - r, denom = r * r + 0.01;
    rel += d * d / denom;
    sq += d * d;
    abs_rel += std::fabs(d) / std::sqrt(denom);
  }
  double n = double(ours.rgb.size());
  out->relmse = rel / n;
  out->rmse = std::sqrt(sq / n);
  out->mare = abs_rel / n;
  return true;
}

}  // namespace accuracy
