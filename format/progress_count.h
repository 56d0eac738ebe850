// format/progress_count.h — work counted on many threads, for a progress display.
//
// ProgressCount adds up work as threads finish pieces of it and passes the running total to
// `report` (done, total). A display, not a log: calls never overlap, a thread that finds another
// reporting goes on without waiting, the count is read under the lock so done never goes down,
// and finish() makes the last call, with done == total. With no report function, or a total of
// 0, it reports nothing.
// Thread safety: add() from any number of threads; finish() once, after every add().
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <utility>

namespace pbrta {

class ProgressCount {
 public:
  using Report = std::function<void(uint64_t done, uint64_t total)>;
  ProgressCount(uint64_t total, Report report) : total_(total), report_(std::move(report)) {}
  void add(uint64_t amount);
  void finish();

 private:
  const uint64_t total_;
  const Report report_;
  std::atomic<uint64_t> done_{0};
  std::mutex reporting_;
};

}  // namespace pbrta
