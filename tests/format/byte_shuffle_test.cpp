// The unshuffle kernels against each other and against the definition (shuffle4_block's
// inverse, bounds checked word by word): every kernel this CPU has, on sizes around the kernels'
// 16- and 32-word steps, with bounds whose offenders sit at every position class, with ordinary
// and streamed stores into aligned and misaligned destinations.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "format/byte_shuffle.h"

namespace pbrta {
namespace {

std::vector<ShuffleKernel> kernels() {
  std::vector<ShuffleKernel> k;
  for (ShuffleKernel c : {ShuffleKernel::kPortable, ShuffleKernel::kAvx2})
    if (shuffle_kernel_available(c)) k.push_back(c);
  return k;
}

TEST(ByteShuffle, EveryKernelInvertsTheShuffle) {
  std::mt19937 rng(7);
  for (uint64_t size : {0,
                        1,
                        3,
                        4,
                        63,
                        64,
                        65,
                        127,
                        128,
                        129,
                        200,
                        255,
                        256,
                        257,
                        1000,
                        4099,
                        65536,
                        65539,
                        int(kShuffleBlock) - 1,
                        int(kShuffleBlock)}) {
    std::vector<uint8_t> raw(size), shuffled(size);
    for (uint8_t& b : raw) b = uint8_t(rng());
    shuffle4_block(raw.data(), shuffled.data(), size);
    for (ShuffleKernel k : kernels()) {
      std::vector<uint8_t> back(size + 1, 0xAB);
      unshuffle4_block_with(k, shuffled.data(), back.data(), size, nullptr, 0);
      EXPECT_EQ(0, std::memcmp(back.data(), raw.data(), size)) << "size " << size;
      EXPECT_EQ(0xAB, back[size]) << "wrote past the block, size " << size;
    }
  }
}

// Bounds over [begin, end) words; the truth computed word by word.
TEST(ByteShuffle, EveryKernelFlagsExactlyTheBoundsWithAnOffender) {
  if (kernels().size() < 2) GTEST_LOG_(INFO) << "only the portable kernel runs on this CPU";
  std::mt19937 rng(11);
  const uint64_t words = 4096 + 7, size = words * 4 + 3;
  for (int trial = 0; trial < 400; ++trial) {
    const uint32_t limit = 1 + rng() % 5000;
    std::vector<uint32_t> values(words);
    for (uint32_t& v : values) v = rng() % limit;  // all in bounds, then a few offenders
    const int offenders = trial % 4;
    for (int o = 0; o < offenders; ++o) {
      // Positions that stress the kernels: step edges, the block's ends, anywhere.
      const uint64_t picks[] = {0, 15, 16, 31, 32, 33, words - 1, words - 8, rng() % words};
      values[picks[rng() % 9]] = limit + rng() % 3 + (trial % 7 == 0 ? 0x80000000u : 0);
    }
    std::vector<uint8_t> raw(size), shuffled(size);
    std::memcpy(raw.data(), values.data(), words * 4);
    for (uint64_t i = words * 4; i < size; ++i) raw[i] = uint8_t(rng());
    shuffle4_block(raw.data(), shuffled.data(), size);
    // Sorted, disjoint bounds with random gaps, some empty.
    std::vector<WordBound> bounds;
    for (uint64_t w = rng() % 40; w < words;) {
      const uint64_t end = std::min<uint64_t>(words, w + rng() % 300);
      bounds.push_back(WordBound{w * 4, end * 4, limit, false});
      w = end + rng() % 40;
    }
    std::vector<bool> truth(bounds.size(), false);
    for (size_t b = 0; b < bounds.size(); ++b)
      for (uint64_t w = bounds[b].begin / 4; w < bounds[b].end / 4; ++w)
        if (values[w] >= limit) truth[b] = true;
    // Into a 64-byte aligned buffer at an offset that is 32-byte aligned or not (streamed
    // stores apply only where it is), with ordinary and with streamed stores.
    const uint64_t offset = uint64_t{trial % 2 ? 32u : 0u} + (trial % 3 == 0 ? 4 : 0);
    for (ShuffleKernel k : kernels())
      for (bool stream : {false, true}) {
        std::vector<WordBound> got = bounds;
        std::vector<uint8_t> buffer(size + offset + 64 + 1, 0xAB);
        const uintptr_t at = reinterpret_cast<uintptr_t>(buffer.data());
        uint8_t* back = buffer.data() + (64 - at % 64) % 64 + offset;
        unshuffle4_block_with(k, shuffled.data(), back, size, got.data(), got.size(), stream);
        ASSERT_EQ(0, std::memcmp(back, raw.data(), size))
            << "trial " << trial << " kernel " << int(k) << " stream " << stream;
        ASSERT_EQ(0xAB, back[size]) << "wrote past the block";
        for (size_t b = 0; b < bounds.size(); ++b)
          ASSERT_EQ(truth[b], got[b].exceeded)
              << "trial " << trial << " kernel " << int(k) << " stream " << stream << " bound " << b
              << " [" << bounds[b].begin / 4 << ", " << bounds[b].end / 4 << ")";
      }
  }
}

TEST(ByteShuffle, LimitZeroFlagsEveryNonEmptyBound) {
  std::vector<uint8_t> raw(4 * 100, 0), shuffled(raw.size());
  shuffle4_block(raw.data(), shuffled.data(), raw.size());
  for (ShuffleKernel k : kernels()) {
    WordBound b[2] = {{0, 0, 0, false}, {8, 400, 0, false}};
    std::vector<uint8_t> back(raw.size());
    unshuffle4_block_with(k, shuffled.data(), back.data(), raw.size(), b, 2);
    EXPECT_FALSE(b[0].exceeded);
    EXPECT_TRUE(b[1].exceeded);
  }
}

}  // namespace
}  // namespace pbrta
