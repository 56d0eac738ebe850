// compiler/huge_page_heap.h — C++ heap blocks of 1 MiB and more in transparent huge pages, for
// the programs that parse scenes (pbrtc, pbrt, the mesh tools, the benchmarks).
//
// Why: on the virtual machines this project runs on, the first touch of a fresh 4 KiB page costs
// microseconds, and parsing a 200 MB scene writes hundreds of MB of fresh arrays (the lexer's
// pooled number arrays, the meshes they become): in base pages, over half of that parse went to
// the page-fault path. Kernels default to THP "madvise", where only memory advised so gets huge
// pages; glibc's allocator asks for them only under a tunable read at process start.
//
// How: heap_allocate gives a block of kHugeHeapBlock bytes or more a mapping of its own from
// map_huge() (format/huge_pages.h), with a 64-byte header saying so, and smaller ones come from
// malloc, whose main heap grows in 32 MiB steps that are advised as they come (what glibc's
// tunable does). compiler/huge_page_new.cpp replaces the global operator new and delete (C++'s
// replaceable allocation functions) with these two; it is not part of the pbrtc_lib library:
// a program opts in by linking the pbrtc_huge_page_new object library (CMakeLists.txt): the
// parsing programs and pbrt (which renders too); pbrtrun, whose big buffers are advised where
// they are made, keeps the standard allocator.
//
// PBRT_HUGE_PAGES=0 in the environment turns it off (every block from malloc). Where THP is
// disabled the mappings are ordinary memory. Memory from malloc must still go to free() and
// memory from new to delete, as always.
#pragma once

#include <cstddef>

namespace pbrtc {

// A block of this many bytes or more starts 64 bytes past a huge-page boundary (unless turned
// off, or the mapping failed and malloc gave it).
inline constexpr size_t kHugeHeapBlock = size_t{1} << 20;

// As operator new: a block of n bytes (16-byte aligned), or std::bad_alloc.
void* heap_allocate(size_t n);
// Frees a block from heap_allocate (nullptr: nothing).
void heap_release(void* p) noexcept;

}  // namespace pbrtc
