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

// How meshes are written: pbrtc --dump keeps each shape's type (plymesh to PLY files,
// trianglemesh inline); pbrt --cat writes every mesh inline as a trianglemesh, and
// pbrt --toply (as pbrt-v3's) every triangle mesh as a plymesh with its PLY file.
enum class DumpMeshes { kAsCompiled, kInline, kAllPly };

struct DumpOptions {
  DumpMeshes meshes = DumpMeshes::kAsCompiled;
  std::string mesh_prefix = "meshes/mesh";  // PLY files: OUTDIR/<prefix><mesh index>.ply
  // Images and lens files named by the paths the scene gave (the archive's provenance, as
  // pbrt-v3's --cat prints them) instead of written out. Such a scene may not compile back
  // to the same archive: an imagemap's gamma and scale were applied to the stored texels.
  bool original_files = false;
};

// The scene text into *text instead of a file; side files (PLY meshes, and images and lens
// files unless original_files) are still written under outdir.
bool dump_archive_text(const pbrta::SceneArchive& archive, const std::string& outdir,
                       const DumpOptions& options, std::string* text, std::string* error);

// Writes width x height texels (channels 1 or 3, interleaved, rows top to
// bottom) as a little-endian PFM ("Pf" or "PF", bottom row first as PFM
// stores it), which pbrt-v3 and compiler/image_decoder read back exactly.
bool write_pfm(const std::string& path, const float* texels, uint32_t width, uint32_t height,
               uint32_t channels, std::string* error);

}  // namespace pbrtc
