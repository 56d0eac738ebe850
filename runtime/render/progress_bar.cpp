// runtime/render/progress_bar.cpp — see progress_bar.h.
#include "runtime/render/progress_bar.h"

#include <algorithm>
#include <cstdio>

#include "runtime/core/clock.h"

namespace rt {

ProgressBar::ProgressBar(int64_t total, bool quiet) : total_(total) {
  if (!quiet) thread_ = std::thread([this] { loop(); });
}

void ProgressBar::finish() {
  if (!thread_.joinable()) return;
  {
    std::lock_guard<std::mutex> lock(m_);
    stop_ = true;
  }
  cv_.notify_all();
  thread_.join();
  print(true);
  std::fputc('\n', stderr);
}

void ProgressBar::set_note(const std::string& note, bool replaces_eta, double fraction) {
  std::lock_guard<std::mutex> lock(m_);
  note_ = note;
  note_replaces_eta_ = replaces_eta;
  fraction_floor_ = std::min(1.0, fraction);
}

void ProgressBar::loop() {
  std::unique_lock<std::mutex> lock(m_);
  while (!cv_.wait_for(lock, std::chrono::milliseconds(250), [this] { return stop_; }))
    print(false);
}

void ProgressBar::print(bool final) {
  double elapsed = seconds_since(t0_);
  // m_ is held: loop() calls this under it, and finish() after the thread has ended.
  double f = std::max(fraction_floor_, total_ > 0 ? double(done_.load()) / double(total_) : 1);
  const int width = 40;
  int bars = int(f * width);
  char bar[width + 1];
  for (int i = 0; i < width; ++i) bar[i] = i < bars ? '+' : ' ';
  bar[width] = 0;
  const std::string& note = note_;
  const bool own_eta = note_replaces_eta_;
  if (final || f >= 1 || f <= 0 || own_eta)
    std::fprintf(stderr, "\rRendering: [%s] %5.1f%% (%.1fs) %s        ", bar, 100 * f, elapsed,
                 note.c_str());
  else
    std::fprintf(stderr, "\rRendering: [%s] %5.1f%% (%.1fs|%.1fs ETA) %s  ", bar, 100 * f, elapsed,
                 elapsed / f - elapsed, note.c_str());
  std::fflush(stderr);
}

}  // namespace rt
