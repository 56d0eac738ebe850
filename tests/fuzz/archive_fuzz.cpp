// libFuzzer target for the archive container reader (format/archive_reader.h): open_memory and
// load_sections on the input as it is, then on a copy whose checksums (sections, frames, table,
// header) and recorded file size have been recomputed (archive_reseal.h), so that mutations get
// past the checksums and reach the layout checks and the decoders. Any crash, leak, sanitizer
// report, hang or allocation beyond the reader's bounds is a bug.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "archive_reseal.h"
#include "format/archive.h"
#include "format/archive_reader.h"
#include "format/isolated_jobs.h"

namespace {

void try_read(std::string_view bytes) {
  pbrta::ArchiveReader reader;
  std::string error;
  if (!reader.open_memory(bytes, "fuzz.pbrta", &error)) return;
  if (!reader.load_sections(1, &error)) return;
  // Touch what a caller would: every loaded byte and its padding.
  volatile uint8_t sink = 0;
  for (uint32_t i = 0; i < reader.section_count(); ++i) {
    const uint8_t* data = reader.section_data(i);
    if (data == nullptr) continue;
    const uint64_t n = reader.section_size(i) + pbrta::kSectionPadding;
    for (uint64_t k = 0; k < n; k += 61) sink = sink + data[k];
    sink = sink + data[n - 1];
  }
}

}  // namespace

// Draco runs in this process, not in a budgeted child (format/isolated_jobs.h): libFuzzer's
// coverage counters and crash reports live here, and its -timeout stands in for the budget.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  pbrta::set_isolation_enabled(false);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try_read(std::string_view(reinterpret_cast<const char*>(data), size));
  std::vector<uint8_t> copy(data, data + size);
  fuzz_support::reseal(&copy);
  try_read(std::string_view(reinterpret_cast<const char*>(copy.data()), copy.size()));
  return 0;
}
