// format/entity_rules.cpp — see entity_rules.h.
#include "format/entity_rules.h"

#include <climits>

namespace pbrta {

CountRule count_rule_of(Category category, uint32_t type) {
  static const int curve = find_type(Category::kShape, "curve");
  static const int heterogeneous = find_type(Category::kMedium, "heterogeneous");
  static const int fourier = find_type(Category::kMaterial, "fourier");
  static const int subsurface = find_type(Category::kMaterial, "subsurface");
  static const int kdsubsurface = find_type(Category::kMaterial, "kdsubsurface");
  if (category == Category::kShape && int64_t(type) == curve) return CountRule::kCurve;
  if (category == Category::kMedium && int64_t(type) == heterogeneous) return CountRule::kDensity;
  if (category == Category::kMaterial && int64_t(type) == fourier) return CountRule::kFourierTable;
  if (category == Category::kMaterial &&
      (int64_t(type) == subsurface || int64_t(type) == kdsubsurface))
    return CountRule::kBssrdfTable;
  return CountRule::kNone;
}

bool check_curve_rules(const CurveCounts& c, RuleViolation* v) {
  auto fail = [&](const char* param, std::string message) {
    v->param = param;
    v->message = std::move(message);
    return false;
  };
  const int64_t degree = c.degree;
  if (degree != 2 && degree != 3)
    return fail("degree", "curve \"degree\" " + std::to_string(degree) +
                              ": only degree 2 and 3 curves are supported");
  if (c.basis != "bezier" && c.basis != "bspline")
    return fail("basis", "curve \"basis\" \"" + std::string(c.basis) +
                             "\": only \"bezier\" and \"bspline\" are supported");
  // Bounded far below 2^63 by the archive's size.
  const int64_t n = int64_t(c.control_points);
  int64_t segments = 0;
  if (c.basis == "bezier") {
    if ((n - 1 - degree) % degree != 0)
      return fail("P", "curve has " + std::to_string(n) + " control points: a degree " +
                           std::to_string(degree) + " Bezier curve needs " +
                           std::to_string(degree) + " n + " + std::to_string(degree + 1) +
                           " for some n >= 0");
    segments = (n - 1) / degree;
  } else {
    if (n < degree + 1)
      return fail("P", "curve has " + std::to_string(n) + " control points: a degree " +
                           std::to_string(degree) + " B-spline needs at least " +
                           std::to_string(degree + 1));
    segments = n - degree;
  }
  if (c.type != "flat" && c.type != "ribbon" && c.type != "cylinder")
    return fail("type", "curve \"type\" \"" + std::string(c.type) +
                            "\" unknown: \"flat\", \"ribbon\" or \"cylinder\" (pbrt-v3 would use "
                            "\"cylinder\")");
  if (c.type == "ribbon" && !c.normals_given)
    return fail("", "a \"ribbon\" curve needs normals \"N\" at its segments' ends");
  if (c.type == "ribbon" && int64_t(c.normals) != segments + 1)
    return fail("N", "a ribbon curve of " + std::to_string(segments) +
                         (segments == 1 ? " segment" : " segments") + " needs " +
                         std::to_string(segments + 1) + " normals, not " +
                         std::to_string(c.normals));
  return true;
}

bool check_density_rule(int32_t nx, int32_t ny, int32_t nz, uint64_t density_count,
                        RuleViolation* v) {
  // Three int32s: the product needs more than 64 bits at worst.
  const __int128 cells = __int128(nx) * ny * nz;
  if (cells == __int128(density_count)) return true;
  const bool fits = cells >= INT64_MIN && cells <= INT64_MAX;
  v->param = "density";
  v->message = "heterogeneous medium has " + std::to_string(density_count) +
               " density values; nx * ny * nz = " + std::to_string(nx) + " * " +
               std::to_string(ny) + " * " + std::to_string(nz) +
               (fits ? " = " + std::to_string(int64_t(cells)) : std::string());
  return false;
}

}  // namespace pbrta
