// tests/runtime/stability/stability_support.h — summaries of rendered test images.
//
// The numerical-stability tests (issue 9) build their scenes as pbrt-v3 text
// and render them with render_text() (runtime/render_text.h). Helpers here
// summarise an image: finiteness of every pixel, mean and its standard error
// (pixels of an independent sampler under a box filter of radius 0.5 are
// independent estimates).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "runtime/core/rgb.h"
#include "runtime/render_text.h"

namespace rt {

// Pixels with a NaN or infinite channel.
inline int count_nonfinite(const Rendered& r) {
  int n = 0;
  for (const Rgb& p : r.pixels) n += !p.is_finite();
  return n;
}

// Mean of one channel-average per pixel, and the standard error of that mean.
struct MeanAndError {
  double mean = 0, sigma = 0, sd = 0;
};
inline MeanAndError mean_and_error(const Rendered& r) {
  MeanAndError m;
  const double n = double(r.pixels.size());
  for (const Rgb& p : r.pixels) m.mean += p.average();
  m.mean /= n;
  double var = 0;
  for (const Rgb& p : r.pixels) var += (p.average() - m.mean) * (p.average() - m.mean);
  m.sd = std::sqrt(var / (n - 1));
  m.sigma = m.sd / std::sqrt(n);
  return m;
}

// %.9g: floats survive the round trip through scene text exactly.
inline std::string fmt(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

}  // namespace rt
