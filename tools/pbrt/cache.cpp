#include "tools/pbrt/cache.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <sstream>

namespace pbrt_tool {

namespace {

constexpr const char* kManifestMagic = "pbrt-cache-manifest 1";

bool make_dirs(const std::string& path, std::string* error) {
  for (size_t i = 1; i <= path.size(); ++i) {
    if (i < path.size() && path[i] != '/') continue;
    std::string part = path.substr(0, i);
    if (::mkdir(part.c_str(), 0777) != 0 && errno != EEXIST) {
      *error = "cannot create cache directory '" + part + "': " + std::strerror(errno);
      return false;
    }
  }
  return true;
}

// Marks a file as just used, for least-recently-used eviction.
void touch(const std::string& path) {
  ::utimensat(AT_FDCWD, path.c_str(), nullptr, 0);
}

struct CacheFile {
  std::string path;
  uint64_t size;
  int64_t mtime_ns;
  bool temp;
};

std::vector<CacheFile> list_files(const std::string& dir) {
  std::vector<CacheFile> out;
  DIR* d = ::opendir(dir.c_str());
  if (!d) return out;
  while (dirent* e = ::readdir(d)) {
    std::string name = e->d_name;
    if (name == "." || name == "..") continue;
    FileStamp st;
    std::string path = dir + "/" + name;
    if (!stat_file(path, &st)) continue;  // deleted meanwhile by another user
    out.push_back({path, st.size, st.mtime_ns, name.rfind(".tmp-", 0) == 0});
  }
  ::closedir(d);
  return out;
}

}  // namespace

SceneCache::SceneCache(std::string dir, uint64_t cap_bytes)
    : dir_(std::move(dir)), cap_bytes_(cap_bytes) {}

SceneCache::~SceneCache() {
  if (lock_fd_ >= 0) ::close(lock_fd_);
}

std::string SceneCache::default_dir() {
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  if (xdg && *xdg == '/') return std::string(xdg) + "/pbrtc";
  const char* home = std::getenv("HOME");
  return std::string(home && *home ? home : "/tmp") + "/.cache/pbrtc";
}

bool SceneCache::open(std::string* error) {
  if (!make_dirs(dir_ + "/archives", error) || !make_dirs(dir_ + "/manifests", error)) return false;
  lock_fd_ = ::open((dir_ + "/lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
  if (lock_fd_ < 0) {
    *error = "cannot open cache lock '" + dir_ + "/lock': " + std::strerror(errno);
    return false;
  }
  return true;
}

SceneCache::Lock::Lock(const SceneCache& cache, LockMode mode) : fd_(cache.lock_fd_) {
  while (fd_ >= 0 && ::flock(fd_, mode == kShared ? LOCK_SH : LOCK_EX) != 0 && errno == EINTR) {
  }
}

SceneCache::Lock::~Lock() {
  if (fd_ >= 0) ::flock(fd_, LOCK_UN);
}

std::string SceneCache::manifest_path(const std::string& key) const {
  return dir_ + "/manifests/" + key + ".manifest";
}

std::string SceneCache::temp_path(const std::string& suffix) const {
  static std::atomic<unsigned> counter{0};
  char b[96];
  std::snprintf(b, sizeof b, "/archives/.tmp-%ld-%lx-%u", long(::getpid()),
                long(std::time(nullptr)), counter++);
  return dir_ + b + suffix;
}

std::string SceneCache::content_key(const std::string& manifest_key,
                                    const std::vector<ManifestInput>& inputs) {
  std::string all = manifest_key + "\n";
  for (const ManifestInput& in : inputs) all += in.stamp.hash + " " + in.path + "\n";
  return hash_string(all);
}

std::string SceneCache::lookup(const std::string& manifest_key) {
  std::ifstream in(manifest_path(manifest_key));
  std::string line, content;
  if (!std::getline(in, line) || line != kManifestMagic) return "";
  if (!std::getline(in, line) || line.rfind("archive ", 0) != 0) return "";
  content = line.substr(8);
  std::vector<ManifestInput> inputs;
  bool moved = false;  // same content, new mtime: refresh the manifest
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string tag;
    ManifestInput m;
    ls >> tag >> m.stamp.size >> m.stamp.mtime_ns >> m.stamp.hash;
    if (tag != "input" || !ls || ls.get() != ' ') return "";
    std::getline(ls, m.path);
    FileStamp now;
    std::string error;
    if (!stat_file(m.path, &now) || now.size != m.stamp.size) return "";
    if (!hash_file(m.path, &now, &error) || now.hash != m.stamp.hash) return "";
    moved |= now.mtime_ns != m.stamp.mtime_ns;
    m.stamp = now;
    inputs.push_back(std::move(m));
  }
  std::string archive = dir_ + "/archives/" + content + ".pbrta";
  if (::access(archive.c_str(), R_OK) != 0) return "";
  if (moved) write_manifest(manifest_key, content, inputs);
  touch(archive);
  touch(manifest_path(manifest_key));
  return archive;
}

bool SceneCache::write_manifest(const std::string& key, const std::string& content,
                                const std::vector<ManifestInput>& inputs) {
  std::string text = std::string(kManifestMagic) + "\narchive " + content + "\n";
  for (const ManifestInput& m : inputs)
    text += "input " + std::to_string(m.stamp.size) + " " + std::to_string(m.stamp.mtime_ns) + " " +
            m.stamp.hash + " " + m.path + "\n";
  std::string tmp = temp_path(".manifest");
  {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    if (!out.flush()) {
      std::remove(tmp.c_str());
      return false;
    }
  }
  if (std::rename(tmp.c_str(), manifest_path(key).c_str()) != 0) {
    std::remove(tmp.c_str());
    return false;
  }
  return true;
}

bool SceneCache::store(const std::string& manifest_key, const std::string& temp,
                       const std::vector<ManifestInput>& inputs, std::string* archive_path,
                       std::string* error) {
  std::string content = content_key(manifest_key, inputs);
  *archive_path = dir_ + "/archives/" + content + ".pbrta";
  if (std::rename(temp.c_str(), archive_path->c_str()) != 0) {
    *error = "cannot store '" + *archive_path + "' in the cache: " + std::strerror(errno);
    std::remove(temp.c_str());
    return false;
  }
  if (!write_manifest(manifest_key, content, inputs)) {
    *error = "cannot write a manifest in '" + dir_ + "/manifests'";
    return false;
  }
  return true;
}

void SceneCache::discard(const std::string& manifest_key, const std::string& archive_path) {
  std::remove(archive_path.c_str());
  std::remove(manifest_path(manifest_key).c_str());
}

uint64_t SceneCache::size_bytes() const {
  uint64_t total = 0;
  for (const char* sub : {"/archives", "/manifests"})
    for (const CacheFile& f : list_files(dir_ + sub)) total += f.size;
  return total;
}

void SceneCache::evict() {
  Lock lock(*this, kExclusive);
  std::vector<CacheFile> files = list_files(dir_ + "/archives");
  std::vector<CacheFile> manifests = list_files(dir_ + "/manifests");
  files.insert(files.end(), manifests.begin(), manifests.end());
  const int64_t stale_ns = (int64_t(std::time(nullptr)) - 3600) * 1000000000;
  uint64_t total = 0;
  std::vector<CacheFile> live;
  for (const CacheFile& f : files) {
    if (f.temp && f.mtime_ns < stale_ns) {
      std::remove(f.path.c_str());
      continue;
    }
    total += f.size;
    // A recent temporary file is another user's archive being written: not ours to delete.
    if (!f.temp) live.push_back(f);
  }
  if (total <= cap_bytes_) return;
  std::sort(live.begin(), live.end(),
            [](const CacheFile& a, const CacheFile& b) { return a.mtime_ns < b.mtime_ns; });
  for (const CacheFile& f : live) {
    if (total <= cap_bytes_) break;
    if (std::remove(f.path.c_str()) == 0) total -= f.size;
  }
}

}  // namespace pbrt_tool
