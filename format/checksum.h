// format/checksum.h — the archive's checksum (ARCHIVE.md): XXH3-64, seed 0, of a byte range.
//
// Large ranges use XXH3's AVX2 kernel when the CPU has AVX2 (the libxxhash export is built for
// SSE2): the same value, faster on the megabytes every load checksums. Not libxxhash's own
// dispatcher: it picks AVX-512, which measured slower over a whole load in a VM.
#pragma once

#include <cstddef>
#include <cstdint>

namespace pbrta {

uint64_t checksum64(const void* data, size_t size);

}  // namespace pbrta
