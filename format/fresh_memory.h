// format/fresh_memory.h — the archive reader's memory: fresh huge-page mappings for the buffers
// a load writes, and the page-population advice it gives the kernel (internal to format/).
//
// Why one place: the reader's decoded-section buffers (format/archive_reader.cpp) and each
// loading thread's scratch blocks (format/thread_decoder.h) follow the same rule
// for when a buffer is worth its own huge-page mapping.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>

namespace pbrta::archive_detail {

inline constexpr size_t kBufferAlignment =
    64;  // a cache line; more than the 16 the format promises
inline constexpr uint64_t kHugePageSize = uint64_t{2} << 20;
// From this size on a buffer gets its own huge-page mapping. Faulting in 256 KiB 4 KiB at a time
// costs more than zeroing one 2 MiB page (measured: ~12 us per 4 KiB fault in this VM, ~0.1 ms per
// 2 MiB page), and there are few such buffers per load (one for all decoded sections, a few per
// thread for zstd), so the rounding wastes little.
inline constexpr uint64_t kHugeBufferThreshold = uint64_t{256} << 10;

// A buffer's last, partial huge page is given as base pages instead when it would hold less than
// this: the kernel zeroes the whole 2 MiB of a huge page however little of it is used. Measured
// (pread of a file into the buffer, then its checksum, best of 1500): with a 20 KiB tail, 2.12 MB
// took 202 us against 233 in whole huge pages; with tails of 64, 128 and 160 KiB, base-page tails
// took 224, 245 and 257 us against 241, 247 and 246.
inline constexpr uint64_t kHugeTailThreshold = uint64_t{64} << 10;

// Fresh zeroed memory in its own mapping of *mapped bytes, nullptr when out of memory; freed with
// munmap(p, *mapped). Huge pages are requested for the whole huge pages, which start at a huge-page
// boundary; bytes are rounded up to whole huge pages, or only to base pages past the last whole
// one when the rest is under kHugeTailThreshold.
uint8_t* map_fresh(uint64_t bytes, uint64_t* mapped);

}  // namespace pbrta::archive_detail
