// format/archive_names.h — printable names of the archive's enums (format/archive.h).
//
// Error messages and reports name sections by the lowercase of their kind ("entities",
// "object_shapes", "geometry") and codecs by "raw", "zstd", "draco". The functions return views of
// static strings, never fail (a value outside the enum is "unknown") and are safe from any thread.
#pragma once

#include <iterator>
#include <string_view>

#include "format/archive.h"

namespace pbrta {

// "scene", "strings", ..., "provenance"; "unknown" for values outside SectionKind.
std::string_view section_kind_name(SectionKind kind);

// "raw", "zstd", "draco"; "unknown" for values outside Codec.
std::string_view codec_name(Codec codec);

}  // namespace pbrta
