// use_huge_page_heap(): a forked child calls it, which re-runs this test
// binary; kIsProbe below records the environment the re-run got.
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

// The re-executed child: records its environment and exits before any test
// runs. It calls use_huge_page_heap() again, as main() would after the
// re-exec: a second exec here would loop forever.
const bool kIsProbe = [] {
  const char* out = std::getenv("HUGE_PAGE_PROBE_OUT");
  if (!out) return false;
  char self[] = "/proc/self/exe";
  char* argv[] = {self, nullptr};
  pbrta::use_huge_page_heap(argv);
  const char* t = std::getenv("GLIBC_TUNABLES");
  write_text(out, t ? t : "(unset)");
  std::_Exit(0);
}();

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
    char* argv[] = {self, nullptr};
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
