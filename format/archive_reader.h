// format/archive_reader.h — opens a scene archive (.pbrta) and decodes its sections.
//
// The generic container layer of the archive (format/archive.h describes the layout): the reader
// maps the file read-only (reads it whole when it is 64 KiB or less), validates the header, the
// section table and the layout of every section, then load_sections() verifies each section's
// checksum and decodes it, in parallel over sections. Uncompressed (kNone, kNoneChunked) sections
// are used in place from the mapping (or the copy), 16-byte aligned and followed by 16 bytes of
// padding, a kNoneChunked one checksummed 1 MiB chunk by chunk on every thread;
// compressed ones are decoded into one owned buffer, each at a 64-byte aligned offset with 16 zero
// bytes after its data. What the sections mean is the caller's business. Opening and the table
// checks are in archive_reader.cpp, the decoding in section_loading.cpp (threads' buffers:
// thread_decoder.h).
//
// Speed (issue 4's load target): fresh memory is the dominant cost after decompression itself,
// and 4 KiB page faults are very slow under virtualization, so everything large the load writes
// (the decoded sections, zstd's contexts and window buffers, the unshuffle scratch) lives in
// mappings with transparent huge pages requested, and the decoded sections of one call share one
// mapping so small ones do not each round up to a page. Codec-4 sections are loaded frame by
// frame on every thread: each frame is read, verified, decoded one-shot into a scratch block and
// unshuffled from there straight into its place, so the decoded bytes are written to memory once
// and every other step works on cached data; the caller's uint32 bounds (triangle indices) are
// checked in the same pass. Legacy codec-2 sections stream one shuffle block at a time through
// the scratch block the same way, one section per thread. Each loading thread keeps its zstd
// context and scratch block for the next load, by any reader, as long as all threads' kept
// buffers stay within 32 MiB: mapping and zeroing them anew was half of a repeated 1 MB load (a
// process's first load pays for them once).
// Draco (codec-3) sections decode last, and only when every other section decoded and every
// Draco stream's checksum matched (checked in this process, before any fork), in up to `threads`
// child processes with a budget (format/isolated_jobs.h) that write into shared memory, copied
// into place: Draco's work on a forged stream is not bounded otherwise. That costs a fork per
// child: killeroo compiled with --draco-bits 14 loads in 38 ms instead of 28 ms in a new process
// (archive_bench --once load, best of 10).
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
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "format/archive.h"
#include "format/byte_shuffle.h"

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
// (for kNone and kNoneChunked: raw == stored). Codecs outside the enum are not plausible.
bool section_sizes_plausible(Codec codec, uint64_t stored_size, uint64_t raw_size);

// The most decoded bytes, over all sections, an archive of file_size bytes may hold.
uint64_t max_total_raw_size(uint64_t file_size);

// The index of the first of n values that is >= limit, or n: the check of a U32Bound (below),
// vectorized.
uint64_t first_at_or_above(const uint32_t* v, uint64_t n, uint32_t limit);

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
struct Decoder;     // one loading thread's zstd context and buffers (format/thread_decoder.h)
class FramePieces;  // one loading thread's frame in progress (format/frame_pieces.h)
}  // namespace archive_detail

class ArchiveReader {
 public:
  ArchiveReader();
  ~ArchiveReader();
  ArchiveReader(ArchiveReader&& other) noexcept;
  ArchiveReader& operator=(ArchiveReader&& other) noexcept;
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
  // (later steps do not run once one fails).
  [[nodiscard]] bool load_sections(int threads, std::string* error);

  // A check made while a section decodes, block by block while the data is in cache: every
  // uint32 in bytes [begin, end) of the section's decoded data is below limit (a mesh's triangle
  // indices against its vertex count). begin and end are multiples of 4 within the raw size.
  struct U32Bound {
    uint32_t section;
    uint64_t begin, end;
    uint32_t limit;
  };
  // Loads the sections listed in `which` that are not loaded yet (skipped kinds are left out),
  // as above, and checks the bounds, which must lie in those sections. On success,
  // (*first_out)[b] is the byte offset in its section of bounds[b]'s first value >= limit, or
  // bounds[b].end when there is none: which one is an error is the caller's business. On failure
  // the sections of this call are left unloaded; earlier calls' stay loaded.
  [[nodiscard]] bool load_sections(int threads, const std::vector<uint32_t>& which,
                                   const std::vector<U32Bound>& bounds,
                                   std::vector<uint64_t>* first_out, std::string* error);

