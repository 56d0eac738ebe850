// format/archive_writer.h — writes a scene archive (.pbrta) from a list of sections.
//
// The generic container layer of the archive (format/archive.h describes the layout): the caller
// adds sections (kind, raw bytes, element count, codec) in table order; write() compresses them
// in parallel over sections and frames, checksums them, lays out the file (64-byte header, the
// table, each section 16-byte aligned and followed by at least 16 zero bytes) and writes it
// atomically. The output depends only on the sections, the effects and the zstd level: every
// frame is compressed by a single-threaded zstd context, so the thread count never changes a byte.
//
// zstd sections are cut into kFrameSize frames; one of more than 1 MiB and at most
// kSmallFramesMax bytes is tried in 1 MiB frames too, and kept so when that costs at most
// 1/kSmallFramesSlack more bytes: its frames then decode on several threads at once (caustic
// glass's 2 MiB of geometry loaded on 2 threads in 0.40 ms instead of 0.70). A compressed section
// whose decoded size would exceed the reader's zip-bomb bounds (format/archive_reader.h:
// kMaxZstdRatio times the stored size + 1 MiB per section) is stored raw instead, so that every
// archive written can be read; table() tells which codec was used.
//
// Ownership: the writer owns copies of (or the moved-in) section bytes until it is destroyed.
// Thread safety: one thread drives a writer; write() uses oneTBB internally.
// Failure: write() returns false with one message ("cannot write 'x.pbrta': No space left on
// device") and leaves no file behind: it writes path + ".tmp-<pid>" in the same directory, syncs
// it and renames it over path, removing the temporary on any failure, so an existing file at path
// is either replaced whole or left as it was.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "format/archive.h"

namespace pbrta {

// Raw bytes per frame. Measured on mesh200 (4.5M triangles), 256 KiB / 1 / 2 / 4 / 8 MiB frames:
// archives 38.7 / 32.7 / 29.5 / 26.1 / 24.8 MB (one frame per 16 MiB section: 24.3 MB): a frame
// cannot refer to an earlier one, and a scene repeats whole meshes. 4 MiB keeps the size within
// 7% of one frame, loaded fastest, and still gives two threads four frames of a 16 MiB section.
inline constexpr uint64_t kFrameSize = uint64_t{4} << 20;
inline constexpr uint64_t kSmallFrameSize = uint64_t{1} << 20;
// The sections that may be stored in 1 MiB frames (see above): a larger one already has four or
// more 4 MiB frames to share out.
inline constexpr uint64_t kSmallFramesMax = uint64_t{16} << 20;
inline constexpr uint64_t kSmallFramesSlack = 20;  // 5%

class ArchiveWriter {
 public:
  // Appends a section, kRaw or kZstd (shuffle: its frames byte-shuffled in 4-byte lanes, for
  // arrays of 4-byte numbers); returns its index in the table. count is stored as given.
  uint32_t add_section(SectionKind kind, std::vector<uint8_t> raw, uint32_t count, Codec codec,
                       bool shuffle = false);
  uint32_t add_section(SectionKind kind, const void* data, size_t size, uint32_t count, Codec codec,
                       bool shuffle = false);
  // Appends a section the caller has already encoded (kDraco: format/draco_codec.h): `stored`
  // is written as it is, `raw` must be what it decodes to (the writer does not decode it to
  // check) and is written instead, raw, if the sizes exceed the reader's bounds.
  uint32_t add_encoded_section(SectionKind kind, std::vector<uint8_t> raw,
                               std::vector<uint8_t> stored, uint32_t count, Codec codec);

  uint32_t section_count() const { return static_cast<uint32_t>(sections_.size()); }

  // Called as sections finish compressing, with the raw bytes compressed so far and the total
  // to compress (the sections whose codec is zstd), for a progress display: from the writer's
  // threads as format/progress_count.h describes (never two calls at once, done never goes
  // down), and once at the end with done == total when every section compressed. Not called
  // when nothing is to be compressed.
  using CompressProgress = std::function<void(uint64_t done, uint64_t total)>;

  // Writes the archive to path (see above). zstd_level is clamped to zstd's range; threads <= 0
  // means all cores. May be called more than once; the sections are kept.
  [[nodiscard]] bool write(const std::string& path, uint64_t effects, int zstd_level, int threads,
                           std::string* error, const CompressProgress& progress = {});

  // After a successful write: the file's size, its header and its table (offsets, stored sizes,
  // codecs actually used), for reports.
  uint64_t last_file_size() const { return header_.file_size; }
  const Header& header() const { return header_; }
  const std::vector<SectionEntry>& table() const { return table_; }

 private:
  struct Section {
    SectionKind kind;
    Codec codec;
    bool shuffle;
    uint32_t count;
    std::vector<uint8_t> raw;
    std::vector<uint8_t> stored;  // add_encoded_section's bytes; empty otherwise
  };
  std::vector<Section> sections_;
  Header header_{};
  std::vector<SectionEntry> table_;
};

}  // namespace pbrta
