// use_huge_page_heap(): a forked child calls it with an argv that re-runs this
// test binary on the probe below, which records the environment it got.
#include "format/huge_page_heap.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <string>

#include "test_support.h"

namespace {

void write_text(const char* path, const std::string& text) {
  if (FILE* f = std::fopen(path, "w")) {
    std::fputs(text.c_str(), f);
    std::fclose(f);
  }
}

// Runs only as the re-executed child. It calls use_huge_page_heap() again, as
// main() would after the re-exec: a second exec here would loop forever.
TEST(HugePageHeapProbe, RecordsItsEnvironment) {
  const char* out = std::getenv("HUGE_PAGE_PROBE_OUT");
  if (!out) GTEST_SKIP() << "only the child of the HugePageHeap tests runs this";
  char self[] = "/proc/self/exe";
  char filter[] = "--gtest_filter=HugePageHeapProbe.*";
  char* argv[] = {self, filter, nullptr};
  pbrta::use_huge_page_heap(argv);
  const char* t = std::getenv("GLIBC_TUNABLES");
  write_text(out, t ? t : "(unset)");
}

// What the child process ended up with: the probe's record, or "not
// re-executed" if use_huge_page_heap() returned.
std::string run_child(const char* tunables, const char* opt_out) {
  std::string out = testing_support::scratch_dir("huge_page_heap") + "/env.txt";
  pid_t pid = fork();
  if (pid == 0) {
    if (tunables)
      setenv("GLIBC_TUNABLES", tunables, 1);
    else
      unsetenv("GLIBC_TUNABLES");
    if (opt_out)
      setenv("PBRT_HUGE_PAGES", opt_out, 1);
    else
      unsetenv("PBRT_HUGE_PAGES");
    setenv("HUGE_PAGE_PROBE_OUT", out.c_str(), 1);
    char self[] = "/proc/self/exe";
    char filter[] = "--gtest_filter=HugePageHeapProbe.*";
    char* argv[] = {self, filter, nullptr};
    pbrta::use_huge_page_heap(argv);
    write_text(out.c_str(), "not re-executed");
    _exit(0);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  return testing_support::read_file(out);
}

TEST(HugePageHeap, ReExecutesOnceWithTheTunable) {
  EXPECT_EQ(run_child(nullptr, nullptr), "glibc.malloc.hugetlb=1");
}

TEST(HugePageHeap, KeepsTheUsersOtherTunables) {
  EXPECT_EQ(run_child("glibc.malloc.tcache_count=0", nullptr),
            "glibc.malloc.tcache_count=0:glibc.malloc.hugetlb=1");
}

TEST(HugePageHeap, LeavesAnExplicitChoiceAlone) {
  EXPECT_EQ(run_child("glibc.malloc.hugetlb=0", nullptr), "not re-executed");
}

TEST(HugePageHeap, CanBeTurnedOff) {
  EXPECT_EQ(run_child(nullptr, "0"), "not re-executed");
}

}  // namespace
