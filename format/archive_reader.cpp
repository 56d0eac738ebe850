#include "format/archive_reader.h"

#include "format/archive_writer.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <new>
#include <optional>
#include <system_error>
#include <thread>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
// For ZSTD_customMem and ZSTD_createDCtx_advanced: exported by the shared library since 1.3.
#define ZSTD_STATIC_LINKING_ONLY
#include <zstd.h>

#include "format/archive_names.h"
#include "format/byte_shuffle.h"
#include "format/checksum.h"
#include "format/draco_codec.h"
#include "format/isolated_jobs.h"
#include "format/zstd_frames.h"

namespace pbrta {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "the archive is little-endian and its structures are read directly");

namespace {

constexpr size_t kBufferAlignment = 64;  // a cache line; more than the 16 the format promises
constexpr uint64_t kHugePageSize = uint64_t{2} << 20;
// From this size on a buffer gets its own huge-page mapping. Faulting in 256 KiB 4 KiB at a time
// costs more than zeroing one 2 MiB page (measured: ~12 us per 4 KiB fault in this VM, ~0.1 ms per
// 2 MiB page), and there are few such buffers per load (one for all decoded sections, a few per
// thread for zstd), so the rounding wastes little.
constexpr uint64_t kHugeBufferThreshold = uint64_t{256} << 10;
// Compressed sections from this size on are read with pread (see load_one); smaller ones, the
// records, are decoded from the mapping, whose pages around them validate() has mostly touched.
constexpr uint64_t kReadThreshold = uint64_t{64} << 10;
// Uncompressed sections from this size on have their pages mapped in one madvise call before
// they are read (MADV_POPULATE_READ, Linux 5.14; older kernels refuse it and fault as before).
// Small: teapot's 13 sections of 0.9 MB, most under 256 KiB, loaded in 0.31-0.33 ms against
// 0.38-0.39 ms with only the 256 KiB ones mapped ahead.
constexpr uint64_t kPopulateThreshold = uint64_t{16} << 10;
#ifdef MADV_POPULATE_READ
constexpr int kMadvPopulateRead = MADV_POPULATE_READ;
#else
constexpr int kMadvPopulateRead = 22;
#endif
// Files up to this size are read whole into memory when opened instead of mapped.
constexpr uint64_t kSmallFileSize = uint64_t{64} << 10;
// A file whose bytes are mostly uncompressed sections is read whole too, into huge pages, up to
// this size; above it, its whole mapping is populated before anything reads through it. In this
// VM the first read of each 4 KiB page of a mapping costs ~0.6 us even once MADV_POPULATE_READ
// has mapped it, while a fresh 2 MiB page is one fault; whether the kernel maps a file's page
// cache 2 MiB at a time varies from run to run (and never happens where the header was read
// through the mapping first), so mapped loads are bimodal and read ones steady. Uncompressed,
// 2 threads, best of 30 loads in each of 6 processes, mapped -> read: killeroo-simple (1.9 MB)
// 0.20-0.46 -> 0.19-0.21 ms, caustic glass (2.1 MB) 0.21-0.59 -> 0.30-0.32 ms, 2d-mappings
// (4.2 MB) 0.30-0.96 -> 0.36-0.40 ms, a generated 5.7 MB mesh file 0.82-0.89 -> 0.72-0.78 ms.
// Larger files lose by the copy as often as they win (projection's 16 MB: 1.2 -> 2.0 ms).
constexpr uint64_t kReadWholeSize = uint64_t{8} << 20;
// Codec-4 sections from this size on are unshuffled with non-temporal stores (unshuffle4_block):
// far larger than the cache, so ordinary stores would read in every line only to overwrite it
// and see it evicted before the renderer reads it. mesh200 (109 MB, 2 threads, paired best of
// 15): 16.8-18.8 -> 15.6-16.6 ms; f10-1ac (40 MB): 8.5-8.9 -> 7.8-8.5 ms.
constexpr uint64_t kStreamSectionSize = uint64_t{8} << 20;
// Loads that read and write fewer bytes than this (stored plus decoded) run on the calling
// thread. Both count: a flat texture's pyramid stores 0.5% of the 18 MB it decodes to, and
// writing those fresh pages is most of its load (f3-18: 5.1 ms on one thread, 3.6 on two).
constexpr uint64_t kSerialLoadBytes = uint64_t{1} << 20;
// An uncompressed section is only checksummed in place, which costs far less a byte than
// decoding: its bytes count 1/kChecksumOnlyWeight as much. The --codec none archives of teapot,
// caustic glass, killeroo and 2d-mappings (0.9-4.2 MB) loaded no faster on two threads than on
// one in a process that loads repeatedly, and in a new process, where the second thread meant
// starting oneTBB's workers, took 1.1-1.6 ms against 0.45-0.9 ms on one; mesh200's 109 MB (8
// geometry sections) loads in 8.1 ms on two, 10.7 on one.
constexpr uint64_t kChecksumOnlyWeight = 8;

bool add_overflows(uint64_t a, uint64_t b, uint64_t* sum) {
  return __builtin_add_overflow(a, b, sum);
}
bool mul_overflows(uint64_t a, uint64_t b, uint64_t* p) {
  return __builtin_mul_overflow(a, b, p);
}

std::string errno_text(int err) {
  return std::error_code(err, std::generic_category()).message();
}

// pread of exactly size bytes at offset, or false with the reason.
bool read_fully(int fd, uint64_t offset, uint64_t size, uint8_t* dst, std::string* why) {
  for (uint64_t got = 0; got < size;) {
    const ssize_t r = ::pread(fd, dst + got, size - got, static_cast<off_t>(offset + got));
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) {
      *why = "cannot read: " + errno_text(errno);
      return false;
    }
    if (r == 0) {
      *why = "truncated while loading: the file shrank after it was opened";
      return false;
    }
    got += static_cast<uint64_t>(r);
  }
  return true;
}

// Whether at least half of a file's bytes are in uncompressed sections, judged from one read of
// its first 4 KiB (the header and a table of up to 84 sections; a longer table counts as
// compressed, so the file is mapped as before). Only a choice between reading and mapping rests
// on these unchecked bytes; validate() checks whichever copy is used.
bool mostly_uncompressed(int fd, uint64_t size) {
  alignas(8) uint8_t probe[4096];
  const ssize_t got = ::pread(fd, probe, sizeof probe, 0);
  if (got < static_cast<ssize_t>(sizeof(Header))) return false;
  Header h;
  std::memcpy(&h, probe, sizeof h);
  if (h.table_offset != sizeof(Header) ||
      h.section_count > (static_cast<uint64_t>(got) - sizeof h) / sizeof(SectionEntry))
    return false;
  uint64_t uncompressed = 0;
  for (uint32_t i = 0; i < h.section_count; ++i) {
    SectionEntry e;
    std::memcpy(&e, probe + sizeof h + uint64_t{i} * sizeof e, sizeof e);
    if (e.codec == static_cast<uint32_t>(Codec::kNone))
      uncompressed += std::min(e.stored_size, size);
  }
  return uncompressed >= size / 2;
}

