#include "format/archive_writer.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <zstd.h>

#include "format/archive_names.h"
#include "format/archive_reader.h"
#include "format/checksum.h"
#include "format/progress_count.h"
#include "format/zstd_frames.h"

namespace pbrta {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "the archive is little-endian and its structures are written directly");

namespace {

uint64_t align_up(uint64_t x, uint64_t a) {
  return (x + a - 1) / a * a;
}

std::string errno_text(int err) {
  return std::error_code(err, std::generic_category()).message();
}

// The table's checksum of a section's stored bytes, by codec (ARCHIVE.md, section 5).
uint64_t section_checksum(Codec codec, const uint8_t* stored, uint64_t stored_size,
                          uint64_t raw_size) {
  switch (codec) {
    case Codec::kRaw:
      return chunked_checksum64(stored, stored_size);
    case Codec::kZstd: {  // its frame index, which covers the frames; ours is well formed
      FrameIndex index;
      std::string unused;
      read_frame_header(stored, stored_size, raw_size, &index, &unused);
      return checksum64(stored, index.index_bytes);
    }
    default:
      return checksum64(stored, stored_size);
  }
}

// One section's stored form. For kRaw, stored is empty and the raw bytes are written.
struct Encoded {
  Codec codec = Codec::kRaw;
  std::vector<uint8_t> stored;
  uint64_t stored_size = 0;
  uint64_t checksum = 0;
  std::string error;
};

bool write_all(int fd, const void* data, uint64_t size) {
  const uint8_t* p = static_cast<const uint8_t*>(data);
  while (size > 0) {
    const size_t chunk = static_cast<size_t>(std::min<uint64_t>(size, uint64_t{1} << 30));
    const ssize_t n = ::write(fd, p, chunk);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    if (n == 0) {
      errno = EIO;
      return false;
    }
    p += n;
    size -= static_cast<uint64_t>(n);
  }
  return true;
}

// Offsets of every section and the file size, given the stored sizes.
uint64_t lay_out(std::vector<SectionEntry>* table) {
  uint64_t pos = sizeof(Header) + table->size() * sizeof(SectionEntry);  // 16-aligned: 48n
  for (SectionEntry& e : *table) {
    e.offset = pos;
    pos = align_up(pos + e.stored_size + kSectionPadding, kSectionAlignment);
  }
  return pos;
}

}  // namespace

uint32_t ArchiveWriter::add_section(SectionKind kind, std::vector<uint8_t> raw, uint32_t count,
                                    Codec codec, bool shuffle) {
  sections_.push_back(Section{kind, codec, shuffle, count, std::move(raw), {}});
  return static_cast<uint32_t>(sections_.size() - 1);
}

uint32_t ArchiveWriter::add_encoded_section(SectionKind kind, std::vector<uint8_t> raw,
                                            std::vector<uint8_t> stored, uint32_t count,
                                            Codec codec) {
  sections_.push_back(Section{kind, codec, false, count, std::move(raw), std::move(stored)});
  return static_cast<uint32_t>(sections_.size() - 1);
}

uint32_t ArchiveWriter::add_section(SectionKind kind, const void* data, size_t size, uint32_t count,
                                    Codec codec, bool shuffle) {
  const uint8_t* p = static_cast<const uint8_t*>(data);
  return add_section(kind, std::vector<uint8_t>(p, p + size), count, codec, shuffle);
}

