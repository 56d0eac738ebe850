// format/archive_reader.h — opens a scene archive (.pbrta) and decodes its sections.
//
// The generic container layer of the archive (format/archive.h describes the layout): the reader
// maps the file read-only (reads it whole when it is 64 KiB or less), validates the header, the
// section table and the layout of every section, then load_sections() verifies each section's
// checksum and decodes it, on every thread: raw sections by 1 MiB chunk, zstd sections by frame.
// Raw sections are used in place from the mapping (or the copy), 16-byte aligned and followed by
// 16 bytes of padding; compressed ones are decoded into one owned buffer, each at a 64-byte
// aligned offset with 16 zero bytes after its data. What the sections mean is the caller's
// business. Opening and the table checks are in archive_reader.cpp, the decoding in
// section_loading.cpp.
//
// Draco sections decode last, and only when every other section decoded and every Draco stream's
// checksum matched (checked in this process, before any fork), in up to `threads` child processes
// with a budget (format/isolated_jobs.h) that write into shared memory, copied into place:
// Draco's work on a forged stream is not bounded otherwise. That costs a fork per child: killeroo
// compiled with --draco-bits 14 loads in 38 ms instead of 28 ms in a new process.
//
// Ownership: the reader owns the mapping and the open file (or, for open_memory, borrows the
// caller's bytes) and the decoded buffer; every pointer it hands out lives until the reader is
// destroyed or moved from.
// Thread safety: open and load_sections run once, from one thread; afterwards every const member
// may be called concurrently from any number of threads.
//
// Failure: the file is untrusted. No number read from it is used before it is checked (all size
// arithmetic is overflow-checked in uint64), and no allocation exceeds the bounds below, so a
// damaged or hostile file fails with a message instead of crashing, hanging or exhausting memory.
// Every member returning bool returns false with one message in *error, which starts with the
// path: "<path>: <reason>" for the header and table, "<path>: section '<name>' (#<index>):
// <reason>" for one section. The exception is a file truncated by another process while mapped:
// touching the lost pages raises SIGBUS, as with any memory-mapped reader (pbrtc never does that:
// it writes a new file and renames it over the old). A file that shrank between open and
// load_sections is an error (its size is checked again when the load starts, before anything
// reads a section); one read whole (64 KiB or less) is a copy, which nothing outside can change.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "format/archive.h"

namespace pbrta {

// Bounds on a section's decoded size, shared with the writer so that everything it writes can
// be read. A compressed section may claim at most kMaxZstdRatio times its stored size plus
// kZstdRatioSlack (a zip-bomb guard: the buffer is allocated before decoding), and all sections
// together at most kMaxZstdRatio times the file size plus kTotalRatioSlack (so a file of many tiny
// sections cannot multiply the per-section slack). The ratio is the most the zstd format itself
// can express (a 4-byte RLE block stands for 128 KiB), so nothing zstd produces is refused: a
// flat texture's MIP pyramid really does compress that far. Draco (kDraco) sections have the
// same bound; the Draco decoder is further limited by the vertex and triangle counts raw_size
// can hold (format/draco_codec.h). Large buffers are mapped lazily, so a lying size costs
// address space, not memory.
inline constexpr uint64_t kMaxRawSize = uint64_t{1} << 40;
inline constexpr uint64_t kMaxZstdRatio = 32768;
inline constexpr uint64_t kZstdRatioSlack = uint64_t{1} << 20;
inline constexpr uint64_t kTotalRatioSlack = uint64_t{64} << 20;

// True when a section of this codec with these stored and raw sizes is within the bounds above
// (for kRaw: raw == stored). Codecs outside the enum are not plausible.
bool section_sizes_plausible(Codec codec, uint64_t stored_size, uint64_t raw_size);

// The most decoded bytes, over all sections, an archive of file_size bytes may hold.
uint64_t max_total_raw_size(uint64_t file_size);

namespace archive_detail {
// Size arithmetic on numbers read from the file: true when a + b (a * b) does not fit in uint64.
inline bool add_overflows(uint64_t a, uint64_t b, uint64_t* sum) {
  return __builtin_add_overflow(a, b, sum);
}
inline bool mul_overflows(uint64_t a, uint64_t b, uint64_t* product) {
  return __builtin_mul_overflow(a, b, product);
}
// Frees a decode buffer: munmap for the large ones (mapped_size > 0), aligned delete else.
struct BufferFree {
  uint64_t mapped_size = 0;
  void operator()(uint8_t* p) const;
};
using Buffer = std::unique_ptr<uint8_t[], BufferFree>;
// Uninitialized memory, 64-byte aligned; from 256 KiB on a mapping of its own with transparent
// huge pages asked for (format/huge_pages.h): a load writes every byte of it, and faulting it in
// 4 KiB at a time costs more than decompressing. Empty when out of memory. With heap_only, always
// from the heap (only the pages touched are in memory).
Buffer allocate(uint64_t bytes, bool heap_only = false);
// Gives a mapped buffer's pages past its first bytes back when they are 1 MiB or more (a heap
// one is left as it is): a huge page a load only partly filled would otherwise stay whole in
// memory while the program runs.
void shrink(Buffer* b, uint64_t bytes);
}  // namespace archive_detail

class ArchiveReader {
 public:
  ArchiveReader();
  ~ArchiveReader();
  ArchiveReader(const ArchiveReader&) = delete;
  ArchiveReader& operator=(const ArchiveReader&) = delete;

