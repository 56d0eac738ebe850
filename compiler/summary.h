// compiler/summary.h — the human-readable summary pbrtc --check prints.
#pragma once

#include <iosfwd>
#include <string>

#include "compiler/scene_desc.h"

namespace pbrtc {

// Names of the effects the scene calls for, comma separated ("none" if empty).
std::string effects_list(const Effects& fx);
void print_summary(std::ostream& out, const std::string& path, const SceneDesc& scene);

}  // namespace pbrtc
