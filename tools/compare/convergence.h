// tools/compare/convergence.h — does a render converge to a reference image?
//
// The noise-aware test every reference comparison uses (one rule for all
// scenes, no per-scene factors): two renders A and B at half the
// reference's samples per pixel with different seeds; ours = (A + B) / 2.
// On whole 8x8 blocks of the data window, per channel:
//   d   = block mean of ours - block mean of the reference
//   var = sum over the block's pixels of ((A - B) / 2)^2 / 64^2
//   paired = sample variance of the 64 pixel differences (ours - reference) / 64
//   z   = d / sqrt(max(2 var, paired) + (0.005 ref)^2 + 1e-8)
// (2 var: the variance counts twice, once for ours, once for the reference, as if it had our
// noise. A reference with a different sample count than A + B together (this project's own
// high-spp references, tools/accuracy) gives `spp_ratio` = (A + B spp) / reference spp: its
// variance is ours times that ratio, and 2 var becomes (1 + spp_ratio) var. paired measures
// both noises from the data: it is the larger where the reference is noisier than ours, as
// pbrt-v3's references are where our path integrator's direct lighting, split as pbrt-v4's,
// is less noisy than pbrt-v3's: glossy reflections of small lights among several.)
// A block passes when |z| < 4 in every
// channel; the images match when at least 99% of blocks pass and each channel's whole-image mean is
// within 1% of the reference's.
#pragma once

#include <string>

#include <vector>

#include "runtime/film/image_io.h"

namespace compare {

struct ConvergenceResult {
  bool ok = false;
  int blocks = 0, blocks_passed = 0;
  double worst_z = 0;
  double mean_ours[3] = {0, 0, 0}, mean_ref[3] = {0, 0, 0};
  double mean_rel_error[3] = {0, 0, 0};
  std::string error;  // images that cannot be compared (sizes, windows)
};

ConvergenceResult check_convergence(const rt::ImageRgb& a, const rt::ImageRgb& b,
                                    const rt::ImageRgb& ref, double spp_ratio = 1);

// The same rule for renders whose noise is correlated from pixel to pixel (mlt's chains,
// sppm's photons), where the pixel-wise variance of two renders underestimates a block's:
// n >= 4 independent renders (different seeds, equal sample counts), ours their mean; each
// block's variance is the spread of the n renders' block means (sample variance / n), and
// the block passes when |d| / sqrt((1 + spp_ratio) var + (0.005 ref)^2) stays below the
// Student-t quantile with n - 1 degrees of freedom that has the normal's two-sided tail at 4
// (so false alarms are as rare as in the two-render rule). A channel's whole-image mean
// passes within 1% of the reference's or within the quantile matching the normal's 3-sigma
// tail of its own spread across the renders (mlt's brightness comes from its bootstrap
// estimate, which varies by a few percent per render; three tests need no 4-sigma margin). At least
// 99% of blocks must pass, as above.
ConvergenceResult check_convergence_spread(const std::vector<rt::ImageRgb>& renders,
                                           const rt::ImageRgb& ref, double spp_ratio = 1);

// The two-sided Student-t quantile with `dof` degrees of freedom whose tail probability equals
// the standard normal's beyond +-z.
double student_t_matching_normal(double z, int dof);

// ours | reference | signed difference (red: ours brighter, blue: darker,
// scaled so 10% of the reference's mean is full intensity), sRGB.
rt::ImageRgb side_by_side(const rt::ImageRgb& a, const rt::ImageRgb& b, const rt::ImageRgb& ref);

}  // namespace compare
