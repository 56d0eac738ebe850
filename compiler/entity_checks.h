// compiler/entity_checks.h — pbrt-v3's checks on a curve shape and a heterogeneous medium that
// the schema cannot express, because they tie one parameter's count to others' values.
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

}  // namespace pbrtc
