#include "compiler/compile_progress.h"

#include <unistd.h>

#include <cstdio>

namespace pbrtc {

TerminalProgress::TerminalProgress(std::string label)
    : label_(std::move(label)),
      enabled_(isatty(STDERR_FILENO) == 1),
      last_(std::chrono::steady_clock::now()) {}

void TerminalProgress::shapes(const SceneDesc& scene) {
  if (!enabled_ || !due()) return;
  show(std::to_string(scene.shapes.size()) + " shapes");
}

void TerminalProgress::phase(const char* name, size_t items) {
  if (!enabled_ || items == 0) return;  // a scene with no image has no "images (0)" step
  last_ = std::chrono::steady_clock::now();
  show(std::string(name) + " (" + std::to_string(items) + ")");
}

void TerminalProgress::encoded(uint64_t done, uint64_t total) {
  if (!enabled_ || (done < total && !due())) return;
  char what[96];
  if (total >= 1000000)
    std::snprintf(what, sizeof what, "Draco meshes, %.2f of %.2f M triangles", double(done) / 1e6,
                  double(total) / 1e6);
  else
    std::snprintf(what, sizeof what, "Draco meshes, %llu of %llu triangles",
                  static_cast<unsigned long long>(done), static_cast<unsigned long long>(total));
  show(what);
}

void TerminalProgress::compressed(uint64_t done, uint64_t total) {
  if (!enabled_ || (done < total && !due())) return;
  // KiB below 1 MiB: what is left to zstd after Draco is often that small.
  const bool mib = total >= (1 << 20);
  const double unit = mib ? 1 << 20 : 1 << 10;
  char what[96];
  std::snprintf(what, sizeof what, "compressing, %.1f of %.1f %s", double(done) / unit,
                double(total) / unit, mib ? "MiB" : "KiB");
  show(what);
}

void TerminalProgress::finish() {
  if (enabled_ && shown_) std::fprintf(stderr, "\r\033[K");
  shown_ = false;
}

bool TerminalProgress::due() {
  const auto now = std::chrono::steady_clock::now();
  if (now - last_ < std::chrono::milliseconds(250)) return false;
  last_ = now;
  return true;
}

void TerminalProgress::show(const std::string& what) {
  std::fprintf(stderr, "\r\033[K%s: %s", label_.c_str(), what.c_str());
  std::fflush(stderr);
  shown_ = true;
}

}  // namespace pbrtc
