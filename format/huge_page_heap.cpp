// Re-exec with glibc's huge-page heap tunable; see huge_page_heap.h.
#include "format/huge_page_heap.h"

#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <string>

namespace pbrta {

void use_huge_page_heap(char** argv) {
  static const char kTunable[] = "glibc.malloc.hugetlb";
  const char* opt_out = std::getenv("PBRT_HUGE_PAGES");
  if (opt_out && std::strcmp(opt_out, "0") == 0) return;
  const char* current = std::getenv("GLIBC_TUNABLES");
  // Already asked for (by us or by the user, whatever the value): never loop.
  if (current && std::strstr(current, kTunable)) return;
  std::string value = current && *current ? std::string(current) + ":" : std::string();
  value += kTunable;
  value += "=1";
  if (::setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0) return;
  ::execv("/proc/self/exe", argv);
  // No /proc, or exec refused: run on with the ordinary heap.
}

}  // namespace pbrta
