#include "format/fresh_memory.h"

#include <unistd.h>

namespace pbrta::archive_detail {

uint8_t* map_fresh(uint64_t bytes, uint64_t* mapped) {
  const uint64_t page = static_cast<uint64_t>(sysconf(_SC_PAGESIZE));
  const uint64_t whole = bytes / kHugePageSize * kHugePageSize, tail = bytes - whole;
  const bool short_tail = whole > 0 && tail > 0 && tail < kHugeTailThreshold;
  if (!short_tail) {
    // A whole number of huge pages, which Linux (6.7 on) places on a huge-page boundary itself.
    *mapped = (bytes + kHugePageSize - 1) / kHugePageSize * kHugePageSize;
    void* p = mmap(nullptr, *mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) return nullptr;
    madvise(p, *mapped, MADV_HUGEPAGE);  // a hint; harmless where unsupported
    return static_cast<uint8_t*>(p);
  }
  // Not a whole number of huge pages: reserve one more, and keep the part that starts on a
  // boundary.
  *mapped = whole + (tail + page - 1) / page * page;
  const uint64_t reserved = *mapped + kHugePageSize;
  void* r = mmap(nullptr, reserved, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (r == MAP_FAILED) return nullptr;
  uint8_t* const begin = static_cast<uint8_t*>(r);
  uint8_t* const p = reinterpret_cast<uint8_t*>(
      (reinterpret_cast<uintptr_t>(begin) + kHugePageSize - 1) / kHugePageSize * kHugePageSize);
  if (p > begin) munmap(begin, static_cast<size_t>(p - begin));
  const uint64_t after = static_cast<uint64_t>(begin + reserved - (p + *mapped));
  if (after > 0) munmap(p + *mapped, after);
  madvise(p, whole, MADV_HUGEPAGE);
  return p;
}

}  // namespace pbrta::archive_detail
