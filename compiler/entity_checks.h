// compiler/entity_checks.h — checks on a curve shape and a medium that the schema cannot
// express, because they tie one parameter's count or value to others'.
//
// pbrt-v3 reports these with Error() and then makes no shape (curves) or no medium, so the scene
// it renders lacks them; pbrtc, which checks scenes as a compiler checks code, makes them compile
// errors at the parameter that is wrong, by the rules in format/entity_rules.h (which the archive
// reader applies too). Normals on a curve that is not a ribbon are ignored with a warning, as
// pbrt-v3 does.
// Each function takes the resolved entity and the directive's parameters (for locations) and
// returns false after reporting an error.
#pragma once

#include "compiler/diagnostics.h"
#include "compiler/params.h"
#include "compiler/scene_desc.h"

namespace pbrtc {

bool check_curve(const Entity& curve, const ParamList& params, Loc loc, Diagnostics* diag);
bool check_heterogeneous_medium(const Entity& medium, const ParamList& params, Loc loc,
                                Diagnostics* diag);
// Both medium types: a known "preset" (compiler/medium_presets.h) is written
// into sigma_a and sigma_s unless the scene gave them (pbrt-v3's order: the
// preset, then the given values, both scaled by "scale" at render), so the
// archive holds the coefficients; an unknown preset, a negative coefficient
// or scale, and |g| >= 1 (where Henyey-Greenstein has no density) are errors;
// a density grid whose extinction differs between channels is a warning.
bool check_medium(Entity* medium, const ParamList& params, Loc loc, Diagnostics* diag);

}  // namespace pbrtc
