// The replaceable global operator new and delete, on heap_allocate and heap_release
// (compiler/huge_page_heap.h). Not part of the pbrtc_lib library: a program links the
// pbrtc_huge_page_new object library to opt in.
#include <cstddef>
#include <new>

#include "compiler/huge_page_heap.h"

// The replaceable allocation functions. libstdc++ routes the array, nothrow and sized forms
// through these two; the aligned forms keep their own (aligned_alloc and free) pair.
void* operator new(std::size_t n) {
  return pbrtc::heap_allocate(n);
}
void* operator new[](std::size_t n) {
  return pbrtc::heap_allocate(n);
}
void operator delete(void* p) noexcept {
  pbrtc::heap_release(p);
}
void operator delete[](void* p) noexcept {
  pbrtc::heap_release(p);
}
void operator delete(void* p, std::size_t) noexcept {
  pbrtc::heap_release(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  pbrtc::heap_release(p);
}
