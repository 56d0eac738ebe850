// compiler/entity_checks.cpp — see entity_checks.h.
#include "compiler/entity_checks.h"

#include <cstdint>
#include <string>

#include "format/entity_rules.h"

namespace pbrtc {
namespace {

// The first value of parameter `name` as the scene gave it, or the directive's location.
Loc value_loc(const ParamList& params, const std::string& name, Loc loc) {
  const ParsedParam* p = name.empty() ? nullptr : params.find(name);
  return p ? p->value_loc : loc;
}

// Reports v at the parameter it names.
bool report(const pbrta::RuleViolation& v, const ParamList& params, Loc loc, Diagnostics* diag) {
  diag->error(value_loc(params, v.param, loc), v.message);
  return false;
}

}  // namespace

bool check_curve(const Entity& c, const ParamList& params, Loc loc, Diagnostics* diag) {
  pbrta::CurveCounts counts;
  counts.degree = c.get_int("degree");
  counts.basis = c.get_string("basis");
  uint32_t points = 0, normals = 0;
  c.get_floats("P", &points);
  c.get_floats("N", &normals);
  counts.control_points = points;
  counts.type = c.get_string("type");
  counts.normals_given = c.given("N");
  counts.normals = normals;
  pbrta::RuleViolation v;
  if (!pbrta::check_curve_rules(counts, &v)) return report(v, params, loc, diag);
  if (counts.normals_given && counts.type != "ribbon")
    diag->warning(value_loc(params, "N", loc),
                  "curve normals are only used by \"ribbon\" curves (ignored, as pbrt-v3 does)");
  return true;
}

bool check_heterogeneous_medium(const Entity& m, const ParamList& params, Loc loc,
                                Diagnostics* diag) {
  uint32_t count = 0;
  m.get_floats("density", &count);
  pbrta::RuleViolation v;
  if (!pbrta::check_density_rule(m.get_int("nx"), m.get_int("ny"), m.get_int("nz"), count, &v))
    return report(v, params, loc, diag);
  return true;
}

}  // namespace pbrtc
