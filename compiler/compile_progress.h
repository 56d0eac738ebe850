// compiler/compile_progress.h — a compile's progress, shown on a terminal.
//
// TerminalProgress shows what build_scene (BuildProgress) and write_archive (ArchiveProgress)
// report on one line of stderr, rewritten in place and prefixed with a label (the scene's path):
// the shape count as the scene builds, each phase with its item count ("PLY meshes (12)"), the
// Draco triangles encoded and the bytes compressed. Counts are redrawn at most 4 times a second;
// a phase with no items is not shown. finish() erases the line, so whatever is printed next (a
// summary, a diagnostic, a render's progress bar) stands alone. Silent when stderr is not a
// terminal, so logs and pipes get none of it.
// Thread safety: as the two interfaces promise their callers, one call at a time.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

#include "compiler/archive_builder.h"
#include "compiler/scene_builder.h"

namespace pbrtc {

// One phase() overrides both interfaces' (the same signature).
class TerminalProgress : public BuildProgress, public ArchiveProgress {
 public:
  explicit TerminalProgress(std::string label);
  void shapes(const SceneDesc& scene) override;
  void phase(const char* name, size_t items) override;
  void encoded(uint64_t done, uint64_t total) override;
  void compressed(uint64_t done, uint64_t total) override;
  // Erases the line if anything was shown.
  void finish();

 private:
  bool due();
  void show(const std::string& what);
  std::string label_;
  bool enabled_;
  bool shown_ = false;
  std::chrono::steady_clock::time_point last_;
};

}  // namespace pbrtc
