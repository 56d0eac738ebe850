// runtime/core/code_pages.cpp — see code_pages.h.
#include "runtime/core/code_pages.h"

#include <elf.h>
#include <link.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstring>

namespace rt {
namespace {

constexpr uintptr_t kMinBytes = 64 << 10;  // Linux's fault-around: 64 KiB

bool traced() {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (!f) return true;  // cannot tell: keep everything
  char line[256];
  long tracer = 0;
  while (std::fgets(line, sizeof line, f))
    if (std::sscanf(line, "TracerPid: %ld", &tracer) == 1) break;
  std::fclose(f);
  return tracer != 0;
}

bool has_text_relocations(const dl_phdr_info* info) {
  for (int i = 0; i < info->dlpi_phnum; ++i) {
    const ElfW(Phdr)& ph = info->dlpi_phdr[i];
    if (ph.p_type != PT_DYNAMIC) continue;
    for (auto* d = reinterpret_cast<const ElfW(Dyn)*>(info->dlpi_addr + ph.p_vaddr);
         d->d_tag != DT_NULL; ++d)
      if (d->d_tag == DT_TEXTREL || (d->d_tag == DT_FLAGS && (d->d_un.d_val & DF_TEXTREL)))
        return true;
  }
  return false;
}

int release_object(dl_phdr_info* info, size_t, void* page_size) {
  const uintptr_t page = *static_cast<const uintptr_t*>(page_size);
  if (std::strstr(info->dlpi_name, "linux-vdso") || has_text_relocations(info)) return 0;
  uintptr_t relro_lo = 0, relro_hi = 0;  // whole pages around the relocated read-only data
  for (int i = 0; i < info->dlpi_phnum; ++i) {
    const ElfW(Phdr)& ph = info->dlpi_phdr[i];
    if (ph.p_type != PT_GNU_RELRO) continue;
    relro_lo = (info->dlpi_addr + ph.p_vaddr) & ~(page - 1);
    relro_hi = (info->dlpi_addr + ph.p_vaddr + ph.p_memsz + page - 1) & ~(page - 1);
  }
  // Consecutive read-only segments (headers, code, constants) go in one call: each call costs
  // tens of microseconds however little it drops (it flushes every thread's TLB), so runs of
  // less than what one fault maps back are left alone. The loader maps an object's whole span,
  // so what lies between its segments is its own (PROT_NONE padding).
  uintptr_t run_lo = 0, run_hi = 0;
  auto flush = [&] {
    if (run_hi >= run_lo + kMinBytes)
      madvise(reinterpret_cast<void*>(run_lo), run_hi - run_lo, MADV_DONTNEED);
    run_lo = run_hi = 0;
  };
  for (int i = 0; i < info->dlpi_phnum; ++i) {
    const ElfW(Phdr)& ph = info->dlpi_phdr[i];
    if (ph.p_type != PT_LOAD) continue;
    // Whole pages inside the segment only.
    const uintptr_t lo = (info->dlpi_addr + ph.p_vaddr + page - 1) & ~(page - 1);
    const uintptr_t hi = (info->dlpi_addr + ph.p_vaddr + ph.p_filesz) & ~(page - 1);
    if ((ph.p_flags & PF_W) || ph.p_filesz < ph.p_memsz || hi <= lo ||
        (lo < relro_hi && relro_lo < hi)) {
      flush();
      continue;
    }
    if (run_hi == 0) run_lo = lo;
    run_hi = hi;
  }
  flush();
  return 0;
}

}  // namespace

bool release_code_pages() {
  if (traced()) return false;
  uintptr_t page = uintptr_t(sysconf(_SC_PAGESIZE));
  dl_iterate_phdr(release_object, &page);
  return true;
}

}  // namespace rt
