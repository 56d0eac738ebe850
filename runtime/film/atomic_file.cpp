// runtime/film/atomic_file.cpp — see atomic_file.h.
#include "runtime/film/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace rt {

std::string temporary_name(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  std::filesystem::path p(path);
  std::string name = "." + p.filename().string() + ".tmp" + std::to_string(getpid()) + "-" +
                     std::to_string(counter.fetch_add(1));
  return (p.parent_path() / name).string();
}

bool commit_file(const std::string& tmp, const std::string& path, const std::string& what,
                 std::string* error) {
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    *error = path + ": cannot rename the finished " + what + " into place: " + std::strerror(errno);
    std::remove(tmp.c_str());
    return false;
  }
  return true;
}

bool check_writable(const std::string& path, const std::string& what, std::string* error) {
  const std::string probe = temporary_name(path);
  FILE* f = std::fopen(probe.c_str(), "wb");
  if (!f) {
    *error = path + ": cannot write the " + what + " there: " + std::strerror(errno);
    return false;
  }
  std::fclose(f);
  std::remove(probe.c_str());
  return true;
}

bool write_file_atomically(const std::string& path, const std::string& bytes,
                           const std::string& what, std::string* error) {
  const std::string tmp = temporary_name(path);
  FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) {
    *error = path + ": cannot create the " + what + ": " + std::strerror(errno);
    return false;
  }
  const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  const int saved = errno;
  if (std::fclose(f) != 0 || !ok) {
    *error = path + ": cannot write the " + what + ": " + std::strerror(ok ? errno : saved);
    std::remove(tmp.c_str());
    return false;
  }
  return commit_file(tmp, path, what, error);
}

}  // namespace rt
