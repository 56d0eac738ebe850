#include "format/archive_reader.h"

#include "format/archive_writer.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <new>
#include <system_error>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <xxhash.h>
// For ZSTD_customMem and ZSTD_createDCtx_advanced: exported by the shared library since 1.3.
#define ZSTD_STATIC_LINKING_ONLY
#include <zstd.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "format/archive_names.h"
#include "format/draco_codec.h"

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

bool add_overflows(uint64_t a, uint64_t b, uint64_t* sum) {
  return __builtin_add_overflow(a, b, sum);
}
bool mul_overflows(uint64_t a, uint64_t b, uint64_t* p) {
  return __builtin_mul_overflow(a, b, p);
}

std::string errno_text(int err) {
  return std::error_code(err, std::generic_category()).message();
}

std::string section_label(uint32_t kind) {
  if (kind > 0 && kind < static_cast<uint32_t>(SectionKind::kCount))
    return std::string(section_kind_name(static_cast<SectionKind>(kind)));
  return "kind " + std::to_string(kind);
}

// The inverse of the writer's shuffle: src holds all byte-0s of the 4-byte words, then all
// byte-1s, ..., then the size % 4 tail bytes unshuffled.
void unshuffle4(const uint8_t* src, uint8_t* dst, uint64_t size) {
  const uint64_t words = size / 4;
  const uint8_t* s0 = src;
  const uint8_t* s1 = src + words;
  const uint8_t* s2 = src + 2 * words;
  const uint8_t* s3 = src + 3 * words;
  uint64_t w = 0;
#if defined(__SSE2__)
  // 16 words at a time: interleave bytes of lanes 0/1 and 2/3, then the 16-bit pairs.
  for (; w + 16 <= words; w += 16) {
    const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s0 + w));
    const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s1 + w));
    const __m128i c = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s2 + w));
    const __m128i d = _mm_loadu_si128(reinterpret_cast<const __m128i*>(s3 + w));
    const __m128i ab_lo = _mm_unpacklo_epi8(a, b), ab_hi = _mm_unpackhi_epi8(a, b);
    const __m128i cd_lo = _mm_unpacklo_epi8(c, d), cd_hi = _mm_unpackhi_epi8(c, d);
    __m128i* out = reinterpret_cast<__m128i*>(dst + 4 * w);
    _mm_storeu_si128(out + 0, _mm_unpacklo_epi16(ab_lo, cd_lo));
    _mm_storeu_si128(out + 1, _mm_unpackhi_epi16(ab_lo, cd_lo));
    _mm_storeu_si128(out + 2, _mm_unpacklo_epi16(ab_hi, cd_hi));
    _mm_storeu_si128(out + 3, _mm_unpackhi_epi16(ab_hi, cd_hi));
  }
#endif
  for (; w < words; ++w) {
    dst[4 * w + 0] = s0[w];
    dst[4 * w + 1] = s1[w];
    dst[4 * w + 2] = s2[w];
    dst[4 * w + 3] = s3[w];
  }
  std::memcpy(dst + 4 * words, src + 4 * words, size - 4 * words);
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

// One loading thread's state, made on its first zstd section: the decompression context (reused
// across sections, so its window buffer is allocated once) and the block that shuffled data is
// decoded into before it is unshuffled into place.
struct archive_detail::Decoder {
  ZSTD_DCtx* dctx = nullptr;
  uint8_t* scratch = nullptr;
  bool tried = false;
  // Where a compressed section's stored bytes are read to (see ArchiveReader::stored_bytes).
  uint8_t* staging = nullptr;
  uint64_t staging_mapped = 0;

  Decoder() = default;
  Decoder(const Decoder&) {}  // a fresh one: contexts are per thread, never shared
  Decoder& operator=(const Decoder&) = delete;
  ~Decoder() {
    ZSTD_freeDCtx(dctx);
    zstd_free(nullptr, scratch);
    if (staging != nullptr) munmap(staging, staging_mapped);
  }
  // A staging buffer of at least bytes, or nullptr when out of memory.
  uint8_t* stage(uint64_t bytes) {
    if (bytes > staging_mapped) {
      if (staging != nullptr) munmap(staging, staging_mapped);
      staging = map_fresh(bytes, &staging_mapped);
      if (staging == nullptr) staging_mapped = 0;
    }
    return staging;
  }
  bool ready() {
    if (!tried) {
      tried = true;
      dctx = ZSTD_createDCtx_advanced(ZSTD_customMem{zstd_alloc, zstd_free, nullptr});
      // Streaming, unlike one-shot decoding, refuses windows over 2^27 by default; every frame
      // one-shot decoding accepts must still load. zstd sizes its buffer by the smaller of the
      // window and the content size, which validate() bounded.
      if (dctx != nullptr) ZSTD_DCtx_setParameter(dctx, ZSTD_d_windowLogMax, ZSTD_WINDOWLOG_MAX);
      scratch = static_cast<uint8_t*>(zstd_alloc(nullptr, kShuffleBlock));
    }
    return dctx != nullptr && scratch != nullptr;
  }
};

