// tests/fuzz/archive_reseal.h — make a mutated archive's checksums right again.
//
// A fuzzer's mutation almost always breaks a checksum, and the reader stops there. reseal()
// recomputes, in place, every checksum the container reader verifies (each section's over its
// stored bytes, the table's, the header's) and the recorded file size, wherever the header and
// table let it find them, so that mutations reach the layout checks, the decoders and the record
// validation behind them. A zstd section's checksum covers only its frame index (header and
// entries), whose entries hold each frame's checksum: those are recomputed first, for every entry
// whose frame lies inside the stored bytes. A raw section's checksum is over its 1 MiB chunks'
// (chunked_xxh3). The compiler tests of record validation reseal their edits with it too
// (tests/compiler/reseal_and_load.h).
#pragma once

#include <xxhash.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "format/archive.h"

namespace fuzz_support {

// A raw section's checksum, written from ARCHIVE.md section 5 (not the reader's code): XXH3-64 of
// the u64 XXH3-64 values of each 1 MiB chunk.
inline uint64_t chunked_xxh3(const uint8_t* data, uint64_t size) {
  constexpr uint64_t kChunk = uint64_t{1} << 20;
  std::vector<uint64_t> sums;
  for (uint64_t at = 0; at < size; at += kChunk)
    sums.push_back(XXH3_64bits(data + at, size - at < kChunk ? size - at : kChunk));
  return XXH3_64bits(sums.data(), sums.size() * sizeof(uint64_t));
}

inline void reseal(std::vector<uint8_t>* b) {
  if (b->size() < sizeof(pbrta::Header)) return;
  pbrta::Header h;
  std::memcpy(&h, b->data(), sizeof(h));
  const uint64_t table_bytes = uint64_t{h.section_count} * sizeof(pbrta::SectionEntry);
  if (table_bytes <= b->size() - sizeof(h)) {
    for (uint32_t i = 0; i < h.section_count; ++i) {
      uint8_t* at = b->data() + sizeof(h) + i * sizeof(pbrta::SectionEntry);
      pbrta::SectionEntry e;
      std::memcpy(&e, at, sizeof(e));
      if (e.offset > b->size() || e.stored_size > b->size() - e.offset) continue;
      uint8_t* stored = b->data() + e.offset;
      uint64_t covered = e.stored_size;
      if (e.codec == uint32_t(pbrta::Codec::kZstd)) {
        pbrta::FrameIndexHeader fh;
        if (e.stored_size < sizeof fh) continue;
        std::memcpy(&fh, stored, sizeof fh);
        if (fh.frame_size == 0 || e.raw_size > (uint64_t{1} << 40)) continue;
        const uint64_t frames = e.raw_size / fh.frame_size + (e.raw_size % fh.frame_size != 0);
        const uint64_t index_bytes = sizeof fh + frames * sizeof(pbrta::FrameEntry);
        if (index_bytes > e.stored_size) continue;
        uint64_t frame_at = index_bytes;
        for (uint64_t k = sizeof fh; k < index_bytes; k += sizeof(pbrta::FrameEntry)) {
          pbrta::FrameEntry f;
          std::memcpy(&f, stored + k, sizeof f);
          if (f.stored_size > e.stored_size - frame_at) break;
          f.checksum = XXH3_64bits(stored + frame_at, f.stored_size);
          std::memcpy(stored + k, &f, sizeof f);
          frame_at += f.stored_size;
        }
        covered = index_bytes;
      }
      e.checksum = e.codec == uint32_t(pbrta::Codec::kRaw) ? chunked_xxh3(stored, covered)
                                                           : XXH3_64bits(stored, covered);
      std::memcpy(at, &e, sizeof(e));
    }
    h.table_checksum = XXH3_64bits(b->data() + sizeof(h), table_bytes);
  }
  h.file_size = b->size();
  h.header_checksum = XXH3_64bits(&h, offsetof(pbrta::Header, header_checksum));
  std::memcpy(b->data(), &h, sizeof(h));
}

}  // namespace fuzz_support