std::string section_label(uint32_t kind) {
  if (kind > 0 && kind < static_cast<uint32_t>(SectionKind::kCount))
    return std::string(section_kind_name(static_cast<SectionKind>(kind)));
  return "kind " + std::to_string(kind);
}

// First nonzero byte in [begin, end) of base, or end.
uint64_t first_nonzero(const uint8_t* base, uint64_t begin, uint64_t end) {
  for (uint64_t i = begin; i < end; ++i)
    if (base[i] != 0) return i;
  return end;
}

uint64_t align_up(uint64_t x, uint64_t a) {
  return (x + a - 1) / a * a;
}

// Fresh zeroed memory in its own mapping, huge pages requested; nullptr when out of memory.
uint8_t* map_fresh(uint64_t bytes, uint64_t* mapped) {
  *mapped = align_up(bytes, kHugePageSize);
  void* p = mmap(nullptr, *mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) return nullptr;
  madvise(p, *mapped, MADV_HUGEPAGE);  // a hint; harmless where unsupported
  return static_cast<uint8_t*>(p);
}

// zstd's allocator: its context and streaming window buffer are large and written at once, so
// they get huge pages like the decode buffers. A header before each block records how to free it.
constexpr size_t kZstdAllocHeader = 64;
void* zstd_alloc(void*, size_t size) {
  uint64_t mapped = 0;
  uint8_t* base = nullptr;
  if (size + kZstdAllocHeader >= kHugeBufferThreshold) {
    base = map_fresh(size + kZstdAllocHeader, &mapped);
  } else {
    base = static_cast<uint8_t*>(std::malloc(size + kZstdAllocHeader));
  }
  if (base == nullptr) return nullptr;
  std::memcpy(base, &mapped, sizeof mapped);
  return base + kZstdAllocHeader;
}
void zstd_free(void*, void* address) {
  if (address == nullptr) return;
  uint8_t* base = static_cast<uint8_t*>(address) - kZstdAllocHeader;
  uint64_t mapped = 0;
  std::memcpy(&mapped, base, sizeof mapped);
  if (mapped > 0)
    munmap(base, mapped);
  else
    std::free(base);
}

}  // namespace

// Bytes of huge-page buffers (scratch and staging) that loading threads keep between loads, in
// all: each thread keeps its buffers for the next load while the total stays within this.
constexpr uint64_t kKeptBufferBudget = uint64_t{32} << 20;
std::atomic<uint64_t> kept_buffer_bytes{0};

// One loading thread's state, kept across load_sections calls and across loads (and readers) for
// the life of the thread: the decompression context (reused across sections, so a streaming
// window buffer is allocated once), the block that shuffled data is decoded into before it is
// unshuffled into place, and the buffer stored bytes are read into. Each is made on first need: a
// thread that only decodes small record sections never maps a scratch block. Keeping the buffers
// matters in a VM: mapping, zeroing and unmapping fresh huge pages for them was half of a
// 0.75 ms load of killeroo-simple, repeated.
struct archive_detail::Decoder {
  ZSTD_DCtx* dctx = nullptr;
  bool tried = false;
  uint8_t* scratch = nullptr;
  uint64_t scratch_size = 0;
  uint64_t scratch_mapped = 0;  // 0: scratch is on the heap
  uint8_t* staging = nullptr;
  uint64_t staging_mapped = 0;
  std::vector<WordBound> bounds;  // the current frame's bounds (load_sections' run)
  std::vector<uint32_t> bound_ids;

  Decoder() = default;
  Decoder(const Decoder&) = delete;
  Decoder& operator=(const Decoder&) = delete;
  ~Decoder() {
    ZSTD_freeDCtx(dctx);
    free_scratch();
    free_staging();
  }
  // After a load: frees the buffers unless they fit the process's budget for kept buffers, and
  // the context if a streamed (codec 2) section grew its window buffer past 1 MiB.
  void trim() {
    if (kept_buffer_bytes.load() > kKeptBufferBudget) {
      free_scratch();
      free_staging();
    }
    if (dctx != nullptr && ZSTD_sizeof_DCtx(dctx) > (size_t{1} << 20)) {
      ZSTD_freeDCtx(dctx);
      dctx = nullptr;
      tried = false;
    }
  }
  // A staging buffer of at least bytes, or nullptr when out of memory.
  uint8_t* stage(uint64_t bytes) {
    if (bytes > staging_mapped) {
      free_staging();
      staging = map_fresh(bytes, &staging_mapped);
      if (staging == nullptr) staging_mapped = 0;
      kept_buffer_bytes += staging_mapped;
    }
    return staging;
  }
  // The context, or nullptr when out of memory.
  ZSTD_DCtx* context() {
    if (!tried) {
      tried = true;
      dctx = ZSTD_createDCtx_advanced(ZSTD_customMem{zstd_alloc, zstd_free, nullptr});
      // Streaming, unlike one-shot decoding, refuses windows over 2^27 by default; every frame
      // one-shot decoding accepts must still load. zstd sizes its buffer by the smaller of the
      // window and the content size, which validate() bounded.
      if (dctx != nullptr) ZSTD_DCtx_setParameter(dctx, ZSTD_d_windowLogMax, ZSTD_WINDOWLOG_MAX);
    }
    return dctx;
  }
  // A scratch block of at least bytes to decode shuffled data into (codec 2: kShuffleBlock, codec
  // 4: its frame's block), or nullptr when out of memory. Sized by need: a small frame (a records
  // section) takes a heap block, not fresh huge pages; a full frame takes exactly two huge pages.
  uint8_t* block(uint64_t bytes) {
    if (bytes > scratch_size) {
      free_scratch();
      if (bytes >= kHugeBufferThreshold) {
        scratch = map_fresh(bytes, &scratch_mapped);
        if (scratch == nullptr) scratch_mapped = 0;
        kept_buffer_bytes += scratch_mapped;
      } else {
        scratch = static_cast<uint8_t*>(std::malloc(bytes));
        scratch_mapped = 0;
      }
      scratch_size = scratch != nullptr ? bytes : 0;
    }
    return scratch;
  }

 private:
  void free_scratch() {
    if (scratch_mapped > 0)
      munmap(scratch, scratch_mapped);
    else
      std::free(scratch);
    kept_buffer_bytes -= scratch_mapped;
    scratch = nullptr;
    scratch_size = scratch_mapped = 0;
  }
  void free_staging() {
    if (staging != nullptr) munmap(staging, staging_mapped);
    kept_buffer_bytes -= staging_mapped;
    staging = nullptr;
    staging_mapped = 0;
  }
};

