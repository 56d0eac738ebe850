// compiler/archive_dump.h — an archive back out as a pbrt-v3 scene (pbrtc --dump).
//
// Writes OUTDIR/<name>.pbrt and, for plymesh shapes, OUTDIR/meshes/*.ply, for
// textures' and lights' images OUTDIR/images/imageN.pfm (the texels as
// decoded, in float32, so they read back bit for bit), so that compiling the
// dump gives an archive byte-identical to the original outside the provenance
// section (format/ARCHIVE.md). Every kind of record is
// re-created in its original order: textures, materials and media under
// generated unique names (the archive keeps names only as provenance), area
// lights inside nested attribute blocks so each shape finds its own as the
// current one, numbers with enough digits to read back exactly (9 for
// floats, 17 for the double-precision transforms).
#pragma once

#include <cstdint>
#include <string>

#include "format/scene_archive.h"

namespace pbrtc {

// False with *error when the archive holds something the dump cannot write
// or a file cannot be written.
bool dump_archive(const pbrta::SceneArchive& archive, const std::string& outdir,
                  const std::string& scene_name, std::string* error);

// Writes width x height texels (channels 1 or 3, interleaved, rows top to
// bottom) as a little-endian PFM ("Pf" or "PF", bottom row first as PFM
// stores it), which pbrt-v3 and compiler/image_decoder read back exactly.
bool write_pfm(const std::string& path, const float* texels, uint32_t width, uint32_t height,
               uint32_t channels, std::string* error);

}  // namespace pbrtc