  // Bounds that are known only once other sections are loaded (a mesh's triangle indices lie
  // where its record, in the mesh records, says). Once every section of `first` has loaded (or
  // failed), plan() is called once, on one of the loading threads, and returns the bounds, which
  // must stay valid until load_sections returns and must lie in `gated` sections; no gated
  // section starts before then. Every other section loads whenever a thread is free, so the plan
  // is no barrier: a separate pass for 100k shapes' mesh records kept one thread idle for 1 ms.
  //
  // Work that reads only some sections can run while the others load: once every section of
  // `needs` has loaded, when_loaded(bytes) is called once, on the loading thread that finished
  // the last of them (before any loading when none is loaded here), with the decoded size of the
  // tasks no thread has started yet: what there is to overlap with. It is not called when one of
  // them failed, and nothing waits for it but the end of load_sections. With needs_first, those
  // sections are taken right after `first`'s, so that the work starts early; otherwise in the
  // usual largest-first order. None may be a Draco section. (The scene's record checks run there
  // while 100k shapes' 26 MB of transforms decode.)
  struct BoundPlan {
    std::vector<uint32_t> first;
    std::vector<uint32_t> gated;
    std::function<const std::vector<U32Bound>&()> plan;
    std::vector<uint32_t> needs;
    std::function<void(uint64_t bytes_not_started)> when_loaded;
    bool needs_first = false;
  };
  // Loads `which` as above, with bounds from plan; first_out as above, one per planned bound.
  [[nodiscard]] bool load_sections(int threads, const std::vector<uint32_t>& which,
                                   const BoundPlan& plan, std::vector<uint64_t>* first_out,
                                   std::string* error);

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

  // True when section_data points into the mapped file (kNone and kNoneChunked sections), not
  // into a copy.
  bool in_place(uint32_t index) const { return sections_[index].in_place; }
  // After load_sections, for a Draco (codec 3) section: the vertex and triangle counts its stream
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
  using Buffer = std::unique_ptr<uint8_t[], archive_detail::BufferFree>;
  static Buffer allocate(uint64_t bytes);
  struct Section {
    const uint8_t* data = nullptr;
    bool in_place = false;
    bool skipped = false;
    uint32_t decoded_counts[2] = {0, 0};  // a Draco section's decoded vertices and triangles
  };

  static constexpr uint32_t kWholeSection = 0xFFFFFFFFu;
  struct LoadTask;
  struct FrameWork;
  bool validate(std::string* error);
  // validate(), and on failure reset() with the path kept for messages.
  bool validate_or_reset(std::string* error);
  // Checks and decodes section index into out (raw_size bytes plus zeroed padding, unless in
  // place). On failure *reason says why, without the file and section: the caller names them
  // (a Draco section's reason comes back from a child process, which cannot).
  bool load_one(uint32_t index, uint8_t* out, archive_detail::Decoder* decoder,
                std::string* reason);
  // Reads, verifies and decodes one frame of a codec-4 or 6 section into the decoder's scratch
  // block (work->scratch), with slot open for it (work) meanwhile, so that other threads may
  // unshuffle its pieces as they decode; the caller unshuffles those left. On failure the slot is
  // closed.
  bool load_frame(const LoadTask& task, archive_detail::Decoder* decoder,
                  archive_detail::FramePieces* slot, FrameWork* work, std::string* error);
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
  // The decoded (not in-place) sections, one buffer per load_sections call, each section at its
  // own 64-byte aligned offset.
  std::vector<Buffer> decoded_;
  const uint8_t* base_ = nullptr;
  uint64_t size_ = 0;
  Header header_{};
  std::vector<SectionEntry> entries_;
  std::vector<Section> sections_;
};

}  // namespace pbrta
