// runtime/render/effects.h — names for the archive's effect bits, for --stats and messages.
#pragma once

#include <cstdint>
#include <string>

namespace rt {

// "area lights, textures" for the bits set in `effects` (or "none").
std::string effect_names(uint64_t effects);

}  // namespace rt
