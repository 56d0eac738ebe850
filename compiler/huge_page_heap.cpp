// Big blocks in huge-page mappings of their own; see huge_page_heap.h.
#include "compiler/huge_page_heap.h"

#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>

#include "format/huge_pages.h"

namespace pbrtc {

using pbrta::advise_huge_pages;
using pbrta::kHugePageSize;
using pbrta::map_huge;

namespace {

// Sits just before a mapped block: heap_release reads it to tell the block from malloc's. A malloc
// block can sit 64 bytes past a huge-page boundary too; the check word (the block's address
// scrambled) is what no malloc'd neighbour holds by chance.
struct alignas(64) BlockHeader {
  uint64_t check;
  uint64_t mapped;
};
constexpr uint64_t kCheckKey = 0x9e3779b97f4a7c15;

// Growth of malloc's main heap (the brk area) is padded to this much, so that most of each
// growth lies in whole huge pages no one has touched yet when it is advised.
constexpr int kHeapGrowth = 32 << 20;

bool enabled() {
  static const bool on = [] {
    const char* v = std::getenv("PBRT_HUGE_PAGES");
    if (v != nullptr && std::strcmp(v, "0") == 0) return false;
    // M_TOP_PAD also stops glibc adjusting its mmap threshold: blocks of 128 KiB to 1 MiB stay
    // mappings of base pages of their own. Raising the threshold to 1 MiB as well (so they come
    // from the advised heap) was measured slower: the 200 MB parse took 0.27-0.61 s in 6
    // rounds, against 0.16-0.51 s for this setting in 4 rounds a minute later, its heap's huge
    // pages stalling on compaction in every round.
    mallopt(M_TOP_PAD, kHeapGrowth);
    return true;
  }();
  return on;
}

// What glibc does for its heap under glibc.malloc.hugetlb=1, which it reads only at start: each
// time the main heap has grown, the new part is advised. (sbrk(0) only reads glibc's variable.)
// Other threads' arenas are not followed: the parse that fills the heap runs on one thread.
void advise_heap_growth() {
  static std::atomic<uintptr_t> advised_to{0};
  const auto top = reinterpret_cast<uintptr_t>(sbrk(0));
  uintptr_t from = advised_to.load(std::memory_order_relaxed);
  if (top <= from || !advised_to.compare_exchange_strong(from, top)) return;
  if (from == 0) from = top > uintptr_t(kHeapGrowth) ? top - kHeapGrowth : 0;  // the first growth
  advise_huge_pages(reinterpret_cast<void*>(from), top - from);
}

}  // namespace

void* heap_allocate(std::size_t n) {
  // Sizes near the address space's are left to malloc, which refuses them (no sum below may
  // wrap).
  if (n >= kHugeHeapBlock && n <= (std::size_t{1} << 47) && enabled()) {
    uint64_t mapped = 0;
    if (void* m = map_huge(n + sizeof(BlockHeader), &mapped)) {
      auto* h = static_cast<BlockHeader*>(m);
      void* p = h + 1;
      h->check = kCheckKey ^ reinterpret_cast<uintptr_t>(p);
      h->mapped = mapped;
      return p;
    }
  }
  for (;;) {
    if (void* p = std::malloc(n == 0 ? 1 : n)) {
      if (enabled()) advise_heap_growth();
      return p;
    }
    std::new_handler handler = std::get_new_handler();
    if (handler == nullptr) throw std::bad_alloc();
    handler();
  }
}

void heap_release(void* p) noexcept {
  if (p == nullptr) return;
  if ((reinterpret_cast<uintptr_t>(p) & (kHugePageSize - 1)) == sizeof(BlockHeader)) {
    // p - 64 starts p's own 4 KiB page: readable whoever allocated p.
    const auto* h = static_cast<const BlockHeader*>(p) - 1;
    if (h->check == (kCheckKey ^ reinterpret_cast<uintptr_t>(p))) {
      munmap(const_cast<BlockHeader*>(h), h->mapped);
      return;
    }
  }
  std::free(p);
}

}  // namespace pbrtc
