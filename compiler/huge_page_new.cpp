// The replaceable global operator new and delete, on heap_allocate and heap_release
// (format/huge_page_heap.h). Not part of the pbrta_format library: a program links the
// pbrta_huge_page_new object library to opt in.
#include <cstddef>
#include <new>

#include "format/huge_page_heap.h"

// The replaceable allocation functions. libstdc++ routes the array, nothrow and sized forms
// through these two; the aligned forms keep their own (aligned_alloc and free) pair.
void* operator new(std::size_t n) {
  return pbrta::heap_allocate(n);
}
void* operator new[](std::size_t n) {
  return pbrta::heap_allocate(n);
}
void operator delete(void* p) noexcept {
  pbrta::heap_release(p);
}
void operator delete[](void* p) noexcept {
  pbrta::heap_release(p);
}
void operator delete(void* p, std::size_t) noexcept {
  pbrta::heap_release(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  pbrta::heap_release(p);
}
