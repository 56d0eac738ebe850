// The scene's samplers, built from real pbrt-v3 text: ranges, stratification
// of the camera dimensions, spp overrides, determinism across clones and
// pixel order, arrays, and integration error against the random sampler.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "runtime/sampler/radical_inverse.h"
#include "sampler_test_support.h"

namespace rt {
namespace {

struct Case {
  const char* name;
  const char* line;
};
const Case kAll[] = {
    {"halton", R"(Sampler "halton" "integer pixelsamples" 16)"},
    {"sobol", R"(Sampler "sobol" "integer pixelsamples" 16)"},
    {"zerotwo", R"(Sampler "02sequence" "integer pixelsamples" 16)"},
    {"lowdisc", R"(Sampler "lowdiscrepancy" "integer pixelsamples" 16)"},
    {"stratified", R"(Sampler "stratified" "integer xsamples" 4 "integer ysamples" 4)"},
    {"random", R"(Sampler "random" "integer pixelsamples" 16)"},
    {"maxmindist", R"(Sampler "maxmindist" "integer pixelsamples" 16)"},
};

// The arrays the tests below request and read: this many 1-D and 2-D values a sample (before
// the sampler's round_count).
constexpr int kArray1d = 3, kArray2d = 5;
void request_arrays(Sampler& s) {
  s.request_1d_array(s.round_count(kArray1d));
  s.request_2d_array(s.round_count(kArray2d));
}

// Everything one pixel's samples return, in call order (arrays included).
std::vector<float> trace_pixel(Sampler& s, Point2i p) {
  std::vector<float> out;
  s.start_pixel(p);
  do {
    out.push_back(s.get_1d());
    Vec2 c = s.get_2d();
    out.push_back(c.x);
    out.push_back(c.y);
    if (const float* a = s.get_1d_array(s.round_count(kArray1d)))
      out.insert(out.end(), a, a + s.round_count(kArray1d));
    else
      out.push_back(-1);
    if (const Vec2* a = s.get_2d_array(s.round_count(kArray2d)))
      for (int i = 0; i < s.round_count(kArray2d); ++i) {
        out.push_back(a[i].x);
        out.push_back(a[i].y);
      }
    else
      out.push_back(-1);
    for (int d = 0; d < 12; ++d) {  // well past the precomputed dimensions
      out.push_back(s.get_1d());
      Vec2 v = s.get_2d();
      out.push_back(v.x);
      out.push_back(v.y);
    }
  } while (s.start_next_sample());
  return out;
}

TEST(Samplers, ValuesInUnitIntervalAndSampleCount) {
  for (const Case& c : kAll) {
    auto s = sampler_from_text(std::string("range_") + c.name, c.line, 0, 11, {{-1, -2}, {37, 21}});
    ASSERT_TRUE(s) << c.name;
    EXPECT_EQ(s->samples_per_pixel(), 16) << c.name;
    request_arrays(*s);
    for (Point2i p : {Point2i{-1, -2}, Point2i{0, 0}, Point2i{36, 20}, Point2i{17, 5}}) {
      std::vector<float> v = trace_pixel(*s, p);
      EXPECT_EQ(s->current_sample_number(), 16) << c.name;
      for (float x : v) {
        ASSERT_GE(x, 0.f) << c.name << " (an array was missing if -1)";
        ASSERT_LT(x, 1.f) << c.name;
      }
    }
    // Past the requested arrays there are none.
    s->start_pixel({0, 0});
    EXPECT_NE(s->get_1d_array(s->round_count(kArray1d)), nullptr) << c.name;
    EXPECT_EQ(s->get_1d_array(s->round_count(kArray1d)), nullptr) << c.name;
    EXPECT_NE(s->get_2d_array(s->round_count(kArray2d)), nullptr) << c.name;
    EXPECT_EQ(s->get_2d_array(s->round_count(kArray2d)), nullptr) << c.name;
  }
}

// A pixel's arrays, read from sample `from` on (the samples before read no array).
std::vector<float> arrays_from(Sampler& s, Point2i p, int from) {
  std::vector<float> out;
  s.start_pixel(p);
  do {
    if (s.current_sample_number() < from) continue;
    const float* a = s.get_1d_array(s.round_count(kArray1d));
    const Vec2* b = s.get_2d_array(s.round_count(kArray2d));
    if (!a || !b) return {};
    out.insert(out.end(), a, a + s.round_count(kArray1d));
    for (int i = 0; i < s.round_count(kArray2d); ++i) out.insert(out.end(), {b[i].x, b[i].y});
  } while (s.start_next_sample());
  return out;
}

// Arrays are made when a pixel first reads them: the values must not depend on when that
// happens, nor on what another pixel read before.
TEST(Samplers, ArraysMadeWhenFirstReadAreThePixelsOwn) {
  for (const Case& c : kAll) {
    auto s = sampler_from_text(std::string("lazy_") + c.name, c.line);
    ASSERT_TRUE(s) << c.name;
    request_arrays(*s);
    const std::vector<float> all = arrays_from(*s, {5, 6}, 0);
    ASSERT_FALSE(all.empty()) << c.name;
    const std::vector<float> other = arrays_from(*s, {9, 1}, 0);
    EXPECT_NE(other, all) << c.name;
    const std::vector<float> late = arrays_from(*s, {5, 6}, 9);
    ASSERT_EQ(late.size(), all.size() * 7 / 16) << c.name;
    EXPECT_TRUE(std::equal(late.begin(), late.end(), all.end() - ptrdiff_t(late.size()))) << c.name;
  }
}

TEST(Samplers, SameValuesWhateverThePixelOrderOrClone) {
  for (const Case& c : kAll) {
    auto s = sampler_from_text(std::string("det_") + c.name, c.line);
    ASSERT_TRUE(s) << c.name;
    request_arrays(*s);
    auto a = s->clone(), b = s->clone();
    std::vector<float> a1 = trace_pixel(*a, {3, 4});
    std::vector<float> a2 = trace_pixel(*a, {40, 9});
    std::vector<float> b2 = trace_pixel(*b, {40, 9});
    trace_pixel(*b, {0, 63});
    std::vector<float> b1 = trace_pixel(*b, {3, 4});
    EXPECT_EQ(a1, b1) << c.name;
    EXPECT_EQ(a2, b2) << c.name;
    EXPECT_NE(a1, a2) << c.name;
    // set_sample_number jumps straight to a sample: same values as getting there in order.
    b->start_pixel({3, 4});
    ASSERT_TRUE(b->set_sample_number(9));
    float first = b->get_1d();
    a->start_pixel({3, 4});
    for (int i = 0; i < 9; ++i) {
      for (int d = 0; d < 7; ++d) a->get_1d();
      a->start_next_sample();
    }
    EXPECT_EQ(a->get_1d(), first) << c.name;
    // Another seed changes the values.
    auto other = sampler_from_text(std::string("det2_") + c.name, c.line, 0, 12345);
    request_arrays(*other);
    EXPECT_NE(trace_pixel(*other, {3, 4}), a1) << c.name;
  }
}

// One pixel's values as a camera sample and a path draw them, with some dimensions skipped
// (as pixel_camera_sample skips a pinhole camera's lens point or a still scene's time, and light
// sampling a delta light's values); a skipped value is recorded as NaN.
std::vector<float> trace_skipping(Sampler& s, Point2i p, bool skip) {
  std::vector<float> out;
  const float nan = std::nanf("");
  auto one = [&](bool skip_this) {
    if (skip && skip_this) {
      s.skip_1d();
      out.push_back(nan);
    } else {
      out.push_back(s.get_1d());
    }
  };
  auto two = [&](bool skip_this) {  // through get_2d_if, which skips what is not read
    const bool read = !(skip && skip_this);
    const Vec2 v = s.get_2d_if(read);
    if (read)
      out.insert(out.end(), {v.x, v.y});
    else
      out.insert(out.end(), {nan, nan});
  };
  s.start_pixel(p);
  do {
    two(false);  // film
    one(true);   // time
    one(false);
    two(true);  // across the arrays' first dimension, which global samplers jump
    if (const float* a = s.get_1d_array(s.round_count(kArray1d)))
      out.insert(out.end(), a, a + kArray1d);
    for (int d = 0; d < 8; ++d) {
      one(d == 2);
      two(d == 3 || d == 6);
    }
  } while (s.start_next_sample());
  return out;
}

// Skipping a dimension leaves every later value as drawing it would, for every sampler, in
// the camera's dimensions, across the arrays' reserved dimensions and past the precomputed
// ones.
TEST(Samplers, SkippedDimensionsLeaveTheLaterValuesAlone) {
  for (const Case& c : kAll) {
    auto s = sampler_from_text(std::string("skip_") + c.name, c.line);
    ASSERT_TRUE(s) << c.name;
    s->request_1d_array(s->round_count(kArray1d));
    auto a = s->clone(), b = s->clone();
    for (Point2i p : {Point2i{3, 4}, Point2i{40, 9}}) {
      const std::vector<float> all = trace_skipping(*a, p, false);
      const std::vector<float> skipped = trace_skipping(*b, p, true);
      ASSERT_EQ(all.size(), skipped.size()) << c.name;
      int compared = 0, left_out = 0;
      for (size_t i = 0; i < all.size(); ++i) {
        if (std::isnan(skipped[i])) {
          ++left_out;
          continue;
        }
        ++compared;
        ASSERT_EQ(all[i], skipped[i]) << c.name << " value " << i;
      }
      EXPECT_EQ(left_out, 16 * 8) << c.name;
      EXPECT_GT(compared, left_out) << c.name;
    }
  }
}

TEST(Samplers, StratifiedOnePointPerCell) {
  auto s = sampler_from_text("strat",
                             R"(Sampler "stratified" "integer xsamples" 4 "integer ysamples" 4)");
  for (Point2i p : {Point2i{0, 0}, Point2i{5, 9}}) EXPECT_TRUE(one_per_cell(first_2d(*s, p), 4, 4));
  // The second 2-D dimension is an independently shuffled stratification.
  s->start_pixel({2, 2});
  std::vector<Vec2> second;
  do {
    s->get_2d();
    second.push_back(s->get_2d());
  } while (s->start_next_sample());
  EXPECT_TRUE(one_per_cell(second, 4, 4));
  // 1-D dimensions: one per 1/16 stratum.
  s->start_pixel({2, 2});
  std::vector<float> xs;
  do xs.push_back(s->get_1d());
  while (s->start_next_sample());
  EXPECT_TRUE(one_per_stratum(xs));

  auto centred = sampler_from_text(
      "strat_c",
      R"(Sampler "stratified" "integer xsamples" 2 "integer ysamples" 2 "bool jitter" "false")");
  std::vector<Vec2> c = first_2d(*centred, {0, 0});
  for (Vec2 v : c) {
    EXPECT_TRUE(v.x == 0.25f || v.x == 0.75f);
    EXPECT_TRUE(v.y == 0.25f || v.y == 0.75f);
  }
}

TEST(Samplers, SppOverride) {
  const char* strat = R"(Sampler "stratified" "integer xsamples" 4 "integer ysamples" 4)";
  struct {
    int n, x, y;
  } splits[] = {{16, 4, 4}, {8, 4, 2}, {4, 2, 2}, {2, 2, 1}, {12, 4, 3}, {7, 7, 1}};
  for (auto sp : splits) {
    auto s = sampler_from_text("ovr_strat", strat, sp.n);
    ASSERT_EQ(s->samples_per_pixel(), sp.n);
    EXPECT_TRUE(one_per_cell(first_2d(*s, {1, 1}), sp.x, sp.y)) << sp.n;
  }
  EXPECT_EQ(sampler_from_text("ovr_h", R"(Sampler "halton")", 7)->samples_per_pixel(), 7);
  EXPECT_EQ(sampler_from_text("ovr_h0", R"(Sampler "halton")")->samples_per_pixel(), 16);
  EXPECT_EQ(sampler_from_text("ovr_r", R"(Sampler "random")")->samples_per_pixel(), 4);
  EXPECT_EQ(sampler_from_text("ovr_r2", R"(Sampler "random")", 9)->samples_per_pixel(), 9);
  EXPECT_EQ(sampler_from_text("ovr_s", R"(Sampler "sobol")", 12)->samples_per_pixel(), 16);
  EXPECT_EQ(sampler_from_text("ovr_s2", R"(Sampler "sobol" "integer pixelsamples" 5)")
                ->samples_per_pixel(),
            8);
  EXPECT_EQ(sampler_from_text("ovr_z", R"(Sampler "02sequence")", 1024)->samples_per_pixel(), 1024);
  EXPECT_EQ(sampler_from_text("ovr_z2", R"(Sampler "lowdiscrepancy" "integer pixelsamples" 3)")
                ->samples_per_pixel(),
            4);
}

TEST(Samplers, ZeroTwoAndSobolCameraSamplesAreNets) {
  for (int spp : {4, 16, 64}) {
    auto z = sampler_from_text("net_z", R"(Sampler "02sequence")", spp);
    auto s = sampler_from_text("net_s", R"(Sampler "sobol")", spp, 5, {{-2, -2}, {50, 30}});
    for (Point2i p : {Point2i{0, 0}, Point2i{13, 7}, Point2i{-2, 29}, Point2i{47, -1}}) {
      EXPECT_TRUE(is_02_net(first_2d(*z, p))) << spp;
      EXPECT_TRUE(is_02_net(first_2d(*s, p))) << spp << " " << p.x << "," << p.y;
    }
  }
  // 02sequence's 1-D arrays: each sample's array is stratified.
  auto z = sampler_from_text("net_za", R"(Sampler "02sequence" "integer pixelsamples" 8)");
  int n = z->round_count(5);
  EXPECT_EQ(n, 8);
  z->request_1d_array(n);
  z->start_pixel({4, 4});
  do {
    const float* a = z->get_1d_array(n);
    ASSERT_NE(a, nullptr);
    EXPECT_TRUE(one_per_stratum(std::vector<float>(a, a + n)));
  } while (z->start_next_sample());
}

TEST(Samplers, SobolImageSamplesFormOneNet) {
  // Sample i of all pixels of a 2^k x 2^k image, placed in the image, is one
  // block of the (scrambled) sequence: a net over the whole image.
  auto s = sampler_from_text("net_image", R"(Sampler "sobol")", 4, 9, {{-3, 2}, {5, 10}});
  for (int sample = 0; sample < 4; ++sample) {
    std::vector<Vec2> pts;
    for (int y = 2; y < 10; ++y)
      for (int x = -3; x < 5; ++x) {
        s->start_pixel({x, y});
        s->set_sample_number(sample);
        Vec2 v = s->get_2d();
        pts.push_back({(float(x + 3) + v.x) / 8, (float(y - 2) + v.y) / 8});
      }
    EXPECT_TRUE(is_02_net(pts)) << sample;
  }
}

TEST(Samplers, HaltonCameraSamplesAreSpread) {
  // Halton's grid is 2^a x 3^b, not square: a pixel's consecutive samples
  // fill every cell of the 2x3 and 4x9 grids (Chinese remainder theorem),
  // and 16 of them every 1/16 in x (a square 4x4 grid does not hold).
  auto h = sampler_from_text("halton_spread", R"(Sampler "halton")", 36, 3, {{0, 0}, {100, 60}});
  for (Point2i p : {Point2i{0, 0}, Point2i{99, 59}, Point2i{31, 17}, Point2i{64, 2}}) {
    std::vector<Vec2> pts = first_2d(*h, p);
    EXPECT_TRUE(one_per_cell(pts, 4, 9)) << p.x << "," << p.y;
    for (int block = 0; block < 6; ++block)
      EXPECT_TRUE(one_per_cell(
          std::vector<Vec2>(pts.begin() + 6 * block, pts.begin() + 6 * block + 6), 2, 3));
    std::vector<float> xs;
    for (int i = 0; i < 16; ++i) xs.push_back(pts[size_t(i)].x);
    EXPECT_TRUE(one_per_stratum(xs));
  }
  // Pixels 128 apart share their pattern (pbrt-v3's 128-pixel tile); others differ.
  auto wide = sampler_from_text("halton_tile", R"(Sampler "halton")", 4, 3, {{0, 0}, {300, 200}});
  std::vector<Vec2> a = first_2d(*wide, {5, 6}), b = first_2d(*wide, {133, 6}),
                    c = first_2d(*wide, {6, 6});
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(a[size_t(i)].x, b[size_t(i)].x);
    EXPECT_EQ(a[size_t(i)].y, b[size_t(i)].y);
  }
  EXPECT_NE(a[0].x + 2 * a[0].y, c[0].x + 2 * c[0].y);
  auto centre =
      sampler_from_text("halton_c", R"(Sampler "halton" "bool samplepixelcenter" "true")");
  for (Vec2 v : first_2d(*centre, {3, 3})) {
    EXPECT_EQ(v.x, 0.5f);
    EXPECT_EQ(v.y, 0.5f);
  }
}

// Seed 0 keeps pbrt-v3's in-pixel positions (the radical inverses of the
// index's remaining digits); other seeds scramble them, so two renders with
// different seeds do not share their positions (the convergence test's two
// halves must measure the noise positions cause), while each still fills
// every stratum (HaltonCameraSamplesAreSpread runs with a seed).
TEST(Samplers, HaltonSeedsScrambleInPixelPositionsAndSeedZeroIsPbrtV3s) {
  const Bounds2i b{{0, 0}, {100, 60}};
  auto s0 = sampler_from_text("halton_seed0", R"(Sampler "halton")", 36, 0, b);
  auto s1 = sampler_from_text("halton_seed1", R"(Sampler "halton")", 36, 1, b);
  auto s2 = sampler_from_text("halton_seed2", R"(Sampler "halton")", 36, 2, b);
  // Pixel (0, 0)'s samples are indices n * 128 * 81 (2^7 = 128 >= 100, 3^4 = 81 >= 60).
  std::vector<Vec2> p0 = first_2d(*s0, {0, 0});
  for (int n = 0; n < 36; ++n) {
    const uint64_t index = uint64_t(n) * 128 * 81;
    EXPECT_EQ(p0[size_t(n)].x, std::min(float(radical_inverse(2, index >> 7)), kOneMinusEpsilon));
    EXPECT_EQ(p0[size_t(n)].y, std::min(float(radical_inverse(3, index / 81)), kOneMinusEpsilon));
  }
  for (Point2i p : {Point2i{0, 0}, Point2i{31, 17}}) {
    std::vector<Vec2> a = first_2d(*s1, p), c = first_2d(*s2, p);
    EXPECT_TRUE(one_per_cell(a, 4, 9));
    EXPECT_TRUE(one_per_cell(c, 4, 9));
    int same = 0;
    for (size_t i = 0; i < a.size(); ++i) same += a[i].x == c[i].x && a[i].y == c[i].y;
    EXPECT_LT(same, 4) << "seeds 1 and 2 share in-pixel positions at " << p.x << "," << p.y;
  }
}

TEST(Samplers, LowDiscrepancyIntegratesBetterThanRandom) {
  // Integrate f(x, y) = x y (exact 1/4) with the camera dimensions of 256
  // samples, over 32 pixels; compare RMS errors.
  auto rms_error = [](Sampler& s) {
    double sum_sq = 0;
    int pixels = 0;
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 8; ++x, ++pixels) {
        double sum = 0;
        for (Vec2 v : first_2d(s, {x * 3, y * 5})) sum += double(v.x) * v.y;
        double err = sum / double(s.samples_per_pixel()) - 0.25;
        sum_sq += err * err;
      }
    return std::sqrt(sum_sq / pixels);
  };
  auto random = sampler_from_text("int_r", R"(Sampler "random")", 256);
  double random_error = rms_error(*random);
  EXPECT_GT(random_error, 0.005);  // about sqrt(7/144)/16 = 0.0138
  EXPECT_LT(random_error, 0.03);
  for (const Case& c : kAll) {
    if (std::string(c.name) == "random") continue;
    auto s = sampler_from_text(std::string("int_") + c.name, c.line, 256);
    double e = rms_error(*s);
    std::printf("%s: rms error %.2e (random %.2e)\n", c.name, e, random_error);
    EXPECT_LT(e, 0.25 * random_error) << c.name << " " << e << " vs random " << random_error;
  }
}

