// compiler/archive_info.h — pbrtc's reports on archives and on the schema.
#pragma once

#include <iosfwd>

#include "format/scene_archive.h"

namespace pbrtc {

// pbrtc --info: version, effects, sections (kind, codec, raw and stored
// sizes), record counts.
void print_archive_info(std::ostream& out, const std::string& path,
                        const pbrta::SceneArchive& archive);
// pbrtc --print-schema: every type's parameters as Markdown tables (SCHEMA.md).
void print_schema_markdown(std::ostream& out);

}  // namespace pbrtc
