#include "compiler/source_files.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace pbrtc {

struct SourceFiles::File {
  std::string display_path;
  Loc included_from;
  // Either a mapping or an owned string holds the bytes.
  void* map = nullptr;
  size_t map_size = 0;
  std::string owned;
  std::string_view text;
  // Byte offsets of line starts, built on the first line_col() call.
  mutable std::vector<uint64_t> line_starts;

  ~File() {
    if (map) munmap(map, map_size);
  }
};

SourceFiles::SourceFiles() = default;
SourceFiles::~SourceFiles() = default;

uint32_t SourceFiles::open(const std::string& path, const std::string& display_path,
                           Loc included_from, std::string* error) {
  int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    *error = std::strerror(errno);
    return kNoFile;
  }
  struct stat st;
  if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    *error = S_ISDIR(st.st_mode) ? "is a directory" : "not a regular file";
    ::close(fd);
    return kNoFile;
  }
  auto f = std::make_unique<File>();
  f->display_path = display_path;
  f->included_from = included_from;
  if (st.st_size > 0) {
    // MAP_POPULATE maps every page in one call: much cheaper than a page fault
    // per 64 KiB of a large scene file, and the whole file is read anyway.
    void* m = mmap(nullptr, size_t(st.st_size), PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
    if (m == MAP_FAILED) {
      *error = std::strerror(errno);
      ::close(fd);
      return kNoFile;
    }
    // Sequential scan: ask the kernel to read ahead aggressively.
    madvise(m, size_t(st.st_size), MADV_SEQUENTIAL);
    f->map = m;
    f->map_size = size_t(st.st_size);
    f->text = std::string_view(static_cast<const char*>(m), f->map_size);
  }
  ::close(fd);
  files_.push_back(std::move(f));
  return uint32_t(files_.size() - 1);
}

uint32_t SourceFiles::add_memory(std::string display_path, std::string text, Loc included_from) {
  auto f = std::make_unique<File>();
  f->display_path = std::move(display_path);
  f->included_from = included_from;
  f->owned = std::move(text);
  f->text = f->owned;
  files_.push_back(std::move(f));
  return uint32_t(files_.size() - 1);
}

std::string_view SourceFiles::text(uint32_t file) const {
  return files_[file]->text;
}
const std::string& SourceFiles::display_path(uint32_t file) const {
  return files_[file]->display_path;
}
Loc SourceFiles::included_from(uint32_t file) const {
  return files_[file]->included_from;
}
size_t SourceFiles::size() const {
  return files_.size();
}

LineCol SourceFiles::line_col(Loc loc) const {
  if (!loc.valid() || loc.file >= files_.size()) return {};
  const File& f = *files_[loc.file];
  if (f.line_starts.empty()) {
    f.line_starts.push_back(0);
    const char* base = f.text.data();
    const char* p = base;
    const char* end = base + f.text.size();
    while (p < end) {
      const void* nl = std::memchr(p, '\n', size_t(end - p));
      if (!nl) break;
      p = static_cast<const char*>(nl) + 1;
      f.line_starts.push_back(uint64_t(p - base));
    }
  }
  auto it = std::upper_bound(f.line_starts.begin(), f.line_starts.end(), loc.offset);
  size_t line = size_t(it - f.line_starts.begin());  // 1-based
  uint64_t start = f.line_starts[line - 1];
  return {uint32_t(line), uint32_t(loc.offset - start + 1)};
}

std::string SourceFiles::format(Loc loc) const {
  if (!loc.valid()) return "<command line>";
  LineCol lc = line_col(loc);
  return display_path(loc.file) + ":" + std::to_string(lc.line) + ":" + std::to_string(lc.column);
}

}  // namespace pbrtc
