// The convergence rule itself: it must accept a render that differs from the
// reference only by noise, and reject one that is off by a few percent or
// has a wrong region, whatever the noise level.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "tools/compare/convergence.h"

namespace {

rt::ImageRgb image(int w, int h) {
  rt::ImageRgb img;
  img.data_window = {{0, 0}, {w, h}};
  img.display_window = img.data_window;
  img.rgb.assign(size_t(w) * h * 3, 0.f);
  return img;
}

// A smooth "true image" with per-pixel noise of relative size sigma, as a
// Monte Carlo render at some sample count would have.
rt::ImageRgb noisy(int w, int h, float sigma, float bias, uint32_t seed) {
  rt::ImageRgb img = image(w, h);
  std::mt19937 gen(seed);
  std::normal_distribution<float> n(0, 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        float truth = 0.2f + 0.5f * float(x) / w + 0.1f * c + 0.2f * float(y) / h;
        img.rgb[3 * (size_t(y) * w + x) + c] = truth * (1 + bias) * (1 + sigma * n(gen));
      }
  return img;
}

// On a 128x96 image: the top-left quarter's values become gain(v), the bottom-right's lose(v).
template <class Gain, class Lose>
void move_light(rt::ImageRgb* img, Gain gain, Lose lose) {
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x)
      for (int c = 0; c < 3; ++c) {
        size_t i = 3 * (size_t(y) * 128 + x) + c, j = 3 * (size_t(y + 48) * 128 + x + 64) + c;
        img->rgb[i] = gain(img->rgb[i]);
        img->rgb[j] = lose(img->rgb[j]);
      }
}

TEST(ConvergenceRule, AcceptsNoiseOnlyDifferences) {
  // Ours at half spp per render: each has sqrt(2) more noise than the reference.
  for (float sigma : {0.01f, 0.1f, 0.3f}) {
    rt::ImageRgb ref = noisy(128, 96, sigma, 0, 1);
    rt::ImageRgb a = noisy(128, 96, sigma * 1.41421f, 0, 2);
    rt::ImageRgb b = noisy(128, 96, sigma * 1.41421f, 0, 3);
    compare::ConvergenceResult r = compare::check_convergence(a, b, ref);
    EXPECT_TRUE(r.ok) << "sigma " << sigma << ": " << r.blocks_passed << "/" << r.blocks;
    EXPECT_EQ(r.blocks, 16 * 12);
  }
}

// Our two halves together with 4x the reference's samples (this project's own high-spp
// references checked against pbrt-v3's), or ours from a less noisy estimator than the
// reference's: the reference has twice our per-half noise. The rule accepts pure noise with
// the sample counts given and also without them (the scatter of the pixel differences measures
// the reference's noise), and still rejects a bias.
TEST(ConvergenceRule, AcceptsAReferenceNoisierThanOurs) {
  const float sigma = 0.2f;
  rt::ImageRgb ref = noisy(128, 96, sigma, 0, 1);
  rt::ImageRgb a = noisy(128, 96, sigma / 1.41421f, 0, 2);
  rt::ImageRgb b = noisy(128, 96, sigma / 1.41421f, 0, 3);
  for (double spp_ratio : {1.0, 4.0}) {
    compare::ConvergenceResult r = compare::check_convergence(a, b, ref, spp_ratio);
    EXPECT_TRUE(r.ok) << "spp ratio " << spp_ratio << ": " << r.blocks_passed << "/" << r.blocks;
    EXPECT_GE(r.blocks_passed, r.blocks - 1) << "spp ratio " << spp_ratio;
  }
  rt::ImageRgb a2 = noisy(128, 96, 0.005f, 0.02f, 2), b2 = noisy(128, 96, 0.005f, 0.02f, 3);
  rt::ImageRgb ref2 = noisy(128, 96, 0.01f, 0, 1);
  EXPECT_FALSE(compare::check_convergence(a2, b2, ref2, 4.0).ok);
  EXPECT_FALSE(compare::check_convergence(a2, b2, ref2).ok);
}

TEST(ConvergenceRule, RejectsABiasOfTwoPercent) {
  for (float sigma : {0.0f, 0.01f, 0.05f}) {
    rt::ImageRgb ref = noisy(128, 96, sigma, 0, 1);
    rt::ImageRgb a = noisy(128, 96, sigma * 1.41421f, 0.02f, 2);
    rt::ImageRgb b = noisy(128, 96, sigma * 1.41421f, 0.02f, 3);
    EXPECT_FALSE(compare::check_convergence(a, b, ref).ok) << "sigma " << sigma;
  }
}

