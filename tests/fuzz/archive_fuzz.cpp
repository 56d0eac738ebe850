// libFuzzer target for the archive container reader (format/archive_reader.h): open_memory and
// load_sections on the input as it is, then on a copy whose checksums (sections, table, header)
// and recorded file size have been recomputed, so that mutations get past the checksums and
// reach the layout checks and the zstd decoder. Any crash, leak, sanitizer report, hang or
// allocation beyond the reader's bounds is a bug.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include <xxhash.h>

#include "format/archive.h"
#include "format/archive_reader.h"

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

// Recomputes every checksum the reader verifies, and the file size, in place.
void reseal(std::vector<uint8_t>* b) {
  if (b->size() < sizeof(pbrta::Header)) return;
  pbrta::Header h;
  std::memcpy(&h, b->data(), sizeof(h));
  const uint64_t table_bytes = uint64_t{h.section_count} * sizeof(pbrta::SectionEntry);
  if (table_bytes <= b->size() - sizeof(h)) {
    for (uint32_t i = 0; i < h.section_count; ++i) {
      uint8_t* at = b->data() + sizeof(h) + i * sizeof(pbrta::SectionEntry);
      pbrta::SectionEntry e;
      std::memcpy(&e, at, sizeof(e));
      if (e.offset <= b->size() && e.stored_size <= b->size() - e.offset) {
        e.checksum = XXH3_64bits(b->data() + e.offset, e.stored_size);
        std::memcpy(at, &e, sizeof(e));
      }
    }
    h.table_checksum = XXH3_64bits(b->data() + sizeof(h), table_bytes);
  }
  h.file_size = b->size();
  h.header_checksum = XXH3_64bits(&h, offsetof(pbrta::Header, header_checksum));
  std::memcpy(b->data(), &h, sizeof(h));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try_read(std::string_view(reinterpret_cast<const char*>(data), size));
  std::vector<uint8_t> copy(data, data + size);
  reseal(&copy);
  try_read(std::string_view(reinterpret_cast<const char*>(copy.data()), copy.size()));
  return 0;
}