bool section_sizes_plausible(Codec codec, uint64_t stored_size, uint64_t raw_size) {
  if (raw_size > kMaxRawSize) return false;
  switch (codec) {
    case Codec::kNone:
      return raw_size == stored_size;
    case Codec::kZstd:
    case Codec::kZstdShuffle4:
    case Codec::kDraco:
    case Codec::kZstdShuffle4Frames: {
      uint64_t limit = 0;
      if (mul_overflows(stored_size, kMaxZstdRatio, &limit) ||
          add_overflows(limit, kZstdRatioSlack, &limit))
        return true;  // the limit exceeds any uint64, so raw_size is below it
      return raw_size <= limit;
    }
    case Codec::kCount:
      break;
  }
  return false;
}

uint64_t max_total_raw_size(uint64_t file_size) {
  uint64_t limit = 0;
  if (mul_overflows(file_size, kMaxZstdRatio, &limit) ||
      add_overflows(limit, kTotalRatioSlack, &limit))
    return UINT64_MAX;
  return limit;
}

namespace {
// This thread's decoder, made on first need and freed when the thread ends; the loading tasks of
// every reader that run on this thread share it (a thread runs one load task at a time). Owned
// through the thread's own storage, where leak checkers see it.
archive_detail::Decoder& thread_decoder() {
  thread_local std::unique_ptr<archive_detail::Decoder> decoder;
  if (!decoder) decoder = std::make_unique<archive_detail::Decoder>();
  return *decoder;
}
}  // namespace

void archive_detail::BufferFree::operator()(uint8_t* p) const {
  if (mapped_size > 0)
    munmap(p, mapped_size);
  else
    ::operator delete[](p, std::align_val_t(kBufferAlignment));
}

// Large buffers are mapped with transparent huge pages requested: decoding writes every byte of
// fresh memory, and faulting it in 4 KiB at a time costs more than decompressing (measured 10x
// slower in a VM). Returns an empty buffer when out of memory.
ArchiveReader::Buffer ArchiveReader::allocate(uint64_t bytes) {
  if (bytes >= kHugeBufferThreshold) {
    uint64_t mapped = 0;
    uint8_t* p = map_fresh(bytes, &mapped);
    return Buffer(p, archive_detail::BufferFree{p != nullptr ? mapped : 0});
  }
  return Buffer(
      static_cast<uint8_t*>(::operator new[](std::max<uint64_t>(bytes, 1),
                                             std::align_val_t(kBufferAlignment), std::nothrow)),
      archive_detail::BufferFree{0});
}

ArchiveReader::ArchiveReader() = default;

ArchiveReader::~ArchiveReader() {
  reset();
}

ArchiveReader::ArchiveReader(ArchiveReader&& other) noexcept {
  *this = std::move(other);
}

ArchiveReader& ArchiveReader::operator=(ArchiveReader&& other) noexcept {
  if (this == &other) return *this;
  reset();
  path_ = std::move(other.path_);
  fd_ = other.fd_;
  other.fd_ = -1;
  map_ = other.map_;
  map_size_ = other.map_size_;
  copy_ = std::move(other.copy_);
  decoded_ = std::move(other.decoded_);
  base_ = other.base_;
  size_ = other.size_;
  header_ = other.header_;
  entries_ = std::move(other.entries_);
  sections_ = std::move(other.sections_);
  other.map_ = nullptr;
  other.map_size_ = 0;
  other.reset();
  return *this;
}

void ArchiveReader::reset() {
  sections_.clear();
  entries_.clear();
  decoded_.clear();
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  if (map_ != nullptr) munmap(map_, map_size_);
  map_ = nullptr;
  map_size_ = 0;
  copy_.reset();
  base_ = nullptr;
  size_ = 0;
  header_ = Header{};
}

std::string ArchiveReader::fail(std::string_view reason) const {
  std::string s = path_;
  s += ": ";
  s += reason;
  return s;
}

std::string ArchiveReader::section_error(uint32_t index, std::string_view reason) const {
  std::string s = path_;
  s += ": section '";
  s += index < entries_.size() ? section_label(entries_[index].kind) : std::string("?");
  s += "' (#" + std::to_string(index) + "): ";
  s += reason;
  return s;
}

bool ArchiveReader::open(const std::string& path, std::string* error) {
  reset();
  path_ = path;
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    *error = fail("cannot open: " + errno_text(errno));
    return false;
  }
  struct stat st;
  if (fstat(fd, &st) != 0) {
    *error = fail("cannot stat: " + errno_text(errno));
    ::close(fd);
    return false;
  }
  if (!S_ISREG(st.st_mode)) {
    *error = fail("not a regular file");
    ::close(fd);
    return false;
  }
  const uint64_t size = static_cast<uint64_t>(st.st_size);
  if (size < sizeof(Header)) {
    // Checked before mmap, which refuses a zero length.
    ::close(fd);
    *error = fail("truncated: the file has " + std::to_string(size) +
                  " bytes, less than the 64-byte header");
    return false;
  }
  const bool uncompressed = size > kSmallFileSize && mostly_uncompressed(fd, size);
  if (size <= kSmallFileSize || (uncompressed && size <= kReadWholeSize)) {
    // Read whole, not mapped, and its sections used in place from this copy. Small files: one
    // read instead of a page fault for the first page (~8 us here) and one read per padding gap
    // (~1.2 us each); a 2 KB archive opened in 31 us that way.
    copy_ = allocate(size);
    std::string why;
    const bool read = copy_ ? read_fully(fd, 0, size, copy_.get(), &why)
                            : (why = "cannot allocate " + std::to_string(size) + " bytes", false);
    ::close(fd);
    if (!read) {
      *error = fail(why);
      copy_.reset();
      return false;
    }
    base_ = copy_.get();
  } else {
    void* map = mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0);
    const int map_errno = errno;
    if (map == MAP_FAILED) {
      ::close(fd);
      *error = fail("cannot map: " + errno_text(map_errno));
      return false;
    }
    // Populated whole, here on one thread: measured no slower than per section in the load for
    // 11-109 MB files (shapes100k's 55 MB: 9.1-9.6 ms either way). A file that shrank since
    // fstat usually fails here rather than with SIGBUS in validate().
    if (uncompressed && madvise(map, size, kMadvPopulateRead) != 0 && errno == EFAULT) {
      munmap(map, size);
      ::close(fd);
      *error = fail("truncated while loading: the file shrank after it was opened");
      return false;
    }
    fd_ = fd;  // kept for load_sections' reads of compressed sections
    map_ = map;
    map_size_ = size;
    base_ = static_cast<const uint8_t*>(map);
  }
  size_ = size;
  return validate_or_reset(error);
}