bool ArchiveWriter::write(const std::string& path, uint64_t effects, int zstd_level, int threads,
                          std::string* error, const CompressProgress& progress) {
  header_ = Header{};
  table_.clear();
  const std::string what = "cannot write '" + path + "': ";
  const uint32_t n = section_count();
  for (uint32_t i = 0; i < n; ++i) {
    const Section& s = sections_[i];
    std::string problem;
    if (static_cast<uint32_t>(s.codec) >= static_cast<uint32_t>(Codec::kCount))
      problem = "unknown codec " + std::to_string(static_cast<uint32_t>(s.codec));
    else if (s.raw.size() > kMaxRawSize)
      problem = "section is larger than 2^40 bytes";
    else if (s.codec == Codec::kDraco &&
             (s.kind != SectionKind::kGeometry || s.count != 1 || s.stored.empty()))
      problem = "codec 'draco' needs a geometry section of one mesh, encoded by the caller";
    else if (s.codec != Codec::kDraco && !s.stored.empty())
      problem = "only codec 'draco' sections come encoded";
    else if (s.shuffle && s.codec != Codec::kZstd)
      problem = "only codec 'zstd' sections are shuffled";
    if (!problem.empty()) {
      *error = what + "section '" + std::string(section_kind_name(s.kind)) + "' (#" +
               std::to_string(i) + "): " + problem;
      return false;
    }
  }
  const int level = std::clamp(zstd_level, ZSTD_minCLevel(), ZSTD_maxCLevel());

  // Compress and checksum, largest sections first so the big ones do not start last.
  std::vector<Encoded> enc(n);
  std::vector<uint32_t> order(n);
  for (uint32_t i = 0; i < n; ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return sections_[a].raw.size() > sections_[b].raw.size();
  });
  auto compresses = [](Codec c) { return c == Codec::kZstd; };
  uint64_t to_compress = 0;
  for (const Section& s : sections_)
    if (compresses(s.codec)) to_compress += s.raw.size();
  ProgressCount compressed(to_compress, progress);
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, n, 1), [&](const tbb::blocked_range<size_t>& r) {
          for (size_t k = r.begin(); k != r.end(); ++k) {
            const uint32_t i = order[k];
            const Section& s = sections_[i];
            Encoded& e = enc[i];
            e.codec = s.codec;
            if (s.codec == Codec::kDraco) {
              e.stored = s.stored;  // encoded by the caller
            } else if (s.codec == Codec::kZstd) {
              if (!encode_zstd_frames(s.raw.data(), s.raw.size(), level, kFrameSize, s.shuffle,
                                      &e.stored, &e.error))
                continue;
              if (s.raw.size() > kSmallFrameSize && s.raw.size() <= kSmallFramesMax) {
                std::vector<uint8_t> small;
                if (!encode_zstd_frames(s.raw.data(), s.raw.size(), level, kSmallFrameSize,
                                        s.shuffle, &small, &e.error))
                  continue;
                if (small.size() <= e.stored.size() + e.stored.size() / kSmallFramesSlack)
                  e.stored = std::move(small);
              }
            }
            // Compresses better than the reader believes possible (say, a black image): store it.
            if (e.codec != Codec::kRaw &&
                !section_sizes_plausible(e.codec, e.stored.size(), s.raw.size())) {
              e.codec = Codec::kRaw;
              e.stored = {};
            }
            const uint8_t* stored = e.codec == Codec::kRaw ? s.raw.data() : e.stored.data();
            e.stored_size = e.codec == Codec::kRaw ? s.raw.size() : e.stored.size();
            e.checksum = section_checksum(e.codec, stored, e.stored_size, s.raw.size());
            if (compresses(s.codec)) compressed.add(s.raw.size());
          }
        });
  });
  for (uint32_t i = 0; i < n; ++i) {
    if (!enc[i].error.empty()) {
      *error = what + "section '" + std::string(section_kind_name(sections_[i].kind)) + "' (#" +
               std::to_string(i) + "): " + enc[i].error;
      return false;
    }
  }
  compressed.finish();

  std::vector<SectionEntry> table(n);
  auto fill_table = [&] {
    for (uint32_t i = 0; i < n; ++i) {
      SectionEntry& t = table[i];
      t = SectionEntry{};
      t.kind = static_cast<uint32_t>(sections_[i].kind);
      t.codec = static_cast<uint32_t>(enc[i].codec);
      t.stored_size = enc[i].stored_size;
      t.raw_size = sections_[i].raw.size();
      t.checksum = enc[i].checksum;
      t.count = sections_[i].count;
    }
    return lay_out(&table);
  };
  uint64_t file_size = fill_table();
  // The reader's bound on the total decoded size: store the most compressible sections as they
  // are until the archive is within it (it only binds with many tiny, very compressible ones).
  for (;;) {
    uint64_t total_raw = 0;
    for (const SectionEntry& t : table) total_raw += t.raw_size;
    if (total_raw <= max_total_raw_size(file_size)) break;
    int worst = -1;
    uint64_t worst_excess = 0;
    for (uint32_t i = 0; i < n; ++i) {
      if (enc[i].codec == Codec::kRaw) continue;
      const uint64_t excess =
          table[i].raw_size - std::min(table[i].raw_size, table[i].stored_size * kMaxZstdRatio);
      if (worst < 0 || excess > worst_excess) {
        worst = static_cast<int>(i);
        worst_excess = excess;
      }
    }
    if (worst < 0) break;  // all stored raw: total_raw <= file_size, so unreachable
    Encoded& e = enc[worst];
    e.codec = Codec::kRaw;
    e.stored = {};
    e.stored_size = sections_[worst].raw.size();
    e.checksum =
        section_checksum(e.codec, sections_[worst].raw.data(), e.stored_size, e.stored_size);
    file_size = fill_table();
  }

  Header h{};
  std::memcpy(h.magic, kMagic, sizeof(kMagic));
  h.major = kMajorVersion;
  h.minor = kMinorVersion;
  h.flags = 0;
  h.effects = effects;
  h.section_count = n;
  h.reserved0 = 0;
  h.table_offset = sizeof(Header);
  h.file_size = file_size;
  h.table_checksum = checksum64(table.data(), table.size() * sizeof(SectionEntry));
  h.header_checksum = checksum64(&h, offsetof(Header, header_checksum));

  // Write to a temporary beside path, sync, rename: readers see the old file or the new one.
  const std::string tmp = path + ".tmp-" + std::to_string(::getpid());
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | O_NOFOLLOW, 0666);
  if (fd < 0) {
    *error = what + errno_text(errno);
    return false;
  }
  auto fail_and_clean = [&](int err, bool close_fd) {
    if (close_fd) ::close(fd);
    ::unlink(tmp.c_str());
    *error = what + errno_text(err);
    return false;
  };
  static const uint8_t kZeros[64] = {};
  uint64_t pos = 0;
  auto put = [&](const void* data, uint64_t size) {
    if (!write_all(fd, data, size)) return false;
    pos += size;
    return true;
  };
  auto pad_to = [&](uint64_t target) {
    while (pos < target)
      if (!put(kZeros, std::min<uint64_t>(target - pos, sizeof(kZeros)))) return false;
    return true;
  };
  if (!put(&h, sizeof(h)) || !put(table.data(), table.size() * sizeof(SectionEntry)))
    return fail_and_clean(errno, true);
  for (uint32_t i = 0; i < n; ++i) {
    const uint8_t* stored =
        enc[i].codec == Codec::kRaw ? sections_[i].raw.data() : enc[i].stored.data();
    if (!pad_to(table[i].offset) || !put(stored, table[i].stored_size))
      return fail_and_clean(errno, true);
  }
  if (!pad_to(file_size)) return fail_and_clean(errno, true);
  if (::fsync(fd) != 0) return fail_and_clean(errno, true);
  if (::close(fd) != 0) return fail_and_clean(errno, false);
  if (::rename(tmp.c_str(), path.c_str()) != 0) return fail_and_clean(errno, false);
  // Make the rename itself durable. Best effort: the file is complete and in place either way.
  const size_t slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "."
                          : slash == 0               ? "/"
                                                     : path.substr(0, slash);
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }

  header_ = h;
  table_ = std::move(table);
  return true;
}

}  // namespace pbrta
