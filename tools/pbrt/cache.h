// tools/pbrt/cache.h — the cache of compiled scene archives ($XDG_CACHE_HOME/pbrtc).
//
// Layout: archives/<content key>.pbrta, manifests/<manifest key>.manifest, lock.
// A manifest key names what was asked for (the top-level scene's absolute path, or
// the hash of standard input and the working directory, with the compiler's version
// and the compile options); its manifest lists every input file the compile read
// (size, mtime, XXH3-128 of the content) and the archive's content key (a hash of
// the manifest key and every input's path and content hash). A lookup re-hashes the
// inputs: a size or content change is a miss; an mtime change with the same content
// is a hit, and the manifest is refreshed (a `touch` alone does not recompile).
//
// Concurrency: archives and manifests are written to temporary files in the cache and
// renamed into place, so readers only ever see whole files and two writers of the same
// entry both succeed (the later rename wins; both wrote the same bytes). Holders of a
// Lock(kShared) may open archives; eviction takes the lock exclusively, so an archive is
// never deleted between a lookup and its load (once opened, deleting it is harmless).
// Eviction deletes least-recently-used files (hits touch the archive and the manifest)
// until the cache's total size is at most the cap, and temporary files older than an
// hour (left by killed writers).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "tools/pbrt/file_hash.h"

namespace pbrt_tool {

struct ManifestInput {
  std::string path;  // absolute
  FileStamp stamp;
};

class SceneCache {
 public:
  SceneCache(std::string dir, uint64_t cap_bytes);
  ~SceneCache();
  SceneCache(const SceneCache&) = delete;
  SceneCache& operator=(const SceneCache&) = delete;

  // $XDG_CACHE_HOME/pbrtc, else $HOME/.cache/pbrtc.
  static std::string default_dir();

  // Creates the directories and opens the lock file.
  bool open(std::string* error);

  enum LockMode { kShared, kExclusive };
  // Holds the cache lock while alive.
  class Lock {
   public:
    Lock(const SceneCache& cache, LockMode mode);
    ~Lock();
    Lock(const Lock&) = delete;
    Lock& operator=(const Lock&) = delete;

   private:
    int fd_;
  };

  // The archive recorded for manifest_key if every input is unchanged, else "".
  // Hold a shared Lock from the lookup through opening the archive.
  std::string lookup(const std::string& manifest_key);
  // A fresh temporary file name inside the cache (same file system as the archives).
  std::string temp_path(const std::string& suffix) const;
  // Moves the archive written at temp into place and records the manifest.
  bool store(const std::string& manifest_key, const std::string& temp,
             const std::vector<ManifestInput>& inputs, std::string* archive_path,
             std::string* error);
  // Deletes an entry whose archive failed to load.
  void discard(const std::string& manifest_key, const std::string& archive_path);
  // Evicts least-recently-used files until the cache fits its cap (takes the lock itself).
  void evict();

  // Total bytes of archives and manifests now in the cache.
  uint64_t size_bytes() const;
  const std::string& dir() const { return dir_; }

  static std::string content_key(const std::string& manifest_key,
                                 const std::vector<ManifestInput>& inputs);

 private:
  std::string manifest_path(const std::string& key) const;
  bool write_manifest(const std::string& key, const std::string& content,
                      const std::vector<ManifestInput>& inputs);

  std::string dir_;
  uint64_t cap_bytes_;
  int lock_fd_ = -1;
};

}  // namespace pbrt_tool