  // Maps the file at path and validates the container (see validate order in the .cpp). On
  // failure the reader is left empty.
  [[nodiscard]] bool open(const std::string& path, std::string* error);

  // Same, on an archive image in memory, named `name` in messages (for tests and fuzzers). The
  // bytes are used in place when 16-byte aligned (copied otherwise) and must then outlive the
  // reader.
  [[nodiscard]] bool open_memory(std::string_view bytes, std::string_view name, std::string* error);

  // Verifies every section's checksum and decodes it, with up to `threads` threads (<= 0: all
  // cores). Sections of kinds this reader does not know (allowed in a newer minor version) are
  // skipped. On failure the message is that of the lowest-numbered failing section among those
  // that failed first, in this order: the other sections, the Draco checksums, Draco decoding
  // (later steps do not run once one fails). With `wanted` (one flag per section), only the wanted
  // sections not loaded yet: a caller may load in steps, and leave sections it will not read
  // undecoded.
  [[nodiscard]] bool load_sections(int threads, std::string* error,
                                   const std::vector<bool>& wanted = {});

  // The archive as opened. header() and the entries are copies of the validated file structures.
  const Header& header() const { return header_; }
  const std::string& path() const { return path_; }
  uint64_t file_size() const { return size_; }
  uint32_t section_count() const { return static_cast<uint32_t>(entries_.size()); }
  const SectionEntry& entry(uint32_t index) const { return entries_[index]; }

  // The index of the first section of this kind, or -1.
  int find_section(SectionKind kind) const;

  // True for a section of a kind unknown to this reader (only possible in a newer minor version).
  bool skipped(uint32_t index) const { return sections_[index].skipped; }

  // After load_sections: the decoded bytes (16-byte aligned, followed by 16 readable bytes) and
  // their count (the entry's raw_size). nullptr for a skipped section or before loading.
  const uint8_t* section_data(uint32_t index) const { return sections_[index].data; }
  uint64_t section_size(uint32_t index) const { return entries_[index].raw_size; }

  // True when section_data points into the mapped file (raw sections), not into a copy.
  bool in_place(uint32_t index) const { return sections_[index].in_place; }
  // After load_sections, for a Draco section: the vertex and triangle counts its stream
  // decoded to (ARCHIVE.md: the mesh record must carry them); 0 and 0 for any other section.
  uint32_t decoded_vertices(uint32_t index) const { return sections_[index].decoded_counts[0]; }
  uint32_t decoded_triangles(uint32_t index) const { return sections_[index].decoded_counts[1]; }

  // The section as an array of entry(section).count elements of T: checks that the section
  // exists and is loaded, that raw_size == count * sizeof(T) and that the data is aligned for T.
  template <class T>
  [[nodiscard]] bool typed_array(uint32_t section, const T** out, uint32_t* count,
                                 std::string* error) const {
    static_assert(std::is_trivially_copyable_v<T>, "archive records are plain data");
    const void* data = nullptr;
    if (!typed_array_bytes(section, sizeof(T), alignof(T), &data, count, error)) return false;
    *out = static_cast<const T*>(data);
    return true;
  }

  // "<path>: section '<name>' (#<index>): <reason>", for callers that validate contents.
  std::string section_error(uint32_t index, std::string_view reason) const;

 private:
  using Buffer = archive_detail::Buffer;
  struct Section {
    const uint8_t* data = nullptr;
    bool in_place = false;
    bool skipped = false;
    uint32_t decoded_counts[2] = {0, 0};  // a Draco section's decoded vertices and triangles
  };

  struct Task;
  bool validate(std::string* error);
  // validate(), and on failure reset() with the path kept for messages.
  bool validate_or_reset(std::string* error);
  // A zstd section's frame index, read and checked against the section's checksum, appended to
  // tasks; or the reason it is refused.
  bool plan_frames(uint32_t index, std::vector<Task>* tasks, std::string* reason) const;
  // One task (a raw chunk or a zstd frame) of load_sections; false with the reason.
  bool run_task(const Task& t, uint8_t* out, uint64_t* chunk_sum, std::string* reason) const;
  // The Draco sections, once everything else has loaded: checksums here, decoding isolated.
  bool load_draco(const std::vector<uint32_t>& draco, const std::vector<uint8_t*>& out, int threads,
                  std::vector<std::string>* errors);
  // False, naming the first section cut, when a mapped file is now shorter than when it was
  // opened: it is checked once at the start of each load, before anything reads the mapping.
  bool unchanged_size(std::string* error) const;
  bool typed_array_bytes(uint32_t section, size_t elem_size, size_t elem_align, const void** out,
                         uint32_t* count, std::string* error) const;
  std::string fail(std::string_view reason) const;
  void reset();

  std::string path_;
  int fd_ = -1;          // the open file while mapped, or -1 (read whole, or open_memory)
  void* map_ = nullptr;  // the mmap'ed file, or nullptr
  size_t map_size_ = 0;
  Buffer copy_;  // a file read whole (up to 64 KiB, kept for the reader's life), or unaligned
                 // open_memory bytes
  // The decoded (not in-place) sections, each at its own 64-byte aligned offset in the buffer
  // of the load_sections call that decoded it.
  std::vector<Buffer> decoded_;
  const uint8_t* base_ = nullptr;
  uint64_t size_ = 0;
  Header header_{};
  std::vector<SectionEntry> entries_;
  std::vector<Section> sections_;
};

}  // namespace pbrta