TEST(ConvergenceRule, RejectsAWrongRegionEvenWhenMeansAgree) {
  rt::ImageRgb ref = noisy(128, 96, 0.01f, 0, 1);
  rt::ImageRgb a = noisy(128, 96, 0.014f, 0, 2), b = noisy(128, 96, 0.014f, 0, 3);
  // Move light from one quarter of the image to another: whole-image means stay.
  for (rt::ImageRgb* img : {&a, &b})
    move_light(
        img, [](float v) { return v + 0.1f; }, [](float v) { return v - 0.1f; });
  compare::ConvergenceResult r = compare::check_convergence(a, b, ref);
  EXPECT_FALSE(r.ok);
  EXPECT_LT(r.blocks_passed, r.blocks * 0.6);
}

// A reference much noisier than ours widens each block's margin to its own noise, no more: a
// region off by 5% still fails, block by block, though the whole-image means agree.
TEST(ConvergenceRule, ANoisyReferenceStillRevealsAWrongRegion) {
  rt::ImageRgb ref = noisy(128, 96, 0.05f, 0, 1);
  rt::ImageRgb a = noisy(128, 96, 0.005f, 0, 2), b = noisy(128, 96, 0.005f, 0, 3);
  for (rt::ImageRgb* img : {&a, &b})
    move_light(
        img, [](float v) { return v * 1.05f; }, [](float v) { return v * 0.95f; });
  compare::ConvergenceResult r = compare::check_convergence(a, b, ref);
  EXPECT_FALSE(r.ok);
  EXPECT_LT(r.blocks_passed, r.blocks * 0.6);
}

TEST(ConvergenceRule, ImagesOfDifferentSizesAreAnErrorNotAPass) {
  rt::ImageRgb ref = noisy(64, 64, 0.01f, 0, 1), a = noisy(64, 32, 0.01f, 0, 2);
  compare::ConvergenceResult r = compare::check_convergence(a, a, ref);
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.error.empty());
}

}  // namespace

namespace {

// Noise correlated between pixels, as mlt's chains and sppm's photons make it: each render has
// blotches (constant over 4x4 pixel patches) and a brightness factor of its own (mlt's
// bootstrap estimate).
rt::ImageRgb blotchy(int w, int h, float sigma, float brightness_sigma, float bias, uint32_t seed) {
  rt::ImageRgb img = image(w, h);
  std::mt19937 gen(seed);
  std::normal_distribution<float> n(0, 1);
  const float brightness = 1 + brightness_sigma * n(gen);
  std::vector<float> patch(size_t((w / 4 + 1) * (h / 4 + 1)));
  for (float& p : patch) p = sigma * n(gen);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        float truth = 0.2f + 0.5f * float(x) / w + 0.1f * c + 0.2f * float(y) / h;
        img.rgb[3 * (size_t(y) * w + x) + c] =
            truth * (1 + bias) * brightness * (1 + patch[size_t((y / 4) * (w / 4 + 1) + x / 4)]);
      }
  return img;
}

}  // namespace

TEST(ConvergenceRule, StudentQuantileMatchesTheNormalTail) {
  const double t7 = compare::student_t_matching_normal(4, 7);
  const double t15 = compare::student_t_matching_normal(4, 15);
  const double t1000 = compare::student_t_matching_normal(4, 1000);
  EXPECT_GT(t7, t15);
  EXPECT_GT(t15, t1000);
  EXPECT_NEAR(t1000, 4, 0.02);
  // Tabulated Student t quantiles (two-sided 0.001 at 7 dof: 5.408) bracket it.
  EXPECT_GT(t7, 5.408);
}

// Correlated noise: the two-render rule (pixel-wise variance) rejects a render that differs
// only by noise; the spread of 8 renders' block means accepts it, and still rejects 2% bias.
TEST(ConvergenceRule, SpreadRuleJudgesCorrelatedNoise) {
  const float sigma = 0.05f, brightness = 0.02f;
  rt::ImageRgb ref = noisy(128, 96, 0.002f, 0, 1);
  std::vector<rt::ImageRgb> renders, biased;
  for (uint32_t k = 0; k < 8; ++k) {
    renders.push_back(blotchy(128, 96, sigma, brightness, 0, 10 + k));
    biased.push_back(blotchy(128, 96, sigma * 0.2f, brightness * 0.2f, 0.02f, 30 + k));
  }
  EXPECT_FALSE(compare::check_convergence(renders[0], renders[1], ref).ok);
  compare::ConvergenceResult r = compare::check_convergence_spread(renders, ref);
  EXPECT_TRUE(r.ok) << r.blocks_passed << "/" << r.blocks << ", means " << r.mean_rel_error[0]
                    << " " << r.mean_rel_error[1];
  compare::ConvergenceResult rb = compare::check_convergence_spread(biased, ref);
  EXPECT_FALSE(rb.ok) << rb.blocks_passed << "/" << rb.blocks;
  EXPECT_FALSE(compare::check_convergence_spread({renders[0], renders[1], renders[2]}, ref).ok);
}
