// heap_allocate/heap_release and the operator new that compiler_tests links
// (compiler/huge_page_heap.h): big blocks in huge-page-advised mappings of their
// own, the main heap advised as it grows, PBRT_HUGE_PAGES=0 turning it off.
#include "compiler/huge_page_heap.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <new>
#include <sstream>
#include <string>
#include <vector>

#include "format/huge_pages.h"
#include "test_support.h"

namespace {

uint64_t offset_in_huge_page(const void* p) {
  return reinterpret_cast<uintptr_t>(p) & (pbrta::kHugePageSize - 1);
}

// The smaps fields of the mapping that holds p (empty if none), and that mapping's name.
std::string mapping_of(const void* p, std::string* name = nullptr) {
  std::ifstream in("/proc/self/smaps");
  std::string line, block;
  bool inside = false;
  const auto at = reinterpret_cast<uintptr_t>(p);
  while (std::getline(in, line)) {
    unsigned long long lo = 0, hi = 0;
    if (std::sscanf(line.c_str(), "%llx-%llx ", &lo, &hi) == 2 && line.find(':') > 17) {
      if (inside) break;
      inside = at >= lo && at < hi;
      if (inside && name) *name = line;
      continue;
    }
    if (inside) block += line + "\n";
  }
  return block;
}

// Whether smaps says the mapping was advised (MADV_HUGEPAGE sets the "hg" flag).
bool advised(const std::string& fields) {
  const size_t at = fields.find("VmFlags:");
  return at != std::string::npos && fields.find(" hg", at) < fields.find('\n', at);
}

bool thp_available() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string s;
  std::getline(in, s);
  return !s.empty() && s.find("[never]") == std::string::npos;
}

size_t mapping_count() {
  std::ifstream in("/proc/self/maps");
  size_t n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

// A child that asks for sizes no sum may wrap on (a wrapped one would come back as a small
// mapping the caller writes past): records how many were refused, and exits before any test
// runs. A child, because malloc's failure moves the calling thread off the main heap, which
// TheMainHeapIsAdvisedAsItGrows needs.
const bool kIsImpossibleProbe = [] {
  const char* out = std::getenv("HUGE_HEAP_IMPOSSIBLE_OUT");
  if (!out) return false;
  int refused = 0;
  for (size_t n : {~size_t{0}, ~size_t{0} - 63, size_t{1} << 62}) {
    try {
      pbrtc::heap_release(pbrtc::heap_allocate(n));
    } catch (const std::bad_alloc&) {
      ++refused;
    }
  }
  if (FILE* f = std::fopen(out, "w")) {
    std::fprintf(f, "%d", refused);
    std::fclose(f);
  }
  std::_Exit(0);
}();

// The child run with PBRT_HUGE_PAGES=0: records where a big block landed and exits before any
// test runs.
const bool kIsProbe = [] {
  const char* out = std::getenv("HUGE_HEAP_PROBE_OUT");
  if (!out) return false;
  void* p = pbrtc::heap_allocate(pbrtc::kHugeHeapBlock * 2);
  if (FILE* f = std::fopen(out, "w")) {
    std::fprintf(f, "%llu", static_cast<unsigned long long>(offset_in_huge_page(p)));
    std::fclose(f);
  }
  pbrtc::heap_release(p);
  std::_Exit(0);
}();

TEST(HugePageHeap, BigBlocksGetHugePageMappingsOfTheirOwn) {
  for (size_t n : {pbrtc::kHugeHeapBlock, size_t{3} << 20, size_t{9} << 20}) {
    auto* p = static_cast<uint8_t*>(pbrtc::heap_allocate(n));
    ASSERT_NE(p, nullptr);
    EXPECT_EQ(offset_in_huge_page(p), 64u) << n;
    std::memset(p, 0xab, n);  // all of it is there
    EXPECT_EQ(p[n - 1], 0xab);
    if (thp_available()) {
      EXPECT_TRUE(advised(mapping_of(p))) << n << " bytes:\n" << mapping_of(p);
    }
    pbrtc::heap_release(p);
  }
  // Smaller blocks come from malloc.
  void* small = pbrtc::heap_allocate(pbrtc::kHugeHeapBlock - 4096);
  EXPECT_NE(offset_in_huge_page(small), 64u);
  pbrtc::heap_release(small);
  pbrtc::heap_release(nullptr);
}

TEST(HugePageHeap, ReleasingUnmapsEveryBigBlock) {
  const size_t before = mapping_count();
  for (int i = 0; i < 200; ++i) pbrtc::heap_release(pbrtc::heap_allocate(size_t{2} << 20));
  EXPECT_LE(mapping_count(), before + 1);
}

TEST(HugePageHeap, OperatorNewUsesIt) {
  // compiler_tests links pbrtc_huge_page_new, as pbrtc does.
  std::vector<float> v(pbrtc::kHugeHeapBlock);  // 4 MiB
  EXPECT_EQ(offset_in_huge_page(v.data()), 64u);
  auto small = std::make_unique<int[]>(16);
  EXPECT_NE(offset_in_huge_page(small.get()), 64u);
}

TEST(HugePageHeap, TheMainHeapIsAdvisedAsItGrows) {
  if (!thp_available()) GTEST_SKIP() << "transparent huge pages are off on this machine";
  // 64 KiB blocks come from malloc's main heap (below glibc's mmap threshold); 48 MiB of them
  // make it grow past what the start-up heap held.
  std::vector<void*> blocks;
  for (int i = 0; i < 768; ++i) blocks.push_back(pbrtc::heap_allocate(64 << 10));
  std::string name;
  const std::string fields = mapping_of(blocks.back(), &name);
  EXPECT_NE(name.find("[heap]"), std::string::npos) << name;
  EXPECT_TRUE(advised(fields)) << name << "\n" << fields;
  for (void* b : blocks) pbrtc::heap_release(b);
}

// This test binary run again as a probe (probe_var naming the file it writes), with
// huge_pages_off; what the probe wrote.
std::string run_probe(const char* probe_var, bool huge_pages_off) {
  const std::string out = testing_support::scratch_dir("huge_page_heap") + "/" + probe_var;
  std::remove(out.c_str());
  const pid_t pid = fork();
  if (pid == 0) {
    if (huge_pages_off) setenv("PBRT_HUGE_PAGES", "0", 1);
    setenv(probe_var, out.c_str(), 1);
    char self[] = "/proc/self/exe";
    char* argv[] = {self, nullptr};
    execv(self, argv);
    _exit(127);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  return testing_support::read_file(out);
}

TEST(HugePageHeap, CanBeTurnedOff) {
  const std::string offset = run_probe("HUGE_HEAP_PROBE_OUT", true);
  ASSERT_FALSE(offset.empty());
  EXPECT_NE(offset, "64");  // from malloc
}

TEST(HugePageHeap, AnImpossibleSizeIsRefused) {
  EXPECT_EQ(run_probe("HUGE_HEAP_IMPOSSIBLE_OUT", false), "3");
}

}  // namespace
