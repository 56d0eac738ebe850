// ArchiveReader: opening a file (read whole or mapped), checking its header, table and padding,
// and the accessors. Decoding the sections is in format/section_loading.cpp.
#include "format/archive_reader.h"

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

#include "format/archive_names.h"
#include "format/checksum.h"
#include "format/huge_pages.h"

namespace pbrta {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "the archive is little-endian and its structures are read directly");

namespace {

using archive_detail::add_overflows;
using archive_detail::allocate;
using archive_detail::mul_overflows;

constexpr size_t kBufferAlignment = 64;  // a cache line; more than the 16 the format promises
constexpr uint64_t kHugeBufferThreshold = uint64_t{256} << 10;

// Files up to this size are read whole into memory when opened; larger ones are mapped, and
// their pages are faulted in by whatever reads them first, with no MADV_POPULATE_READ ahead of it.
// ext4 now caches a file written in large blocks (as pbrtc writes) in large folios, and one fault
// maps a whole folio: in this VM (kernel 6.18) reading and checksumming through a plain mapping
// beat both the copy into fresh huge pages and a populated mapping at every size measured.
// --codec none, 2 threads, best of 300 loads (archive_bench --phases), read whole or populated ->
// mapped: teapot (0.9 MB) 160-162 -> 113 us, caustic glass (2.1 MB) 207-210 -> 123 us,
// 2d-mappings (4.2 MB) 315 -> 129 us, projection (16.8 MB, populated) 714-727 -> 506-520 us;
// best of 30: shapes100k (58 MB, populated) 4.3-4.5 -> 3.3-3.7 ms. A file evicted and read back
// from disk is cached in smaller folios and its faults cost more, but mapping still wins:
// caustic glass read back so, 244 us read whole -> 189 us mapped.
constexpr uint64_t kSmallFileSize = uint64_t{64} << 10;

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

}  // namespace

bool section_sizes_plausible(Codec codec, uint64_t stored_size, uint64_t raw_size) {
  if (raw_size > kMaxRawSize) return false;
  switch (codec) {
    case Codec::kRaw:
      return raw_size == stored_size;
    case Codec::kZstd:
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

archive_detail::Buffer archive_detail::allocate(uint64_t bytes, bool heap_only) {
  if (bytes >= kHugeBufferThreshold && !heap_only) {
    uint64_t mapped = 0;
    uint8_t* p = static_cast<uint8_t*>(map_huge(bytes, &mapped));
    return Buffer(p, BufferFree{p != nullptr ? mapped : 0});
  }
  return Buffer(
      static_cast<uint8_t*>(::operator new[](std::max<uint64_t>(bytes, 1),
                                             std::align_val_t(kBufferAlignment), std::nothrow)),
      BufferFree{0});
}

void archive_detail::shrink(Buffer* b, uint64_t bytes) {
  const uint64_t mapped = b->get_deleter().mapped_size;
  const uint64_t page = uint64_t(sysconf(_SC_PAGESIZE));
  const uint64_t keep = std::max<uint64_t>(page, (bytes + page - 1) / page * page);
  // Splitting a huge page costs 20-50 us: only worth it for a good part of one.
  if (mapped == 0 || keep >= mapped || mapped - keep < (uint64_t{1} << 20)) return;
  munmap(b->get() + keep, mapped - keep);
  b->get_deleter().mapped_size = keep;
}

ArchiveReader::ArchiveReader() = default;

ArchiveReader::~ArchiveReader() {
  reset();
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
  if (size <= kSmallFileSize) {
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
    fd_ = fd;  // kept for unchanged_size()
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
  if (header_.major < kMajorVersion) {
    *error = fail("archive version " + version + ": recompile with this pbrtc");
    return false;
  }
  if (header_.major > kMajorVersion) {
    *error = fail("archive version " + version + ": this reader reads " +
                  std::to_string(kMajorVersion) + ".x; update pbrtc and pbrtrun");
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
    if (codec == Codec::kRaw && e.raw_size != e.stored_size)
      return bad("raw size " + std::to_string(e.raw_size) + " differs from stored size " +
                 std::to_string(e.stored_size) + " with codec '" + std::string(codec_name(codec)) +
                 "'");
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
    // Read through the mapping, as the load reads every section: a gap as pbrtc writes it (16 to
    // 31 bytes) starts in the last page of the section before it, which the load faults in anyway.
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

bool ArchiveReader::unchanged_size(std::string* error) const {
  struct stat st;
  if (fd_ < 0 || fstat(fd_, &st) != 0 || static_cast<uint64_t>(st.st_size) >= size_) return true;
  // Name the first section in the file that no longer fits, with its padding.
  const uint64_t now = static_cast<uint64_t>(st.st_size);
  int cut = -1;
  for (uint32_t i = 0; i < entries_.size(); ++i)
    if (entries_[i].offset + entries_[i].stored_size + kSectionPadding > now &&
        (cut < 0 || entries_[i].offset < entries_[static_cast<uint32_t>(cut)].offset))
      cut = static_cast<int>(i);
  const std::string reason = "truncated while loading: the file shrank after it was opened";
  *error = cut >= 0 ? section_error(static_cast<uint32_t>(cut), reason) : fail(reason);
  return false;
}

int ArchiveReader::find_section(SectionKind kind) const {
  for (uint32_t i = 0; i < entries_.size(); ++i)
    if (entries_[i].kind == static_cast<uint32_t>(kind)) return static_cast<int>(i);
  return -1;
}
}  // namespace pbrta
