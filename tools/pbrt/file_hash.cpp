#include "tools/pbrt/file_hash.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <xxhash.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

namespace pbrt_tool {

namespace {

std::string hex(const XXH128_hash_t& h) {
  char b[33];
  std::snprintf(b, sizeof b, "%016llx%016llx", (unsigned long long)h.high64,
                (unsigned long long)h.low64);
  return b;
}

}  // namespace

bool stat_file(const std::string& path, FileStamp* stamp) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return false;
  stamp->size = uint64_t(st.st_size);
  stamp->mtime_ns = int64_t(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec;
  return true;
}

bool hash_file(const std::string& path, FileStamp* stamp, std::string* error) {
  int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    *error = "cannot read '" + path + "': " + std::strerror(errno);
    return false;
  }
  struct stat st {};
  ::fstat(fd, &st);
  stamp->size = uint64_t(st.st_size);
  stamp->mtime_ns = int64_t(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec;
  std::unique_ptr<XXH3_state_t, decltype(&XXH3_freeState)> state(XXH3_createState(),
                                                                 &XXH3_freeState);
  XXH3_128bits_reset(state.get());
  std::vector<char> block(size_t(1) << 20);
  for (;;) {
    ssize_t n = ::read(fd, block.data(), block.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      *error = "cannot read '" + path + "': " + std::strerror(errno);
      ::close(fd);
      return false;
    }
    if (n == 0) break;
    XXH3_128bits_update(state.get(), block.data(), size_t(n));
  }
  ::close(fd);
  stamp->hash = hex(XXH3_128bits_digest(state.get()));
  return true;
}

std::string hash_string(const std::string& bytes) {
  return hex(XXH3_128bits(bytes.data(), bytes.size()));
}

}  // namespace pbrt_tool
