// release_code_pages(): code pages leave the resident set, and everything the program runs
// afterwards (its own code, libraries, virtual calls through relocated tables, initialised
// data) still works and reads the same values.
#include "runtime/core/code_pages.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <functional>
#include <memory>
#include <sstream>
#include <string>

namespace rt {
namespace {

long resident_kib() {
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  long size = 0, resident = 0;
  if (!f) return -1;
  if (std::fscanf(f, "%ld %ld", &size, &resident) != 2) resident = -1;
  std::fclose(f);
  return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

struct Shape {
  virtual ~Shape() = default;
  virtual int sides() const = 0;
};
struct Square : Shape {
  int sides() const override { return 4; }
};

const char* const kNames[] = {"alpha", "beta", "gamma"};  // relocated pointers (RELRO)
int counter = 0;                                          // writable data

std::string work() {
  std::unique_ptr<Shape> s = std::make_unique<Square>();
  std::function<int(int)> twice = [](int x) { return 2 * x; };
  std::ostringstream out;
  out << kNames[1] << ' ' << s->sides() << ' ' << twice(++counter) << ' ' << std::to_string(0.5);
  return out.str();
}

TEST(CodePages, DropsCodeFromTheResidentSetAndTheProgramRunsOn) {
  counter = 41;
  const std::string before = work();
  EXPECT_EQ(before, "beta 4 84 0.500000");
  counter = 41;
  const long resident = resident_kib();
  if (!release_code_pages()) GTEST_SKIP() << "release_code_pages() does nothing under a debugger";
  const long after = resident_kib();
  EXPECT_EQ(counter, 41);  // written data stays as written
  ASSERT_GT(resident, 0);
  // This test program maps gtest, libstdc++ and libc code it has run: well over 256 KiB.
  EXPECT_LT(after, resident - 256) << "resident " << resident << " KiB, after " << after;
  EXPECT_EQ(work(), before);
  release_code_pages();  // twice is harmless
  EXPECT_EQ(std::string(kNames[2]), "gamma");
}

}  // namespace
}  // namespace rt
