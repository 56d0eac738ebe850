// compiler/archive_dump.h — an archive back out as a pbrt-v3 scene (pbrtc --dump).
//
// Writes OUTDIR/<name>.pbrt and, for plymesh shapes, OUTDIR/meshes/*.ply, so
// that compiling the dump gives an archive byte-identical to the original
// outside the provenance section (format/ARCHIVE.md). Every kind of record is
// re-created in its original order: textures, materials and media under
// generated unique names (the archive keeps names only as provenance), area
// lights inside nested attribute blocks so each shape finds its own as the
// current one, numbers with enough digits to read back exactly (9 for
// floats, 17 for the double-precision transforms).
#pragma once

#include <string>

#include "format/scene_archive.h"

namespace pbrtc {

// False with *error when the archive holds something the dump cannot write
// yet (decoded images, lens data) or a file cannot be written.
bool dump_archive(const pbrta::SceneArchive& archive, const std::string& outdir,
                  const std::string& scene_name, std::string* error);

}  // namespace pbrtc
