#include "tools/pbrt/cached_compile.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>

#include "compiler/image_reader.h"
#include "runtime/core/clock.h"

namespace pbrt_tool {

namespace {

// This executable's size and modification time, and those of the image module it would load:
// a rebuilt compiler never reuses archives an older one wrote, whatever its version string says.
std::string executable_identity() {
  std::string id;
  for (const std::string& file : {std::string("/proc/self/exe"), pbrtc::image_module_file()}) {
    FileStamp st;
    id += file + "=" +
          (stat_file(file, &st) ? std::to_string(st.size) + ":" + std::to_string(st.mtime_ns)
                                : "unknown") +
          " ";
  }
  return id;
}

std::vector<ManifestInput> stamp_inputs(const std::vector<std::string>& paths, bool* ok) {
  std::vector<ManifestInput> inputs;
  *ok = true;
  for (const std::string& p : paths) {
    bool seen = false;
    for (const ManifestInput& m : inputs) seen |= m.path == p;
    if (seen) continue;
    ManifestInput m;
    m.path = p;
    std::string error;
    if (!hash_file(p, &m.stamp, &error)) *ok = false;
    inputs.push_back(std::move(m));
  }
  return inputs;
}

}  // namespace

const char* outcome_name(CacheOutcome o) {
  switch (o) {
    case CacheOutcome::kHit:
      return "hit";
    case CacheOutcome::kMiss:
      return "miss";
    case CacheOutcome::kRebuilt:
      return "rebuilt (corrupt)";
    case CacheOutcome::kOutdated:
      return "rebuilt (outdated)";
    case CacheOutcome::kBypassed:
      return "bypassed (--no-cache)";
  }
  return "?";
}

std::string manifest_key(const SceneSource& source) {
  std::string what = source.is_stdin()
                         ? "stdin " + hash_string(source.text) + " in " + absolute_path(".")
                         : "file " + absolute_path(source.path);
  return hash_string(what + "\n" + compile_options_key() + "\n" + executable_identity());
}

std::unique_ptr<pbrta::SceneArchive> obtain_archive(const SceneSource& source, SceneCache* cache,
                                                    int threads, bool quiet, ObtainStats* stats) {
  auto archive = std::make_unique<pbrta::SceneArchive>();
  archive->skip_source_texels();  // it renders
  std::string error;
  std::vector<std::string> inputs;
  if (!cache) {
    stats->outcome = CacheOutcome::kBypassed;
    const char* tmpdir = std::getenv("TMPDIR");
    std::string path = std::string(tmpdir && *tmpdir ? tmpdir : "/tmp") + "/pbrt-XXXXXX";
    int fd = ::mkstemp(path.data());
    if (fd < 0) {
      std::cerr << "pbrt: error: cannot create a temporary file in " << path << "\n";
      return nullptr;
    }
    ::close(fd);
    auto t0 = std::chrono::steady_clock::now();
    bool ok = compile_scene(source, path, threads, quiet, &inputs);
    stats->compile_seconds = rt::seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    ok = ok && archive->load(path, threads, &error);
    stats->load_seconds = rt::seconds_since(t0);
    std::remove(path.c_str());
    if (!ok) {
      if (!error.empty()) std::cerr << "pbrt: error: " << error << "\n";
      return nullptr;
    }
    return archive;
  }

  const std::string key = manifest_key(source);
  stats->outcome = CacheOutcome::kMiss;
  {
    auto t0 = std::chrono::steady_clock::now();
    SceneCache::Lock lock(*cache, SceneCache::kShared);
    std::string path = cache->lookup(key);
    stats->lookup_seconds = rt::seconds_since(t0);
    if (!path.empty()) {
      t0 = std::chrono::steady_clock::now();
      bool ok = archive->load(path, threads, &error);
      stats->load_seconds = rt::seconds_since(t0);
      if (ok) {
        stats->outcome = CacheOutcome::kHit;
        stats->archive_path = path;
        return archive;
      }
      // The reader's words for an archive of another major version (format/archive_reader.cpp).
      const bool outdated = error.find(": archive version ") != std::string::npos;
      if (!quiet)
        std::cerr << "pbrt: cache entry " << path << (outdated ? " is outdated (" : " is corrupt (")
                  << error << "); deleted, recompiling\n";
      cache->discard(key, path);
      stats->outcome = outdated ? CacheOutcome::kOutdated : CacheOutcome::kRebuilt;
      archive = std::make_unique<pbrta::SceneArchive>();
      archive->skip_source_texels();
    }
  }

  // Compile without the lock: it may take minutes, and other users only need it to evict.
  std::string temp = cache->temp_path(".pbrta");
  auto t0 = std::chrono::steady_clock::now();
  bool ok = compile_scene(source, temp, threads, quiet, &inputs);
  stats->compile_seconds = rt::seconds_since(t0);
  if (!ok) {
    std::remove(temp.c_str());
    return nullptr;
  }
  bool stamped;
  std::vector<ManifestInput> manifest = stamp_inputs(inputs, &stamped);
  {
    SceneCache::Lock lock(*cache, SceneCache::kShared);
    std::string path;
    if (stamped) {
      if (!cache->store(key, temp, manifest, &path, &error)) {
        std::cerr << "pbrt: warning: " << error << "\n";
        path = temp;  // still render what was compiled
      }
    } else {
      path = temp;  // an input vanished since the compile read it: do not record it
    }
    t0 = std::chrono::steady_clock::now();
    ok = archive->load(path, threads, &error);
    stats->load_seconds = rt::seconds_since(t0);
    if (path == temp) std::remove(temp.c_str());
    stats->archive_path = path == temp ? "" : path;
  }
  if (!ok) {
    std::cerr << "pbrt: error: " << error << "\n";
    return nullptr;
  }
  cache->evict();
  return archive;
}

}  // namespace pbrt_tool
