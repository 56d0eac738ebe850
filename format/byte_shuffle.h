// format/byte_shuffle.h — the 4-byte-lane byte shuffle of codecs 2 and 4 (ARCHIVE.md section 5).
//
// Blosc-style: each block of kShuffleBlock bytes (the last may be shorter) becomes all byte-0s
// of the block's 4-byte words, then all byte-1s, byte-2s, byte-3s, then the block's size % 4 tail
// bytes as they are. Grouping float bytes by significance is what lets zstd find their
// redundancy; cutting sections into blocks lets a reader unshuffle through a cache-sized buffer
// instead of a second copy of the section. src and dst must not overlap.
#pragma once

#include <cstdint>

namespace pbrta {

inline constexpr uint64_t kShuffleBlock = uint64_t{256} << 10;

// A range of a block's decoded uint32 words that must all be below limit (a mesh's triangle
// indices against its vertex count): byte offsets in the block, multiples of 4, within its
// 4 * (size / 4) bytes of whole words. exceeded is set when one is not.
struct WordBound {
  uint64_t begin, end;
  uint32_t limit;
  bool exceeded;
};

// One block of size <= kShuffleBlock bytes, and its inverse. The inverse checks the bounds
// (sorted by begin, disjoint) on the words while it has them in registers, which costs next to
// nothing; reading the indices back afterwards cost a tenth of a load. With stream, the AVX2
// kernel writes around the cache (non-temporal stores, from the first 32-byte aligned word on):
// for a section far larger than the cache, an ordinary store first reads in each line it will
// overwrite whole, and the line is evicted before anything reads it.
void shuffle4_block(const uint8_t* src, uint8_t* dst, uint64_t size);
void unshuffle4_block(const uint8_t* src, uint8_t* dst, uint64_t size, WordBound* bounds = nullptr,
                      uint64_t num_bounds = 0, bool stream = false);

// The unshuffle's kernels: portable (SSE2 on x86-64) and AVX2, which unshuffle4_block picks when
// the CPU has it. Exposed so tests can run each against the other on the same bytes.
enum class ShuffleKernel { kPortable, kAvx2 };
bool shuffle_kernel_available(ShuffleKernel kernel);
void unshuffle4_block_with(ShuffleKernel kernel, const uint8_t* src, uint8_t* dst, uint64_t size,
                           WordBound* bounds, uint64_t num_bounds, bool stream = false);

// A whole section, block by block.
void shuffle4(const uint8_t* src, uint8_t* dst, uint64_t size);

}  // namespace pbrta
