// tools/pbrt/cached_compile.h — a scene's archive, from the cache or freshly compiled.
//
// With a cache: look the scene up (tools/pbrt/cache.h) and load the archive found; if
// it fails to load the entry is deleted, the scene recompiled and the outcome is kRebuilt
// (checksums, validation) or kOutdated (an archive version this pbrtc does not read: entries are
// keyed by the archive version, so only an entry edited or copied in by hand gets there). On a miss
// the scene is compiled to a temporary file in the cache, moved into place, loaded, and the cache
// evicted down to its cap. Without a cache the archive is compiled to a temporary file that is
// deleted once loaded (the loaded archive maps it, so it stays readable until the SceneArchive
// dies). Returns null after printing why on stderr (compile errors as "file:line:col: error:").
#pragma once

#include <memory>
#include <string>

#include "format/scene_archive.h"
#include "tools/pbrt/cache.h"
#include "tools/pbrt/scene_compile.h"

namespace pbrt_tool {

enum class CacheOutcome { kHit, kMiss, kRebuilt, kOutdated, kBypassed };
// "hit", "miss", "rebuilt (corrupt)", "rebuilt (outdated)", "bypassed"
const char* outcome_name(CacheOutcome o);

struct ObtainStats {
  CacheOutcome outcome = CacheOutcome::kBypassed;
  double lookup_seconds = 0, compile_seconds = 0, load_seconds = 0;
  std::string archive_path;  // in the cache ("" when bypassed)
};

std::unique_ptr<pbrta::SceneArchive> obtain_archive(const SceneSource& source, SceneCache* cache,
                                                    int threads, bool quiet, ObtainStats* stats);

// The key of a scene's manifest: what was asked for, the compiler and its options.
std::string manifest_key(const SceneSource& source);

}  // namespace pbrt_tool
