// format/huge_page_heap.h — back the C/C++ heap with transparent huge pages.
//
// On the virtual machines this project runs on, the first touch of a fresh
// 4 KiB page costs microseconds, and a mesh-heavy compile or load touches
// hundreds of megabytes of fresh heap: parsing a 200 MB scene spent more than
// half its time in the page-fault path, and Embree's build of a 4M-triangle
// scene about as much. glibc (2.35 and later) can ask for transparent huge
// pages for its heap and large chunks (`glibc.malloc.hugetlb=1`), but reads
// that tunable only at process start, from the environment.
//
// use_huge_page_heap(argv), called first thing in main(), re-executes the
// program once (same argv, same fds, via /proc/self/exe) with the tunable
// added to GLIBC_TUNABLES. It returns without doing anything when the tunable
// is already set (so there is at most one re-exec), when PBRT_HUGE_PAGES=0 is
// set, or when the exec fails (the program then runs with the ordinary heap).
// Where THP is disabled or the glibc is older, the tunable is simply ignored.
#pragma once

namespace pbrta {

void use_huge_page_heap(char** argv);

}  // namespace pbrta
