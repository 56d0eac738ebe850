// compiler/entity_checks.cpp — see entity_checks.h.
#include "compiler/entity_checks.h"

#include <cmath>
#include <cstdint>
#include <string>

#include "compiler/medium_presets.h"
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
  const float* density = m.get_floats("density", &count);
  pbrta::RuleViolation v;
  if (!pbrta::check_density_rule(m.get_int("nx"), m.get_int("ny"), m.get_int("nz"), count, &v))
    return report(v, params, loc, diag);
  for (uint32_t i = 0; i < count; ++i)
    if (!(density[i] >= 0) || !std::isfinite(density[i])) {
      diag->error(value_loc(params, "density", loc),
                  "heterogeneous medium density value " + std::to_string(i) + " is " +
                      std::to_string(density[i]) + " (densities are finite and not negative)");
      return false;
    }
  return true;
}

bool check_medium(Entity* m, const ParamList& params, Loc loc, Diagnostics* diag) {
  bool ok = true;
  const std::string& preset = m->get_string("preset");
  if (!preset.empty()) {
    const MeasuredMedium* mm = find_measured_medium(preset);
    if (!mm) {
      diag->error(
          value_loc(params, "preset", loc),
          "unknown medium preset \"" + preset + "\" (known: " + measured_medium_names() + ")");
      return false;
    }
    for (const char* name : {"sigma_a", "sigma_s"}) {
      Value& v = m->values[size_t(m->slot(name))];
      if (v.given) continue;
      const float* rgb = name[6] == 'a' ? mm->sigma_a : mm->sigma_prime_s;
      for (int i = 0; i < 3; ++i) m->floats[v.offset + i] = rgb[i];
      v.given = true;
    }
  }
  for (const char* name : {"sigma_a", "sigma_s"}) {
    const float* rgb = m->get_floats(name);
    if (rgb[0] < 0 || rgb[1] < 0 || rgb[2] < 0) {
      diag->error(value_loc(params, name, loc),
                  std::string("medium \"") + name + "\" has a negative component");
      ok = false;
    }
  }
  if (!(m->get_float("scale") >= 0)) {
    diag->error(value_loc(params, "scale", loc), "medium \"scale\" must not be negative");
    ok = false;
  }
  if (ok && m->type_name() == "heterogeneous") {
    // pbrt-v3's grid medium tracks one extinction, the red channel's, and says so.
    const float k = m->get_float("scale");
    const float* a = m->get_floats("sigma_a");
    const float* sc = m->get_floats("sigma_s");
    float t[3];
    for (int i = 0; i < 3; ++i) t[i] = a[i] * k + sc[i] * k;
    if (t[1] != t[0] || t[2] != t[0])
      diag->warning(loc, "heterogeneous medium: sigma_a + sigma_s differs between channels; "
                         "its extinction is the red channel's in all three (as in pbrt-v3)");
  }
  const float g = m->get_float("g");
  if (!(g > -1 && g < 1)) {
    diag->error(value_loc(params, "g", loc),
                "medium \"g\" must lie in (-1, 1): Henyey-Greenstein has no density at +-1");
    ok = false;
  }
  return ok;
}

}  // namespace pbrtc