bool ArchiveReader::validate_or_reset(std::string* error) {
  if (validate(error)) return true;
  const std::string name = path_;
  reset();
  path_ = name;
  return false;
}

bool ArchiveReader::open_memory(std::string_view bytes, std::string_view name, std::string* error) {
  reset();
  path_ = std::string(name);
  if (reinterpret_cast<uintptr_t>(bytes.data()) % kSectionAlignment == 0) {
    base_ = reinterpret_cast<const uint8_t*>(bytes.data());
  } else {
    // Sections are promised 16-byte alignment: a misaligned image is copied.
    copy_ = allocate(bytes.size());
    if (!copy_) {
      *error = fail("cannot allocate " + std::to_string(bytes.size()) + " bytes");
      return false;
    }
    if (!bytes.empty()) std::memcpy(copy_.get(), bytes.data(), bytes.size());
    base_ = copy_.get();
  }
  size_ = bytes.size();
  return validate_or_reset(error);
}

// Checks, in this order: header size, magic, header checksum, version, reserved header fields,
// table offset, table bounds, table checksum, then each entry in table order (kind, codec,
// reserved, alignment, position after the table, bounds, decoded size), then overlaps, the
// recorded file size, the total decoded size and that all padding is zero. Every byte of a valid
// archive is thus covered by a checksum or must be zero.
bool ArchiveReader::validate(std::string* error) {
  if (size_ < sizeof(Header)) {
    *error = fail("truncated: the file has " + std::to_string(size_) +
                  " bytes, less than the 64-byte header");
    return false;
  }
  std::memcpy(&header_, base_, sizeof(Header));
  if (std::memcmp(header_.magic, kMagic, sizeof(kMagic)) != 0) {
    *error = fail("not a pbrt scene archive (bad magic)");
    return false;
  }
  if (checksum64(base_, offsetof(Header, header_checksum)) != header_.header_checksum) {
    *error = fail("header checksum mismatch");
    return false;
  }
  const std::string version = std::to_string(header_.major) + "." + std::to_string(header_.minor);
  const std::string supported = std::to_string(kMajorVersion) + ".x";
  if (header_.major > kMajorVersion) {
    *error = fail("archive version " + version + "; this reader supports " + supported +
                  " — update pbrtc/pbrtrun");
    return false;
  }
  if (header_.major < kMajorVersion) {
    *error = fail("archive version " + version + "; this reader supports " + supported +
                  " — recompile the scene with this pbrtc");
    return false;
  }
  if (header_.flags != 0 || header_.reserved0 != 0) {
    *error = fail("reserved header fields are not zero");
    return false;
  }
  if (header_.table_offset != sizeof(Header)) {
    *error =
        fail("section table offset is " + std::to_string(header_.table_offset) + "; expected 64");
    return false;
  }
  // section_count < 2^32, so this cannot overflow; checked anyway so the rule has no exceptions.
  uint64_t table_bytes = 0, table_end = 0;
  if (mul_overflows(header_.section_count, sizeof(SectionEntry), &table_bytes) ||
      add_overflows(sizeof(Header), table_bytes, &table_end) || table_end > size_) {
    *error = fail("truncated: the section table (" + std::to_string(header_.section_count) +
                  " sections) ends at byte " + std::to_string(table_end) + " but the file has " +
                  std::to_string(size_) + " bytes");
    return false;
  }
  if (checksum64(base_ + sizeof(Header), table_bytes) != header_.table_checksum) {
    *error = fail("section table checksum mismatch");
    return false;
  }
  const uint32_t n = header_.section_count;
  entries_.resize(n);
  if (n > 0) std::memcpy(entries_.data(), base_ + sizeof(Header), table_bytes);
  sections_.clear();
  sections_.resize(n);

  const bool newer_minor = header_.minor > kMinorVersion;
  uint64_t total_raw = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const SectionEntry& e = entries_[i];
    auto bad = [&](const std::string& reason) {
      *error = section_error(i, reason);
      return false;
    };
    if (e.kind == 0 || e.kind >= static_cast<uint32_t>(SectionKind::kCount)) {
      // A newer minor version may add kinds; their sections are laid out like any other and
      // checked below, but never decoded.
      if (!newer_minor)
        return bad("unknown section kind " + std::to_string(e.kind) + " in a version " + version +
                   " archive");
      sections_[i].skipped = true;
    }
    if (e.codec >= static_cast<uint32_t>(Codec::kCount))
      return bad("unknown codec " + std::to_string(e.codec));
    // A Draco stream is one mesh: the decoder lays it out as that mesh's geometry section.
    if (e.codec == static_cast<uint32_t>(Codec::kDraco) &&
        (e.kind != static_cast<uint32_t>(SectionKind::kGeometry) || e.count != 1))
      return bad("codec 'draco' is only for a geometry section of one mesh (this one is kind " +
                 std::to_string(e.kind) + " with count " + std::to_string(e.count) + ")");
    if (e.reserved != 0) return bad("reserved field is not zero");
    if (e.offset % kSectionAlignment != 0)
      return bad("offset " + std::to_string(e.offset) + " is not a multiple of 16");
    if (e.offset < table_end)
      return bad("offset " + std::to_string(e.offset) +
                 " lies inside the header or section table, which end at byte " +
                 std::to_string(table_end));
    uint64_t end = 0, padded_end = 0;
    if (add_overflows(e.offset, e.stored_size, &end) || end > size_)
      return bad("truncated: section ends at byte " +
                 (end >= e.offset ? std::to_string(end) : std::string("> 2^64")) +
                 " but the file has " + std::to_string(size_) + " bytes");
    if (add_overflows(end, kSectionPadding, &padded_end) || padded_end > size_)
      return bad("truncated: the padding after the section ends at byte " +
                 std::to_string(end + kSectionPadding) + " but the file has " +
                 std::to_string(size_) + " bytes");
    if (e.raw_size > kMaxRawSize)
      return bad("raw size " + std::to_string(e.raw_size) + " exceeds the limit of 2^40 bytes");
    const Codec codec = static_cast<Codec>(e.codec);
    if (codec == Codec::kNone && e.raw_size != e.stored_size)
      return bad("raw size " + std::to_string(e.raw_size) + " differs from stored size " +
                 std::to_string(e.stored_size) + " with codec 'none'");
    if (!section_sizes_plausible(codec, e.stored_size, e.raw_size))
      return bad("raw size " + std::to_string(e.raw_size) + " is implausible for " +
                 std::to_string(e.stored_size) + " bytes of " + std::string(codec_name(codec)) +
                 " (at most " + std::to_string(kMaxZstdRatio) + "x + 1 MiB)");
    if (codec == Codec::kZstdShuffle4Frames &&
        frame_count(e.raw_size) * sizeof(FrameEntry) > e.stored_size)  // raw_size <= 2^40
      return bad("the frame index of " + std::to_string(frame_count(e.raw_size)) +
                 " entries does not fit in " + std::to_string(e.stored_size) + " stored bytes");
    total_raw += e.raw_size;  // n < 2^32 sections of < 2^40 bytes: no overflow
  }

  // Sections in file order must not overlap each other or each other's padding.
  std::vector<uint32_t> order(n);
  for (uint32_t i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return entries_[a].offset != entries_[b].offset ? entries_[a].offset < entries_[b].offset
                                                    : a < b;
  });
  for (uint32_t k = 1; k < n; ++k) {
    const SectionEntry& prev = entries_[order[k - 1]];
    const SectionEntry& cur = entries_[order[k]];
    const uint64_t prev_end = prev.offset + prev.stored_size + kSectionPadding;  // checked above
    if (cur.offset < prev_end) {
      *error = section_error(order[k],
                             "starts at byte " + std::to_string(cur.offset) + ", inside section '" +
                                 section_label(prev.kind) + "' (#" + std::to_string(order[k - 1]) +
                                 ") or its padding, which end at byte " + std::to_string(prev_end));
      return false;
    }
  }

  if (header_.file_size != size_) {
    *error = fail(
        (header_.file_size > size_ ? "truncated: the header records " : "the header records ") +
        std::to_string(header_.file_size) + " bytes but the file has " + std::to_string(size_) +
        " bytes");
    return false;
  }
  if (total_raw > max_total_raw_size(size_)) {
    *error = fail("the sections decode to " + std::to_string(total_raw) +
                  " bytes in all, implausible for a file of " + std::to_string(size_) +
                  " bytes (at most " + std::to_string(kMaxZstdRatio) + "x + 64 MiB)");
    return false;
  }

  // Everything outside the header, the table and the sections is padding and must be zero.
  uint64_t gap_begin = table_end;
  for (uint32_t k = 0; k <= n; ++k) {
    const uint64_t gap_end = k < n ? entries_[order[k]].offset : size_;
    uint64_t nz = gap_end;
    if (fd_ >= 0) {
      // Read, not touched through the mapping: each gap lies at the end of a section, on a page
      // of its own for large ones, and faulting a page in costs ~12 us in a VM against ~1 us for
      // the read (mesh200, 18 sections: open took 0.16 ms through the mapping, 0.06 ms so).
      uint8_t buf[4096];
      for (uint64_t at = gap_begin; at < gap_end && nz == gap_end;) {
        const uint64_t m = std::min<uint64_t>(sizeof buf, gap_end - at);
        std::string why;
        if (!read_at(at, m, buf, &why)) {
          *error = fail(why);
          return false;
        }
        const uint64_t i = first_nonzero(buf, 0, m);
        if (i != m) nz = at + i;
        at += m;
      }
    } else {
      nz = first_nonzero(base_, gap_begin, gap_end);
    }
    if (nz != gap_end) {
      const std::string reason = "nonzero byte at offset " + std::to_string(nz) +
                                 " in the padding after the " +
                                 (k == 0 ? std::string("section table") : std::string("section"));
      *error = k == 0 ? fail(reason) : section_error(order[k - 1], reason);
      return false;
    }
    if (k < n) gap_begin = entries_[order[k]].offset + entries_[order[k]].stored_size;
  }
  return true;
}

