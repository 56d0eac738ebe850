// The building blocks: radical inverses, Joe & Kuo's Sobol' matrices, the
// Sobol' pixel inversion, and the per-pixel point patterns.
#include <gtest/gtest.h>

#include <set>

#include "runtime/sampler/radical_inverse.h"
#include "runtime/sampler/sample_patterns.h"
#include "runtime/sampler/sobol_matrices.h"
#include "sampler_test_support.h"

namespace rt {
namespace {

TEST(RadicalInverse, KnownValuesAndInverse) {
  EXPECT_DOUBLE_EQ(radical_inverse(2, 6), 0.375);               // 110 -> .011
  EXPECT_DOUBLE_EQ(radical_inverse(3, 5), 2.0 / 3 + 1.0 / 9);   // 12 -> .21
  EXPECT_DOUBLE_EQ(radical_inverse(5, 7), 2.0 / 5 + 1.0 / 25);  // 12 -> .21
  EXPECT_EQ(halton_prime(0), 2u);
  EXPECT_EQ(halton_prime(2), 5u);
  EXPECT_EQ(halton_prime(999), 7919u);
  // The first `digits` digits of radical_inverse(inverse_radical_inverse(x)) spell x.
  for (uint64_t x = 0; x < 81; ++x) {
    uint64_t index = inverse_radical_inverse<3>(x, 4);
    EXPECT_NEAR(radical_inverse(3, index) * 81, double(x), 1e-9) << x;
  }
  // With the identity permutation the scrambled form is the plain one.
  uint16_t identity[7] = {0, 1, 2, 3, 4, 5, 6};
  for (uint64_t a : {0ull, 1ull, 48ull, 123456ull})
    EXPECT_NEAR(scrambled_radical_inverse(7, a, identity), radical_inverse(7, a), 1e-7);
  // A permutation maps digits, including the infinite run of zeros (as perm[0]).
  uint16_t swap01[2] = {1, 0};
  EXPECT_NEAR(scrambled_radical_inverse(2, 0, swap01), 1.0, 1e-7);
  EXPECT_NEAR(scrambled_radical_inverse(2, 1, swap01), 0.5, 1e-7);
}

TEST(RadicalInverse, PermutationsDependOnSeed) {
  DigitPermutations a(1), b(1), c(2);
  int differing = 0;
  for (int d = 0; d < 50; ++d) {
    uint32_t base = halton_prime(d);
    std::set<int> digits(a.for_dimension(d), a.for_dimension(d) + base);
    EXPECT_EQ(digits.size(), base);  // a permutation
    EXPECT_TRUE(std::equal(a.for_dimension(d), a.for_dimension(d) + base, b.for_dimension(d)));
    differing += !std::equal(a.for_dimension(d), a.for_dimension(d) + base, c.for_dimension(d));
  }
  EXPECT_GE(differing, 45);
}

TEST(SobolMatrices, FirstPointsMatchJoeKuo) {
  // Joe & Kuo's reference output for 3 dimensions (points in Gray-code order).
  const double expected[10][3] = {{0, 0, 0},
                                  {0.5, 0.5, 0.5},
                                  {0.75, 0.25, 0.25},
                                  {0.25, 0.75, 0.75},
                                  {0.375, 0.375, 0.625},
                                  {0.875, 0.875, 0.125},
                                  {0.625, 0.125, 0.875},
                                  {0.125, 0.625, 0.375},
                                  {0.1875, 0.3125, 0.9375},
                                  {0.6875, 0.8125, 0.4375}};
  for (uint64_t n = 0; n < 10; ++n)
    for (int d = 0; d < 3; ++d)
      EXPECT_EQ(sobol_bits(n ^ (n >> 1), d) * 0x1p-32, expected[n][d]) << n << " " << d;
}

TEST(SobolMatrices, EveryDimensionIsStratifiedIn1D) {
  // Each dimension's matrix is nonsingular: the first 2^k points take every
  // k-bit prefix once (a (0,k,1)-net), for every tabulated dimension.
  for (int d = 0; d < kSobolDimensions; ++d) {
    std::set<uint32_t> prefixes;
    for (uint64_t i = 0; i < 1024; ++i) prefixes.insert(sobol_bits(i, d) >> 22);
    EXPECT_EQ(prefixes.size(), 1024u) << "dimension " << d;
  }
}

TEST(SobolMatrices, PixelIndexerFindsThePointInEachPixel) {
  for (int m : {0, 1, 3, 5}) {
    SobolPixelIndexer indexer(m);
    const uint32_t side = 1u << m;
    for (uint64_t frame : {0ull, 1ull, 5ull, 1000ull}) {
      std::set<uint64_t> seen;
      for (uint32_t y = 0; y < side; ++y)
        for (uint32_t x = 0; x < side; ++x) {
          uint64_t index = indexer.index(frame, x, y);
          EXPECT_EQ(index >> (2 * m), frame);
          if (m > 0) {
            EXPECT_EQ(sobol_bits(index, 0) >> (32 - m), x);
            EXPECT_EQ(sobol_bits(index, 1) >> (32 - m), y);
          }
          seen.insert(index);
        }
      EXPECT_EQ(seen.size(), size_t(side) * side);
    }
  }
}

TEST(SamplePatterns, StratifiedLatinAndZeroTwo) {
  Rng rng(3);
  std::vector<Vec2> grid(12);
  stratified_2d(grid.data(), 4, 3, rng, true);
  EXPECT_TRUE(one_per_cell(grid, 4, 3));
  stratified_2d(grid.data(), 4, 3, rng, false);
  EXPECT_FLOAT_EQ(grid[0].x, 0.125f);
  EXPECT_FLOAT_EQ(grid[0].y, 1.f / 6);

  std::vector<float> lhs(2 * 7);
  latin_hypercube(lhs.data(), 7, 2, rng);
  std::vector<float> xs, ys;
  for (int i = 0; i < 7; ++i) {
    xs.push_back(lhs[2 * i]);
    ys.push_back(lhs[2 * i + 1]);
  }
  EXPECT_TRUE(one_per_stratum(xs));
  EXPECT_TRUE(one_per_stratum(ys));

  // 4 pixel samples of 8 values: each sample's 8 form a (0,3,2)-net.
  std::vector<Vec2> pts(32);
  sobol_2d_pattern(8, 4, pts.data(), rng);
  for (int s = 0; s < 4; ++s)
    EXPECT_TRUE(is_02_net(std::vector<Vec2>(pts.begin() + 8 * s, pts.begin() + 8 * s + 8)));
  EXPECT_TRUE(is_02_net(pts));
  std::vector<float> vdc(16);
  van_der_corput_pattern(4, 4, vdc.data(), rng);
  for (int s = 0; s < 4; ++s)
    EXPECT_TRUE(one_per_stratum(std::vector<float>(vdc.begin() + 4 * s, vdc.begin() + 4 * s + 4)));
  EXPECT_TRUE(one_per_stratum(vdc));
}

// The patterns skip shuffling samples of one value and step the generator once per sample
// instead: what those shuffles draw, whatever the generator's state.
TEST(SamplePatterns, ShufflingOneValueDrawsOnce) {
  for (uint64_t seed : {1u, 5u, 77u})
    for (int n : {1, 3, 64, 1024}) {
      Rng shuffled(seed, 9), stepped(seed, 9);
      std::vector<float> values(size_t(n), 0.5f);
      std::vector<Vec2> points(size_t(n), Vec2{0.25f, 0.75f});
      for (int i = 0; i < n; ++i) shuffle_blocks(values.data() + i, 1, 1, shuffled);
      for (int i = 0; i < n; ++i) shuffle_points(points.data() + i, 1, 1, shuffled);
      stepped.advance(2 * n);
      EXPECT_EQ(shuffled.next_u32(), stepped.next_u32()) << "n " << n;
    }
}

}  // namespace
}  // namespace rt
