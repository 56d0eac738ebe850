// runtime/core/atomic_add.h — adding to an atomic double from many threads.
//
// std::atomic<double> has fetch_add only from C++20; the film's splats and sppm's photon
// sums add with a compare-and-swap loop, relaxed: only the final sum is read, after the
// threads have joined.
#pragma once

#include <atomic>

namespace rt {

inline void atomic_add(std::atomic<double>* a, double v) {
  double old = a->load(std::memory_order_relaxed);
  while (!a->compare_exchange_weak(old, old + v, std::memory_order_relaxed)) {
  }
}

}  // namespace rt