int ArchiveReader::find_section(SectionKind kind) const {
  for (uint32_t i = 0; i < entries_.size(); ++i)
    if (entries_[i].kind == static_cast<uint32_t>(kind)) return static_cast<int>(i);
  return -1;
}

bool ArchiveReader::load_one(uint32_t index, uint8_t* out, archive_detail::Decoder* decoder,
                             std::string* reason) {
  const SectionEntry& e = entries_[index];
  Section& s = sections_[index];
  auto bad = [&](const std::string& why) {
    *reason = why;
    return false;
  };
  const Codec codec = static_cast<Codec>(e.codec);
  const uint8_t* src = base_ + e.offset;
  if (codec != Codec::kNone && fd_ >= 0 && e.stored_size >= kReadThreshold) {
    // The stored bytes of a compressed section are read once and decoded once, so they are read
    // with pread into this thread's huge-page staging buffer instead of through the mapping:
    // faulting page-cache pages into the mapping 4 KiB at a time cost twice as much as the copy
    // (measured on a 23 MB archive: 10.6 ms against 5.2 ms of CPU for mapping + checksum).
    std::string why;
    src = read_staged(e.offset, e.stored_size, decoder, &why);
    if (src == nullptr) return bad(why);
  }
  if (codec == Codec::kNone && map_ != nullptr && e.stored_size >= kPopulateThreshold) {
    // Used in place: map all its pages in one call before the checksum reads them, instead of
    // one fault per 64 KiB (shapes100k uncompressed, 55 MB: 21.5 -> 19.5 ms; cloud 3.0 -> 2.4).
    // A file that shrank since open fails here (EFAULT) rather than with SIGBUS below.
    const uintptr_t page = static_cast<uintptr_t>(sysconf(_SC_PAGESIZE));
    const uintptr_t begin = reinterpret_cast<uintptr_t>(src) / page * page;
    const uintptr_t end = reinterpret_cast<uintptr_t>(src) + e.stored_size + kSectionPadding;
    if (madvise(reinterpret_cast<void*>(begin), end - begin, kMadvPopulateRead) != 0 &&
        errno == EFAULT)
      return bad("truncated while loading: the file shrank after it was opened");
  }
  // Before anything decodes these bytes.
  if (checksum64(src, e.stored_size) != e.checksum) return bad("checksum mismatch");
  if (codec == Codec::kNone) {
    // validate() guarantees 16 bytes of (zero) padding after it inside the file.
    s.data = src;
    s.in_place = true;
    return true;
  }
  const uint64_t raw = e.raw_size;
  std::memset(out + raw, 0, kSectionPadding);
  if (codec == Codec::kDraco) {
    // validate() bounds raw_size; draco_decode_section checks the mesh lays out to exactly it.
    std::string why;
    if (!draco_decode_section(src, e.stored_size, raw, out, &why)) return bad(why);
    s.data = out;
    return true;
  }
  std::string why;
  if (!is_one_zstd_frame(src, e.stored_size, raw, "the table says " + std::to_string(raw), &why))
    return bad(why);
  ZSTD_DCtx* dctx = decoder->context();
  if (dctx == nullptr) return bad("zstd: cannot create a decompression context");
  auto decoded_to = [&](uint64_t got) {
    return bad("zstd frame decoded to " + std::to_string(got) + " bytes but the table says " +
               std::to_string(raw));
  };

  if (codec == Codec::kZstd) {
    const size_t got = ZSTD_decompressDCtx(dctx, out, raw, src, e.stored_size);
    if (ZSTD_isError(got)) return bad(std::string("zstd: ") + ZSTD_getErrorName(got));
    if (got != raw) return decoded_to(got);
    s.data = out;
    return true;
  }

  // Shuffled: stream one shuffle block at a time into the scratch block, which stays in cache,
  // and unshuffle it from there into its place. Decoding into `out` and unshuffling there would
  // write the section twice and read it back once; zstd's window buffer, reused across the
  // section, is small enough to stay in cache too.
  uint8_t* scratch = decoder->block(kShuffleBlock);
  if (scratch == nullptr) return bad("cannot allocate a block to decode it through");
  ZSTD_DCtx_reset(dctx, ZSTD_reset_session_only);
  ZSTD_inBuffer in{src, static_cast<size_t>(e.stored_size), 0};
  size_t hint = 1;  // ZSTD_decompressStream's result: 0 once the frame is complete and flushed
  for (uint64_t at = 0; at < raw; at += kShuffleBlock) {
    const size_t n = static_cast<size_t>(std::min(kShuffleBlock, raw - at));
    ZSTD_outBuffer block{scratch, n, 0};
    while (block.pos < n) {
      const size_t in_before = in.pos, out_before = block.pos;
      hint = ZSTD_decompressStream(dctx, &block, &in);
      if (ZSTD_isError(hint)) return bad(std::string("zstd: ") + ZSTD_getErrorName(hint));
      if (block.pos < n && (hint == 0 || (in.pos == in_before && block.pos == out_before)))
        return decoded_to(at + block.pos);  // ended (or stalled) short of raw_size
    }
    unshuffle4_block(scratch, out + at, n);
  }
  if (hint != 0) {
    // The output ended where the frame should: zstd must agree that nothing is left.
    uint8_t extra = 0;
    ZSTD_outBuffer probe{&extra, 1, 0};
    hint = ZSTD_decompressStream(dctx, &probe, &in);
    if (ZSTD_isError(hint)) return bad(std::string("zstd: ") + ZSTD_getErrorName(hint));
    if (probe.pos != 0 || hint != 0) return decoded_to(raw + probe.pos);
  }
  s.data = out;
  return true;
}

