#include "format/fresh_memory.h"

namespace pbrta::archive_detail {

uint8_t* map_fresh(uint64_t bytes, uint64_t* mapped) {
  *mapped = (bytes + kHugePageSize - 1) / kHugePageSize * kHugePageSize;
  void* p = mmap(nullptr, *mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) return nullptr;
  madvise(p, *mapped, MADV_HUGEPAGE);  // a hint; harmless where unsupported
  return static_cast<uint8_t*>(p);
}

}  // namespace pbrta::archive_detail
