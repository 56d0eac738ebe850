// runtime/core/clock.h — wall-clock seconds for the timings that --stats,
// the cache report and the benchmarks print.
#pragma once

#include <chrono>

namespace rt {

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace rt