// Pearson's chi-square of counts against equal expected counts.
double chi_square_uniform(const std::vector<int>& counts) {
  double total = 0;
  for (int c : counts) total += c;
  const double expected = total / double(counts.size());
  double chi2 = 0;
  for (int c : counts) chi2 += (c - expected) * (c - expected) / expected;
  return chi2;
}

TEST(Samplers, HighDimensionsStayUniform) {
  // Past the tables (Sobol 128 dims, Halton 1000) values are hashed. Over many pixels and
  // samples, dimensions 1000-1099 must be uniform (16 bins), and consecutive dimensions must be
  // independent (8 x 8 bins of pairs): a hash that repeats, sticks, or ties one dimension to the
  // next fails one or the other. The thresholds are where the chi-square distribution's tail is
  // 2e-4 (15 and 63 degrees of freedom), and the values are a fixed sequence, so the test is
  // deterministic.
  for (const char* line : {R"(Sampler "sobol")", R"(Sampler "halton")"}) {
    auto s = sampler_from_text("high", line, 16);
    std::vector<int> bins(16, 0), pairs(64, 0), per_pixel_first(16, 0);
    for (int p = 0; p < 40; ++p) {
      s->start_pixel({p, 2 * p});
      do {
        float previous = 0;
        for (int d = 0; d < 1100; ++d) {
          const float v = s->get_1d();
          ASSERT_TRUE(v >= 0 && v < 1) << line << " dimension " << d << ": " << v;
          if (d < 1000) continue;
          ++bins[size_t(v * 16)];
          if (d % 2 == 1) ++pairs[size_t(previous * 8) * 8 + size_t(v * 8)];
          if (d == 1000) ++per_pixel_first[size_t(v * 16)];
          previous = v;
        }
      } while (s->start_next_sample());
    }
    EXPECT_LT(chi_square_uniform(bins), 42.6) << line;    // 64000 values
    EXPECT_LT(chi_square_uniform(pairs), 111.0) << line;  // 32000 pairs
    // One dimension across the 640 samples of 40 pixels: not one value over and over.
    EXPECT_LT(chi_square_uniform(per_pixel_first), 42.6) << line;
  }
}

