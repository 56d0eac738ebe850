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

// The same on a plain float that other threads add to as well (the film's splats in a
// one-pass render), with the compiler's atomic builtins.
inline void atomic_add(float* a, float v) {
  float old;
  __atomic_load(a, &old, __ATOMIC_RELAXED);
  float sum = old + v;
  while (!__atomic_compare_exchange(a, &old, &sum, true, __ATOMIC_RELAXED, __ATOMIC_RELAXED))
    sum = old + v;
}

}  // namespace rt
