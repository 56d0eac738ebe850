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

// A raw section's checksum (ARCHIVE.md, section 5): checksum64 of the chunks' checksum64 values,
// each chunk kRawChunk bytes (the last shorter). The loader hashes the chunks on its own threads
// and combines them with combine_chunk_checksums; this is the one-call form the writer uses.
uint64_t chunked_checksum64(const void* data, size_t size);
uint64_t combine_chunk_checksums(const uint64_t* chunk_checksums, size_t count);
uint64_t checksum_chunk_count(uint64_t size);

}  // namespace pbrta