TEST(Samplers, MaxMinDistCameraSamples) {
  // x = i / spp exactly; y = C_k i takes every 1/spp stratum once (each
  // tabulated matrix is nonsingular), for every power of two we can afford.
  for (int k = 0; k <= 16; ++k) {
    auto s = sampler_from_text("maxmin", R"(Sampler "maxmindist")", 1 << k);
    ASSERT_EQ(s->samples_per_pixel(), 1 << k);
    std::vector<Vec2> pts = first_2d(*s, {2, 3});
    std::vector<float> xs, ys;
    for (Vec2 v : pts) {
      xs.push_back(v.x);
      ys.push_back(v.y);
      EXPECT_EQ(v.x * float(1 << k), std::floor(v.x * float(1 << k))) << k;
    }
    EXPECT_TRUE(one_per_stratum(xs)) << k;
    EXPECT_TRUE(one_per_stratum(ys)) << k;
  }
  EXPECT_EQ(sampler_from_text("maxmin5", R"(Sampler "maxmindist" "integer pixelsamples" 5)")
                ->samples_per_pixel(),
            8);
  EXPECT_EQ(sampler_from_text("maxmin_big", R"(Sampler "maxmindist")", 100000)->samples_per_pixel(),
            65536);
}

}  // namespace
}  // namespace rt
