#include "format/archive_names.h"

namespace pbrta {

std::string_view section_kind_name(SectionKind kind) {
  // Indexed by SectionKind (1-based; 0 is no kind).
  static constexpr std::string_view kNames[] = {
      "unknown",       "scene",     "strings", "entities", "values",      "words",  "transforms",
      "textures",      "materials", "media",   "lights",   "area_lights", "shapes", "objects",
      "object_shapes", "instances", "meshes",  "geometry", "images",      "texels", "provenance"};
  static_assert(std::size(kNames) == size_t(SectionKind::kCount), "a name for every kind");
  const uint32_t k = uint32_t(kind);
  return k < std::size(kNames) ? kNames[k] : kNames[0];
}

std::string_view codec_name(Codec codec) {
  static constexpr std::string_view kNames[] = {"raw", "zstd", "draco"};
  static_assert(std::size(kNames) == size_t(Codec::kCount), "a name for every codec");
  return uint32_t(codec) < std::size(kNames) ? kNames[uint32_t(codec)] : "unknown";
}

}  // namespace pbrta
