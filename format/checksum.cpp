#include "format/checksum.h"

#include <xxhash.h>

#include <algorithm>
#include <vector>

#include "format/archive.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>  // xxhash.h includes it only when the whole file is built for AVX2
#define PBRTA_XXH3_AVX2 1
// XXH3 compiled from libxxhash's header with its AVX2 kernel, in this file only, for CPUs that
// have AVX2; names get libxxhash's XXH_INLINE_ prefix, so nothing clashes with the library.
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2")
#endif
#define XXH_INLINE_ALL
#define XXH_VECTOR XXH_AVX2
#include <xxhash.h>
namespace pbrta {
namespace {
uint64_t checksum64_avx2(const void* data, size_t size) {
  return XXH_INLINE_XXH3_64bits(data, size);
}
}  // namespace
}  // namespace pbrta
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
#endif

namespace pbrta {

uint64_t checksum64(const void* data, size_t size) {
#if defined(PBRTA_XXH3_AVX2)
  // Below a few KiB both run in well under a microsecond; the CPU check is made once.
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2 && size >= 4096) return checksum64_avx2(data, size);
#endif
  return XXH3_64bits(data, size);
}

uint64_t checksum_chunk_count(uint64_t size) {
  return size / kRawChunk + (size % kRawChunk != 0);
}

uint64_t combine_chunk_checksums(const uint64_t* chunk_checksums, size_t count) {
  // The values as little-endian u64s, which is how this (little-endian) host holds them.
  static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the archive is little-endian");
  return checksum64(chunk_checksums, count * sizeof(uint64_t));
}

uint64_t chunked_checksum64(const void* data, size_t size) {
  const auto* bytes = static_cast<const uint8_t*>(data);
  std::vector<uint64_t> chunks(checksum_chunk_count(size));
  for (size_t k = 0; k < chunks.size(); ++k) {
    const uint64_t at = k * kRawChunk;
    chunks[k] = checksum64(bytes + at, std::min<uint64_t>(kRawChunk, size - at));
  }
  return combine_chunk_checksums(chunks.data(), chunks.size());
}

}  // namespace pbrta
