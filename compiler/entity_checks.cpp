// compiler/entity_checks.cpp — see entity_checks.h.
#include "compiler/entity_checks.h"

#include <cstdint>
#include <string>

namespace pbrtc {
namespace {

// Where parameter `name` was given, or the directive when it was not.
Loc where(const ParamList& params, const char* name, Loc loc) {
  const ParsedParam* p = params.find(name);
  return p ? p->value_loc : loc;
}

}  // namespace

bool check_curve(const Entity& c, const ParamList& params, Loc loc, Diagnostics* diag) {
  const int32_t degree = c.get_int("degree");
  if (degree != 2 && degree != 3) {
    diag->error(where(params, "degree", loc), "curve \"degree\" " + std::to_string(degree) +
                                                  ": only degree 2 and 3 curves are supported");
    return false;
  }
  const std::string& basis = c.get_string("basis");
  if (basis != "bezier" && basis != "bspline") {
    diag->error(where(params, "basis", loc),
                "curve \"basis\" \"" + basis + "\": only \"bezier\" and \"bspline\" are supported");
    return false;
  }
  uint32_t ncp = 0;
  c.get_floats("P", &ncp);
  const int64_t n = ncp;
  int64_t segments = 0;
  if (basis == "bezier") {
    // pbrt-v3's test, with C++'s remainder: too few points can pass it and give no segment.
    if ((n - 1 - degree) % degree != 0) {
      diag->error(where(params, "P", loc),
                  "curve has " + std::to_string(n) + " control points: a degree " +
                      std::to_string(degree) + " Bezier curve needs " + std::to_string(degree) +
                      " n + " + std::to_string(degree + 1) + " for some n >= 0");
      return false;
    }
    segments = (n - 1) / degree;
  } else {
    if (n < degree + 1) {
      diag->error(where(params, "P", loc),
                  "curve has " + std::to_string(n) + " control points: a degree " +
                      std::to_string(degree) + " B-spline needs at least " +
                      std::to_string(degree + 1));
      return false;
    }
    segments = n - degree;
  }
  const std::string& type = c.get_string("type");
  if (type != "flat" && type != "ribbon" && type != "cylinder") {
    diag->error(where(params, "type", loc),
                "curve \"type\" \"" + type +
                    "\" unknown: \"flat\", \"ribbon\" or \"cylinder\" (pbrt-v3 would use "
                    "\"cylinder\")");
    return false;
  }
  uint32_t normals = 0;
  c.get_floats("N", &normals);
  const bool has_normals = c.given("N");
  if (has_normals && type != "ribbon") {
    diag->warning(where(params, "N", loc),
                  "curve normals are only used by \"ribbon\" curves (ignored, as pbrt-v3 does)");
  } else if (type == "ribbon" && !has_normals) {
    diag->error(loc, "a \"ribbon\" curve needs normals \"N\" at its segments' ends");
    return false;
  } else if (type == "ribbon" && int64_t(normals) != segments + 1) {
    diag->error(where(params, "N", loc), "a ribbon curve of " + std::to_string(segments) +
                                             (segments == 1 ? " segment" : " segments") +
                                             " needs " + std::to_string(segments + 1) +
                                             " normals, not " + std::to_string(normals));
    return false;
  }
  return true;
}

bool check_heterogeneous_medium(const Entity& m, const ParamList& params, Loc loc,
                                Diagnostics* diag) {
  uint32_t count = 0;
  m.get_floats("density", &count);
  const int64_t nx = m.get_int("nx"), ny = m.get_int("ny"), nz = m.get_int("nz");
  // Three int32s: the product needs more than 64 bits at worst.
  const __int128 cells = __int128(nx) * ny * nz;
  if (cells != __int128(count)) {
    const bool fits = cells >= INT64_MIN && cells <= INT64_MAX;
    diag->error(where(params, "density", loc),
                "heterogeneous medium has " + std::to_string(count) +
                    " density values; nx * ny * nz = " + std::to_string(nx) + " * " +
                    std::to_string(ny) + " * " + std::to_string(nz) +
                    (fits ? " = " + std::to_string(int64_t(cells)) : std::string()));
    return false;
  }
  return true;
}

}  // namespace pbrtc
