// tools/compare/convergence.h — does a render converge to a reference image?
//
// The noise-aware test every reference comparison uses (one rule for all
// scenes, no per-scene factors): two renders A and B at half the
// reference's samples per pixel with different seeds; ours = (A + B) / 2.
// On whole 8x8 blocks of the data window, per channel:
//   d   = block mean of ours - block mean of the reference
//   var = sum over the block's pixels of ((A - B) / 2)^2 / 64^2
//   z   = d / sqrt(2 var + (0.005 ref)^2 + 1e-8)
// (the variance counts twice: once for ours, once for the reference, which
// has the same sample count). A reference with a different sample count than
// A + B together (this project's own high-spp references, tools/accuracy)
// gives `spp_ratio` = (A + B spp) / reference spp: its variance is ours
// times that ratio, and 2 var becomes (1 + spp_ratio) var. A block passes when |z| < 4 in every
// channel; the images match when at least 99% of blocks pass and each channel's whole-image mean is
// within 1% of the reference's.
#pragma once

#include <string>

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

// ours | reference | signed difference (red: ours brighter, blue: darker,
// scaled so 10% of the reference's mean is full intensity), sRGB.
rt::ImageRgb side_by_side(const rt::ImageRgb& a, const rt::ImageRgb& b, const rt::ImageRgb& ref);

}  // namespace compare
