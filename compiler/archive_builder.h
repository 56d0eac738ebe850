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

#include "compiler/scene_desc.h"
#include "compiler/source_files.h"
#include "format/archive.h"

namespace pbrtc {

struct ArchiveOptions {
  bool compress = true;  // false: --codec none (sections usable in place)
  int zstd_level = 6;
  int threads = 0;       // 0: all cores
  // Geometry sections hold whole meshes up to this many raw bytes, so a
  // large scene decompresses in parallel.
  uint64_t geometry_chunk_bytes = uint64_t(16) << 20;
  // Texels sections hold whole images (all levels) up to this many raw bytes; a larger image
  // has a section of its own.
  uint64_t texel_chunk_bytes = uint64_t(16) << 20;
};

struct ArchiveStats {
  uint64_t file_size = 0;
  uint64_t raw_size = 0;
  uint32_t sections = 0;
};

// Writes scene to path. base_dir is the top-level scene file's directory
// (file names inside are stored relative to it). False with *error set on
// failure; no file is left behind then.
bool write_archive(const SceneDesc& scene, const SourceFiles& files, const std::string& base_dir,
                   const std::string& path, const ArchiveOptions& options, ArchiveStats* stats,
                   std::string* error);

}  // namespace pbrtc
