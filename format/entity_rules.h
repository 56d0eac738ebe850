// format/entity_rules.h — pbrt-v3's rules that tie one parameter's count to other parameters'
// values, for the two entity types that have them: a curve shape and a heterogeneous medium.
//
// pbrt-v3 reports a broken one with Error() and makes no shape or medium. pbrtc reports it at
// compile time (compiler/entity_checks.h, at the offending parameter), and the archive reader
// refuses an archive holding one (format/ARCHIVE.md section 10), so a renderer may index a
// curve's control points and normals, or a density grid, by these counts without checking.
//
// Rules (pbrt-v3's curve.cpp and api.cpp):
//   curve: "degree" 2 or 3; "basis" "bezier" or "bspline"; a Bezier curve has degree * n +
//     degree + 1 control points for some n (pbrt-v3's test, C++ remainder included: with degree
//     2 a single point passes and makes no segment), a B-spline at least degree + 1; "type"
//     "flat", "ribbon" or "cylinder"; a ribbon curve has exactly one normal per segment end.
//   heterogeneous medium: exactly nx * ny * nz "density" values.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "format/schema.h"

namespace pbrta {

// Which of the rules below an entity type is held to: the one list of the types that have them,
// for the reader's checks (format/scene_validation.cpp). A fourier
// material's table ties its arrays' counts together as well; its rules are in
// format/fourier_table.h.
enum class CountRule : uint8_t { kNone, kCurve, kDensity, kFourierTable, kBssrdfTable };
CountRule count_rule_of(Category category, uint32_t type);

// A broken rule: the parameter to point at and why (empty param: the entity as a whole).
struct RuleViolation {
  std::string param;
  std::string message;
};

struct CurveCounts {
  int32_t degree = 3;
  std::string_view basis = "bezier";
  uint64_t control_points = 0;
  std::string_view type = "flat";
  bool normals_given = false;
  uint64_t normals = 0;
};

// False with *v set when the curve breaks a rule.
bool check_curve_rules(const CurveCounts& c, RuleViolation* v);

// False with *v set when density_count is not nx * ny * nz.
bool check_density_rule(int32_t nx, int32_t ny, int32_t nz, uint64_t density_count,
                        RuleViolation* v);

}  // namespace pbrta
