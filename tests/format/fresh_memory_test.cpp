// map_fresh(): the reader's buffers. Whatever the size, the mapping covers it, is zeroed and
// writable to its end, and unmaps cleanly; a buffer with a short tail past its last whole huge
// page gets base pages for the tail, its huge pages starting on a huge-page boundary.
#include "format/fresh_memory.h"

#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>

namespace pbrta::archive_detail {
namespace {

TEST(FreshMemory, MappingsCoverTheBufferZeroedAndAligned) {
  const uint64_t page = uint64_t(sysconf(_SC_PAGESIZE));
  const uint64_t huge = kHugePageSize, tail = kHugeTailThreshold;
  struct Case {
    uint64_t bytes, mapped;
  };
  const Case cases[] = {
      {1, huge},                               // less than a huge page: one huge page
      {huge - 1, huge},                        //
      {huge, huge},                            // exactly whole huge pages
      {huge + 1, huge + page},                 // a short tail: base pages
      {huge + 20 * 1024, huge + 20 * 1024},    // caustic glass's 2.12 MB
      {2 * huge + tail - 1, 2 * huge + tail},  // the longest short tail
      {huge + tail, 2 * huge},                 // a tail this long gets a huge page
      {3 * huge + huge / 2, 4 * huge},         //
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.bytes);
    uint64_t mapped = 0;
    uint8_t* p = map_fresh(c.bytes, &mapped);
    ASSERT_NE(p, nullptr);
    EXPECT_EQ(mapped, c.mapped);
    if (mapped % huge != 0) {
      EXPECT_EQ(reinterpret_cast<uintptr_t>(p) % huge, 0u);
    }
    // Zeroed and writable across the whole mapping, its last byte included.
    uint64_t nonzero = 0;
    for (uint64_t at = 0; at < mapped; at += page) nonzero += p[at] != 0;
    EXPECT_EQ(nonzero, 0u);
    EXPECT_EQ(p[mapped - 1], 0);
    p[0] = 1;
    p[mapped - 1] = 1;
    EXPECT_EQ(munmap(p, mapped), 0);
  }
}

}  // namespace
}  // namespace pbrta::archive_detail
