// compiler/archive_builder.h — a SceneDesc to a scene archive.
//
// Lays the resolved scene out as the sections format/ARCHIVE.md specifies
// (strings, entities and their values, transforms, records, geometry chunks,
// provenance) and hands them to format's ArchiveWriter, which compresses and
// writes the file atomically. Output depends only on the scene: file names
// are stored relative to the top-level scene's directory, no timestamps, and
// the bytes are the same whatever the thread count.
#pragma once

#include <string>
#include <vector>

#include "compiler/scene_desc.h"
#include "compiler/source_files.h"
#include "format/archive.h"

namespace pbrtc {

// Called while an archive is written, so a long compile can show where it is: phase() once
// before each long step ("Draco meshes": the meshes Draco will take; "compressing", or
// "writing" for --codec none: the sections), then, within it, encoded() as Draco meshes finish
// (triangles so far and in all) and compressed() as sections finish compressing (raw bytes so
// far and in all). Those two come from worker threads, never two calls at once, done never
// goes down, and the last has done == total unless the write fails. Must be cheap; the callee
// throttles by time.
struct ArchiveProgress {
  virtual ~ArchiveProgress() = default;
  virtual void phase(const char* name, size_t items) = 0;
  virtual void encoded(uint64_t done, uint64_t total) = 0;
  virtual void compressed(uint64_t done, uint64_t total) = 0;
};

struct ArchiveOptions {
  bool compress = true;  // false: --codec none (sections usable in place)
  int zstd_level = 6;
  int threads = 0;  // 0: all cores
  // Geometry sections hold whole meshes up to this many raw bytes, so a
  // large scene decompresses in parallel.
  uint64_t geometry_chunk_bytes = uint64_t(16) << 20;
  // Texels sections hold whole images (all levels) up to this many raw bytes; a larger image
  // has a section of its own.
  uint64_t texel_chunk_bytes = uint64_t(16) << 20;
  // Lossy mesh compression (format/draco_codec.h): 0 off, else the position quantization bits
  // (8..30). Every mesh of at least draco_min_triangles triangles goes into a geometry section
  // of its own with codec kDraco, unless it has tangents (Draco cannot carry them) or a
  // zero-length normal (Draco would make it a unit vector, and pbrt-v3 treats a zero shading
  // normal as absent). Needs compress.
  int draco_bits = 0;
  bool draco_sequential = false;  // keep vertex and triangle order (larger)
  uint32_t draco_min_triangles = 64;
  // Texel storage (--texture-precision, ARCHIVE.md images): the PixelFormat of every image
  // pyramid and source image (imagemap textures, environment, projection and goniometric
  // maps); environment-map sampling distributions stay f32. kFloat32 writes the bytes pbrtc
  // always wrote. write_archive refuses an image the format cannot hold (f16: a finite value
  // of magnitude 65520 or more; unorm8: anything outside [0, 1]) with an error naming it.
  pbrta::PixelFormat texture_format = pbrta::PixelFormat::kFloat32;
  ArchiveProgress* progress = nullptr;  // null: silent (tests, pbrtc --quiet)
};

// One mesh stored with Draco: sizes, the displacement measured against the original vertices
// (largest per-axis distance to the nearest original), the bound the bits imply and the float
// rounding Draco may add to it (format/draco_codec.h), all in object space.
struct DracoMeshStats {
  uint32_t mesh = 0;
  uint64_t triangles = 0;
  uint64_t stored_bytes = 0, raw_bytes = 0;
  double displacement = 0, bound = 0, slack = 0;
  double encode_seconds = 0, decode_seconds = 0;
};

struct ArchiveStats {
  uint64_t file_size = 0;
  uint64_t raw_size = 0;
  uint32_t sections = 0;
  std::vector<DracoMeshStats> draco;  // in mesh order
  // Meshes Draco could take but that stayed lossless: Draco failed, dropped degenerate
  // triangles, or compressed beyond the reader's bounds.
  uint32_t draco_kept_lossless = 0;
};

// Writes scene to path. base_dir is the top-level scene file's directory
// (file names inside are stored relative to it). False with *error set on
// failure; no file is left behind then.
bool write_archive(const SceneDesc& scene, const SourceFiles& files, const std::string& base_dir,
                   const std::string& path, const ArchiveOptions& options, ArchiveStats* stats,
                   std::string* error);

}  // namespace pbrtc
