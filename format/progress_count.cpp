#include "format/progress_count.h"

namespace pbrta {

void ProgressCount::add(uint64_t amount) {
  done_ += amount;
  if (!report_) return;
  std::unique_lock<std::mutex> lock(reporting_, std::try_to_lock);
  if (!lock) return;
  const uint64_t done = done_.load();
  if (done < total_) report_(done, total_);
}

void ProgressCount::finish() {
  if (report_ && total_ > 0) report_(total_, total_);
}

}  // namespace pbrta