// Branch-free within blocks of 1024 so the compiler vectorizes it (with plain SSE2 too, which has
// no unsigned compare).
uint64_t first_at_or_above(const uint32_t* v, uint64_t n, uint32_t limit) {
  constexpr uint64_t kBlock = 1024;
  for (uint64_t at = 0; at < n; at += kBlock) {
    const uint64_t end = std::min(n, at + kBlock);
    uint32_t any = 0;
    for (uint64_t k = at; k < end; ++k) any |= static_cast<uint32_t>(v[k] >= limit);
    if (any != 0)
      for (uint64_t k = at; k < end; ++k)
        if (v[k] >= limit) return k;
  }
  return n;
}

// One unit of parallel loading: a whole section, or one frame of a codec-4 section.
struct ArchiveReader::LoadTask {
  uint32_t section;
  uint32_t frame;       // kWholeSection, or the frame's index
  uint64_t raw_offset;  // of the block within the section
  uint64_t raw_size;
  FrameRef ref;  // codec 4 only
};

bool ArchiveReader::load_frame(const LoadTask& t, uint8_t* out, archive_detail::Decoder* decoder,
                               WordBound* bounds, uint64_t num_bounds, std::string* error) {
  const SectionEntry& e = entries_[t.section];
  auto bad = [&](const std::string& reason) {
    *error = section_error(t.section, "frame " + std::to_string(t.frame) + ": " + reason);
    return false;
  };
  ZSTD_DCtx* dctx = decoder->context();
  uint8_t* scratch = decoder->block(t.raw_size);
  if (dctx == nullptr || scratch == nullptr)
    return bad("zstd: cannot allocate a decompression context");
  const uint8_t* src = base_ + e.offset + t.ref.offset;  // validate(): inside the file
  if (fd_ >= 0 && t.ref.size >= kReadThreshold) {
    // Read, not mapped: see load_one (and like load_one, a small one is decoded from the
    // mapping). A frame is small, so it stays in cache from the read through the checksum to the
    // decoder.
    std::string why;
    src = read_staged(e.offset + t.ref.offset, t.ref.size, decoder, &why);
    if (src == nullptr) return bad(why);
  }
  std::string why;
  if (!decode_frame(dctx, src, t.ref, t.raw_size, scratch, out + t.raw_offset, bounds, num_bounds,
                    e.raw_size >= kStreamSectionSize, &why))
    return bad(why);
  return true;
}

bool ArchiveReader::read_at(uint64_t offset, uint64_t size, uint8_t* dst, std::string* why) const {
  return read_fully(fd_, offset, size, dst, why);
}

const uint8_t* ArchiveReader::read_staged(uint64_t offset, uint64_t size,
                                          archive_detail::Decoder* decoder,
                                          std::string* why) const {
  uint8_t* stage = decoder->stage(size);
  if (stage == nullptr) {
    *why = "cannot allocate " + std::to_string(size) + " bytes to read it";
    return nullptr;
  }
  return read_at(offset, size, stage, why) ? stage : nullptr;
}

bool ArchiveReader::load_sections(int threads, std::string* error) {
  std::vector<uint32_t> all(section_count());
  for (uint32_t i = 0; i < section_count(); ++i) all[i] = i;
  std::vector<uint64_t> unused;
  return load_sections(threads, all, {}, &unused, error);
}

