// runtime/core/atomic_add.h — adding to an atomic float or double from many threads.
//
// std::atomic<double> has fetch_add only from C++20; the film's pending splats and sppm's
// photon sums add with a compare-and-swap loop, relaxed: only the final sum is read, after
// the threads have joined.
#pragma once

#include <atomic>

namespace rt {

template <typename T>
inline void atomic_add(std::atomic<T>* a, typename std::atomic<T>::value_type v) {
  T old = a->load(std::memory_order_relaxed);
  while (!a->compare_exchange_weak(old, old + v, std::memory_order_relaxed)) {
  }
}

}  // namespace rt
