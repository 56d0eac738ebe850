// format/huge_pages.h — transparent huge pages for the large buffers a program is about to fill.
//
// Why: on the virtual machines this project runs on, the first touch of a fresh 4 KiB page costs
// microseconds, and a mesh-heavy compile or load writes hundreds of megabytes of fresh memory
// (decoding an archive into 4 KiB pages measured 10x slower than into huge pages). Kernels default
// to THP "madvise": only memory advised so gets huge pages. The parser's pooled arrays
// (compiler/params.cpp) and the archive's decode buffers (format/archive_reader.h) are advised
// here; the heap of the parsing programs by compiler/huge_page_heap.h. A hint: where THP
// is unavailable nothing changes.
#pragma once

#include <cstddef>
#include <cstdint>

namespace pbrta {

inline constexpr uint64_t kHugePageSize = uint64_t{2} << 20;

// Asks for huge pages over the whole 2 MiB pages inside [data, data + bytes).
void advise_huge_pages(void* data, size_t bytes);

// Fresh zeroed memory of at least bytes, in a mapping of its own that starts on a huge-page
// boundary, huge pages asked for; nullptr when out of address space. Free with
// munmap(p, *mapped).
void* map_huge(uint64_t bytes, uint64_t* mapped);

}  // namespace pbrta