bool ArchiveReader::load_sections(int threads, const std::vector<uint32_t>& which,
                                  const std::vector<U32Bound>& bounds,
                                  std::vector<uint64_t>* first_out, std::string* error) {
  if (base_ == nullptr) {
    *error = fail("no archive is open");
    return false;
  }
  const uint32_t n = section_count();
  std::vector<uint32_t> order;
  std::vector<uint8_t> wanted(n, 0);
  for (uint32_t i : which)
    if (i < n && !wanted[i] && !sections_[i].skipped && sections_[i].data == nullptr) {
      wanted[i] = 1;
      order.push_back(i);
    }
  std::sort(order.begin(), order.end());
  // The bounds, by section; each must lie inside a section loaded here, on 4-byte boundaries.
  std::vector<std::vector<uint32_t>> bounds_of(n);
  for (uint32_t b = 0; b < bounds.size(); ++b) {
    const U32Bound& u = bounds[b];
    if (u.section >= n || !wanted[u.section] || u.begin > u.end ||
        u.end > entries_[u.section].raw_size || u.begin % 4 != 0 || u.end % 4 != 0) {
      *error = fail("internal error: bound " + std::to_string(b) +
                    " does not lie in a section loaded here");
      return false;
    }
    if (u.begin < u.end) bounds_of[u.section].push_back(b);  // an empty one holds nothing to check
  }
  for (std::vector<uint32_t>& list : bounds_of)  // decode_frame wants them sorted by begin
    std::sort(list.begin(), list.end(),
              [&](uint32_t a, uint32_t b) { return bounds[a].begin < bounds[b].begin; });
  std::vector<std::atomic<uint64_t>> first(bounds.size());
  for (uint32_t b = 0; b < bounds.size(); ++b) first[b].store(bounds[b].end);

  // Every decoded section in one buffer, in table order, each at a 64-byte boundary (no two
  // threads write one cache line) and followed by its padding. validate() bounded the sizes;
  // the sum is checked anyway.
  std::vector<uint64_t> slot(n, 0);
  uint64_t total = 0;
  for (uint32_t i : order) {
    if (entries_[i].codec == static_cast<uint32_t>(Codec::kNone)) continue;
    slot[i] = total;
    uint64_t end = 0;
    if (add_overflows(total, entries_[i].raw_size, &end) ||
        add_overflows(end, kSectionPadding + kBufferAlignment, &end)) {
      *error = fail("the sections' decoded sizes overflow");
      return false;
    }
    total = end / kBufferAlignment * kBufferAlignment;
  }
  uint8_t* decoded = nullptr;
  if (total > 0) {
    Buffer buffer = allocate(total);
    if (!buffer) {
      *error = fail("cannot allocate " + std::to_string(total) + " bytes to decode the sections");
      return false;
    }
    decoded = buffer.get();
    decoded_.push_back(std::move(buffer));
  }

  // The tasks: codec-4 sections by frame (their indexes read and checked here, on this thread:
  // 16 bytes per 4 MiB frame), every other section whole.
  std::vector<std::string> errors(n);
  std::vector<LoadTask> tasks;
  for (uint32_t i : order) {
    const SectionEntry& e = entries_[i];
    if (e.codec != static_cast<uint32_t>(Codec::kZstdShuffle4Frames)) {
      tasks.push_back(LoadTask{i, kWholeSection, 0, e.raw_size, {}});
      continue;
    }
    const uint64_t index_bytes = frame_count(e.raw_size) * sizeof(FrameEntry);
    std::vector<uint8_t> index;
    const uint8_t* at = base_ + e.offset;
    std::string why;
    if (fd_ >= 0 && index_bytes > 0) {
      index.resize(index_bytes);  // validate(): index_bytes <= stored_size
      if (!read_at(e.offset, index_bytes, index.data(), &why)) {
        errors[i] = section_error(i, why);
        continue;
      }
      at = index.data();
    }
    std::vector<FrameRef> frames;
    if (checksum64(at, index_bytes) != e.checksum) {
      errors[i] = section_error(i, "checksum mismatch");
    } else if (!read_frame_index(at, e.raw_size, e.stored_size, &frames, &why)) {
      errors[i] = section_error(i, why);
    } else {
      // The last frame's task zeroes the padding: here it would fault in a fresh page for each
      // section, on this thread alone, before any work is shared.
      if (frames.empty()) std::memset(decoded + slot[i] + e.raw_size, 0, kSectionPadding);
      for (uint32_t k = 0; k < frames.size(); ++k) {
        const uint64_t begin = uint64_t{k} * kFrameBlock;
        tasks.push_back(
            LoadTask{i, k, begin, std::min(kFrameBlock, e.raw_size - begin), frames[k]});
      }
    }
  }

  // Largest first, so one big section does not start last and leave the other threads idle.
  std::vector<uint32_t> schedule(tasks.size());
  for (uint32_t k = 0; k < tasks.size(); ++k) schedule[k] = k;
  std::stable_sort(schedule.begin(), schedule.end(),
                   [&](uint32_t a, uint32_t b) { return tasks[a].raw_size > tasks[b].raw_size; });
  std::vector<std::string> task_errors(tasks.size());
  // Records the first value >= limit of bound b in [lo, hi) of data (the section's bytes).
  auto scan = [&](uint32_t b, const uint8_t* data, uint64_t lo, uint64_t hi) {
    const uint64_t k4 = first_at_or_above(reinterpret_cast<const uint32_t*>(data + lo),
                                          (hi - lo) / 4, bounds[b].limit);
    if (k4 == (hi - lo) / 4) return;
    const uint64_t found = lo + 4 * k4;
    uint64_t seen = first[b].load(std::memory_order_relaxed);
    while (found < seen && !first[b].compare_exchange_weak(seen, found)) {
    }
  };
  auto run = [&](uint32_t k) {
    const LoadTask& t = tasks[k];
    uint8_t* out = decoded + slot[t.section];
    archive_detail::Decoder& decoder = thread_decoder();
    if (t.frame == kWholeSection) {
      if (!load_one(t.section, out, &decoder, &task_errors[k])) {
        task_errors[k] = section_error(t.section, task_errors[k]);
        return;
      }
      const uint8_t* data = sections_[t.section].data;
      for (uint32_t b : bounds_of[t.section]) scan(b, data, bounds[b].begin, bounds[b].end);
      return;
    }
    // The bounds over this frame's block, relative to it: checked as the block unshuffles, and
    // searched for the first offender only when one is exceeded.
    std::vector<WordBound>& local = decoder.bounds;
    std::vector<uint32_t>& which_bound = decoder.bound_ids;
    local.clear();
    which_bound.clear();
    const uint64_t block_end = t.raw_offset + t.raw_size;
    for (uint32_t b : bounds_of[t.section]) {
      const uint64_t lo = std::max(bounds[b].begin, t.raw_offset);
      const uint64_t hi = std::min(bounds[b].end, block_end);
      if (lo >= hi) continue;
      local.push_back(WordBound{lo - t.raw_offset, hi - t.raw_offset, bounds[b].limit, false});
      which_bound.push_back(b);
    }
    if (!load_frame(t, out, &decoder, local.data(), local.size(), &task_errors[k])) return;
    const uint64_t section_size = entries_[t.section].raw_size;
    if (block_end == section_size) std::memset(out + section_size, 0, kSectionPadding);
    for (size_t j = 0; j < local.size(); ++j)
      if (local[j].exceeded)
        scan(which_bound[j], out, t.raw_offset + local[j].begin, t.raw_offset + local[j].end);
  };
  // Draco sections go last, and only when every other section decoded: Draco's own work on a
  // forged stream is not bounded (format/draco_codec.h: seconds from a few KB), so a file with
  // any other fault fails without running it.
  const size_t draco_from =
      size_t(std::stable_partition(schedule.begin(), schedule.end(),
                                   [&](uint32_t k) {
                                     return entries_[tasks[k].section].codec !=
                                            static_cast<uint32_t>(Codec::kDraco);
                                   }) -
             schedule.begin());
  // A small load (the records of a scene) runs on this thread: waking the workers costs more.
  uint64_t work_bytes = 0;  // validate() bounded every size: no overflow
  for (uint32_t i : order)
    work_bytes += entries_[i].codec == static_cast<uint32_t>(Codec::kNone)
                      ? entries_[i].raw_size / kChecksumOnlyWeight
                      : entries_[i].stored_size + entries_[i].raw_size;
  const bool serial = threads == 1 || work_bytes < kSerialLoadBytes || schedule.size() < 2;
  std::optional<tbb::task_arena> arena;
  // int(): a value, not a reference to the constant (which has no definition to link to).
  if (!serial) arena.emplace(threads > 0 ? threads : int(tbb::task_arena::automatic));
  auto run_all = [&](size_t begin, size_t end) {
    if (serial) {
      for (size_t k = begin; k < end; ++k) run(schedule[k]);
      thread_decoder().trim();
      return;
    }
    // Each thread takes the next task in schedule order until none is left.
    std::atomic<size_t> next{begin};
    arena->execute([&] {
      tbb::parallel_for(0, arena->max_concurrency(), [&](int) {
        for (size_t k = next++; k < end; k = next++) run(schedule[k]);
        thread_decoder().trim();
      });
    });
  };
  run_all(0, draco_from);
  bool failed = false;
  for (uint32_t i : order) failed |= !errors[i].empty();
  for (size_t k = 0; k < draco_from; ++k) failed |= !task_errors[schedule[k]].empty();
  // The Draco streams' checksums, here and before any child is forked: a damaged stream fails
  // for the price of hashing it (microseconds), not of a process (a millisecond or more). Read
  // with pread from a file, as the frame indexes are, so a file that shrank since it was opened
  // fails here with an error, not SIGBUS.
  if (!failed) {
    for (size_t k = draco_from; k < schedule.size(); ++k) {
      const uint32_t i = tasks[schedule[k]].section;
      const SectionEntry& e = entries_[i];
      std::string why;
      const uint8_t* at = fd_ >= 0 ? read_staged(e.offset, e.stored_size, &thread_decoder(), &why)
                                   : base_ + e.offset;
      if (at == nullptr) {
        task_errors[schedule[k]] = section_error(i, why);
        failed = true;
        continue;
      }
      if (checksum64(at, e.stored_size) != e.checksum) {
        task_errors[schedule[k]] = section_error(i, "checksum mismatch");
        failed = true;
      }
    }
  }
  if (!failed && draco_from < schedule.size()) {
    if (isolation_enabled()) {
      // In child processes with a budget (format/isolated_jobs.h), each decoding into shared
      // memory that is then copied into place: Draco never runs in this process. Jobs go in
      // section order, so the section that stops a child is reported before those it left.
      std::vector<uint32_t> job_task(schedule.begin() + std::ptrdiff_t(draco_from), schedule.end());
      std::sort(job_task.begin(), job_task.end(),
                [&](uint32_t a, uint32_t b) { return tasks[a].section < tasks[b].section; });
      std::vector<IsolatedJob> jobs;
      std::vector<uint8_t*> dst;
      for (uint32_t k : job_task) {
        const uint32_t i = tasks[k].section;
        jobs.push_back(
            IsolatedJob{entries_[i].raw_size + kSectionPadding, entries_[i].stored_size});
        dst.push_back(decoded + slot[i]);
      }
      std::vector<std::string> job_errors;
      std::vector<char> by_job;
      const int processes = threads > 0 ? threads : int(std::thread::hardware_concurrency());
      run_isolated(
          jobs, dst, processes, IsolationBudget{},
          [&](size_t j, uint8_t* out, std::string* why) {
            return load_one(tasks[job_task[j]].section, out, &thread_decoder(), why);
          },
          &job_errors, &by_job);
      for (size_t j = 0; j < jobs.size(); ++j) {
        const uint32_t i = tasks[job_task[j]].section;
        if (!job_errors[j].empty()) {
          task_errors[job_task[j]] =
              section_error(i, by_job[j] ? job_errors[j] : "draco: " + job_errors[j]);
          continue;
        }
        // The child may have been subverted by its stream: the padding is this process's to set,
        // and what validate() checks is checked here as for any section.
        std::memset(decoded + slot[i] + entries_[i].raw_size, 0, kSectionPadding);
        sections_[i].data = decoded + slot[i];
        sections_[i].in_place = false;
        for (uint32_t b : bounds_of[i]) scan(b, sections_[i].data, bounds[b].begin, bounds[b].end);
      }
    } else {
      run_all(draco_from, schedule.size());
    }
  }
  // The lowest-numbered failing section's first failure (tasks are in section, frame order).
  for (uint32_t k = 0; k < tasks.size(); ++k) {
    const uint32_t i = tasks[k].section;
    if (!task_errors[k].empty() && (errors[i].empty())) errors[i] = task_errors[k];
  }
  for (uint32_t i : order) {
    if (errors[i].empty()) continue;
    *error = errors[i];
    for (uint32_t j : order) {  // all or nothing
      sections_[j].data = nullptr;
      sections_[j].in_place = false;
    }
    if (decoded != nullptr) decoded_.pop_back();
    return false;
  }
  for (uint32_t i : order)
    if (entries_[i].codec == static_cast<uint32_t>(Codec::kZstdShuffle4Frames))
      sections_[i].data = decoded + slot[i];
  first_out->resize(bounds.size());
  for (uint32_t b = 0; b < bounds.size(); ++b) (*first_out)[b] = first[b].load();
  return true;
}

bool ArchiveReader::typed_array_bytes(uint32_t section, size_t elem_size, size_t elem_align,
                                      const void** out, uint32_t* count, std::string* error) const {
  if (section >= entries_.size()) {
    *error = fail("section #" + std::to_string(section) + " does not exist (the archive has " +
                  std::to_string(entries_.size()) + ")");
    return false;
  }
  const SectionEntry& e = entries_[section];
  const uint8_t* data = sections_[section].data;
  if (data == nullptr) {
    *error = section_error(section, "not loaded");
    return false;
  }
  if (e.raw_size != uint64_t{e.count} * elem_size) {
    *error = section_error(section, std::to_string(e.raw_size) + " bytes is not " +
                                        std::to_string(e.count) + " records of " +
                                        std::to_string(elem_size) + " bytes");
    return false;
  }
  if (reinterpret_cast<uintptr_t>(data) % elem_align != 0) {
    *error =
        section_error(section, "data is not aligned to " + std::to_string(elem_align) + " bytes");
    return false;
  }
  *out = data;
  *count = e.count;
  return true;
}

}  // namespace pbrta
