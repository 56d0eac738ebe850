// tools/pbrt/file_hash.h — content hashes for the compiled-scene cache.
//
// XXH3-128 of a file's bytes (read in 1 MiB blocks, so a multi-gigabyte mesh never sits in
// memory) with the size and modification time seen when it was read, and of strings. Hashes
// print as 32 lower-case hex digits: the cache's file names and manifest fields.
#pragma once

#include <cstdint>
#include <string>

namespace pbrt_tool {

struct FileStamp {
  uint64_t size = 0;
  int64_t mtime_ns = 0;
  std::string hash;  // 32 hex digits
};

// False with *error when the file cannot be read.
bool hash_file(const std::string& path, FileStamp* stamp, std::string* error);
// Size and modification time only (no read).
bool stat_file(const std::string& path, FileStamp* stamp);
std::string hash_string(const std::string& bytes);

}  // namespace pbrt_tool