bool section_sizes_plausible(Codec codec, uint64_t stored_size, uint64_t raw_size) {
  if (raw_size > kMaxRawSize) return false;
  switch (codec) {
    case Codec::kNone:
      return raw_size == stored_size;
    case Codec::kZstd:
    case Codec::kZstdShuffle4:
    case Codec::kDraco: {
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
  decoded_.reset();
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
  void* map = mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0);
  const int map_errno = errno;
  if (map == MAP_FAILED) {
    ::close(fd);
    *error = fail("cannot map: " + errno_text(map_errno));
    return false;
  }
  fd_ = fd;  // kept for load_sections' reads of compressed sections
  map_ = map;
  map_size_ = size;
  base_ = static_cast<const uint8_t*>(map);
  size_ = size;
  if (!validate(error)) {
    const std::string name = path_;
    reset();
    path_ = name;
    return false;
  }
  return true;
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
  if (!validate(error)) {
    const std::string keep = path_;
    reset();
    path_ = keep;
    return false;
  }
  return true;
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
  if (XXH3_64bits(base_, offsetof(Header, header_checksum)) != header_.header_checksum) {
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
  if (XXH3_64bits(base_ + sizeof(Header), table_bytes) != header_.table_checksum) {
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
    const uint64_t nz = first_nonzero(base_, gap_begin, gap_end);
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
                             std::string* error) {
  const SectionEntry& e = entries_[index];
  Section& s = sections_[index];
  auto bad = [&](const std::string& reason) {
    *error = section_error(index, reason);
    return false;
  };
  const Codec codec = static_cast<Codec>(e.codec);
  const uint8_t* src = base_ + e.offset;
  if (codec != Codec::kNone && fd_ >= 0) {
    // The stored bytes of a compressed section are read once and decoded once, so they are read
    // with pread into this thread's huge-page staging buffer instead of through the mapping:
    // faulting page-cache pages into the mapping 4 KiB at a time cost twice as much as the copy
    // (measured on a 23 MB archive: 10.6 ms against 5.2 ms of CPU for mapping + checksum).
    uint8_t* stage = decoder->stage(e.stored_size);
    if (stage == nullptr)
      return bad("cannot allocate " + std::to_string(e.stored_size) + " bytes to read it");
    for (uint64_t got = 0; got < e.stored_size;) {
      const ssize_t r = ::pread(fd_, stage + got, e.stored_size - got, e.offset + got);
      if (r < 0 && errno == EINTR) continue;
      if (r < 0) return bad("cannot read: " + errno_text(errno));
      if (r == 0) return bad("truncated while loading: the file shrank after it was opened");
      got += static_cast<uint64_t>(r);
    }
    src = stage;
  }
  // Before anything decodes these bytes.
  if (XXH3_64bits(src, e.stored_size) != e.checksum) return bad("checksum mismatch");
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
  const unsigned long long content = ZSTD_getFrameContentSize(src, e.stored_size);
  if (content == ZSTD_CONTENTSIZE_ERROR) return bad("zstd: not a zstd frame");
  if (content == ZSTD_CONTENTSIZE_UNKNOWN) return bad("zstd: the frame does not record its size");
  if (content != raw)
    return bad("zstd frame content size is " + std::to_string(content) + " but the table says " +
               std::to_string(raw));
  const size_t frame = ZSTD_findFrameCompressedSize(src, e.stored_size);
  if (ZSTD_isError(frame)) return bad(std::string("zstd: ") + ZSTD_getErrorName(frame));
  if (frame != e.stored_size)
    return bad(std::to_string(e.stored_size - frame) + " bytes follow the zstd frame");
  if (!decoder->ready()) return bad("zstd: cannot create a decompression context");
  ZSTD_DCtx* dctx = decoder->dctx;
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
  ZSTD_DCtx_reset(dctx, ZSTD_reset_session_only);
  ZSTD_inBuffer in{src, static_cast<size_t>(e.stored_size), 0};
  size_t hint = 1;  // ZSTD_decompressStream's result: 0 once the frame is complete and flushed
  for (uint64_t at = 0; at < raw; at += kShuffleBlock) {
    const size_t n = static_cast<size_t>(std::min(kShuffleBlock, raw - at));
    ZSTD_outBuffer block{decoder->scratch, n, 0};
    while (block.pos < n) {
      const size_t in_before = in.pos, out_before = block.pos;
      hint = ZSTD_decompressStream(dctx, &block, &in);
      if (ZSTD_isError(hint)) return bad(std::string("zstd: ") + ZSTD_getErrorName(hint));
      if (block.pos < n && (hint == 0 || (in.pos == in_before && block.pos == out_before)))
        return decoded_to(at + block.pos);  // ended (or stalled) short of raw_size
    }
    unshuffle4(decoder->scratch, out + at, n);
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

bool ArchiveReader::load_sections(int threads, std::string* error) {
  if (base_ == nullptr) {
    *error = fail("no archive is open");
    return false;
  }
  const uint32_t n = section_count();
  std::vector<uint32_t> order;
  for (uint32_t i = 0; i < n; ++i)
    if (!sections_[i].skipped && sections_[i].data == nullptr) order.push_back(i);
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
    decoded_ = allocate(total);
    if (!decoded_) {
      *error = fail("cannot allocate " + std::to_string(total) + " bytes to decode the sections");
      return false;
    }
    decoded = decoded_.get();
  }
  // Largest first, so one big section does not start last and leave the other threads idle.
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return entries_[a].stored_size > entries_[b].stored_size;
  });
  std::vector<std::string> errors(n);
  std::vector<uint8_t> failed(n, 0);
  tbb::enumerable_thread_specific<archive_detail::Decoder> decoders;
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, order.size(), 1),
                      [&](const tbb::blocked_range<size_t>& r) {
                        for (size_t k = r.begin(); k != r.end(); ++k) {
                          const uint32_t i = order[k];
                          if (!load_one(i, decoded + slot[i], &decoders.local(), &errors[i]))
                            failed[i] = 1;
                        }
                      });
  });
  for (uint32_t i = 0; i < n; ++i) {
    if (failed[i]) {
      *error = errors[i];
      for (Section& s : sections_) {  // all or nothing
        s.data = nullptr;
        s.in_place = false;
      }
      decoded_.reset();
      return false;
    }
  }
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
