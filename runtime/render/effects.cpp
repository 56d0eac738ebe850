// runtime/render/effects.cpp — see effects.h.
#include "runtime/render/effects.h"

#include "format/archive.h"

namespace rt {

std::string effect_names(uint64_t effects) {
  static const struct {
    uint64_t bit;
    const char* name;
  } kNames[] = {
      {pbrta::kEffectMedia, "media"},
      {pbrta::kEffectMotionBlur, "motion blur"},
      {pbrta::kEffectTextures, "textures"},
      {pbrta::kEffectAreaLights, "area lights"},
      {pbrta::kEffectInfiniteLights, "infinite lights"},
      {pbrta::kEffectSubsurface, "subsurface"},
      {pbrta::kEffectInstancing, "instancing"},
      {pbrta::kEffectAlpha, "alpha"},
  };
  std::string out;
  for (const auto& n : kNames)
    if (effects & n.bit) {
      if (!out.empty()) out += ", ";
      out += n.name;
    }
  return out.empty() ? "none" : out;
}

}  // namespace rt
