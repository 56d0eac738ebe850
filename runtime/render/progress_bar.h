// runtime/render/progress_bar.h — the "Rendering: [+++   ] 40.0% (3.1s|4.6s ETA)" line on stderr.
//
// Counts units of work (tiles, passes) towards a total; add() is thread-safe and
// cheap (one relaxed atomic add), so workers call it as they finish. A
// background thread redraws the line every 250 ms; finish() (or the
// destructor) draws it once more at its final value and ends the line. Quiet:
// no thread, no output. set_note() appends text to the line (the render's error
// estimate); with replaces_eta the note carries its own ETA and the bar's is not shown;
// the bar then shows at least `fraction` done (the way to a target error).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

namespace rt {

class ProgressBar {
 public:
  ProgressBar(int64_t total, bool quiet);
  ~ProgressBar() { finish(); }
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  void add(int64_t n) { done_.fetch_add(n, std::memory_order_relaxed); }
  void finish();
  void set_note(const std::string& note, bool replaces_eta, double fraction = 0);

 private:
  void loop();
  void print(bool final);

  std::atomic<int64_t> done_{0};
  std::string note_;  // under m_
  bool note_replaces_eta_ = false;
  double fraction_floor_ = 0;
  int64_t total_;
  bool stop_ = false;
  std::mutex m_;
  std::condition_variable cv_;
  std::thread thread_;
  std::chrono::steady_clock::time_point t0_ = std::chrono::steady_clock::now();
};

}  // namespace rt
