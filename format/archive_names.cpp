#include "format/archive_names.h"

namespace pbrta {

std::string_view section_kind_name(SectionKind kind) {
  switch (kind) {
    case SectionKind::kScene:
      return "scene";
    case SectionKind::kStrings:
      return "strings";
    case SectionKind::kEntities:
      return "entities";
    case SectionKind::kValues:
      return "values";
    case SectionKind::kWords:
      return "words";
    case SectionKind::kTransforms:
      return "transforms";
    case SectionKind::kTextures:
      return "textures";
    case SectionKind::kMaterials:
      return "materials";
    case SectionKind::kMedia:
      return "media";
    case SectionKind::kLights:
      return "lights";
    case SectionKind::kAreaLights:
      return "area_lights";
    case SectionKind::kShapes:
      return "shapes";
    case SectionKind::kObjects:
      return "objects";
    case SectionKind::kObjectShapes:
      return "object_shapes";
    case SectionKind::kInstances:
      return "instances";
    case SectionKind::kMeshes:
      return "meshes";
    case SectionKind::kGeometry:
      return "geometry";
    case SectionKind::kImages:
      return "images";
    case SectionKind::kTexels:
      return "texels";
    case SectionKind::kProvenance:
      return "provenance";
    case SectionKind::kCount:
      break;
  }
  return "unknown";
}

std::string_view codec_name(Codec codec) {
  switch (codec) {
    case Codec::kNone:
      return "none";
    case Codec::kZstd:
      return "zstd";
    case Codec::kZstdShuffle4:
      return "zstd_shuffle4";
    case Codec::kDraco:
      return "draco";
    case Codec::kZstdShuffle4Frames:
      return "zstd_shuffle4_frames";
    case Codec::kNoneChunked:
      return "none_chunked";
    case Codec::kZstdShuffle4Frames1M:
      return "zstd_shuffle4_frames_1m";
    case Codec::kCount:
      break;
  }
  return "unknown";
}

}  // namespace pbrta
