// runtime/film/error_estimate.h — the render's own error, from its two half images.
//
// The film keeps two halves of every pixel's samples apart (film.h, sample_half),
// two independent estimates e and o of the converged pixel c. With equal halves the
// image is about (e + o) / 2, whose variance is Var(e) / 2 = E[(e - o)^2] / 4; and
// E[e o] = c^2 since the halves are independent. So the squared relative error that
// pbrt-converge measures against a reference, (x - c)^2 / (c^2 + 0.01), is estimated
// per pixel and channel by
//
//     ((e - o)^2 / 4) / (max(e o, m^2 / 4) + 0.01),   m = (e + o) / 2
//
// (the m^2 / 4 floor keeps a pixel whose one half happens to be black from counting
// as if the scene were black there), and the image's relative error is the square
// root of its mean over pixels and channels. With fewer than two samples per pixel
// there is no second half and no estimate.
//
// How good it is (tests/runtime/render/error_estimate_test.cpp, against long
// references of shared scenes): with independent samples (the random sampler) within
// 0.7x-1.4x of the true error from 4 spp on. Low-discrepancy samplers converge faster
// than either half of their samples shows, so there the estimate is pessimistic, more
// so as samples grow and the fewer dimensions the integrand has: 1.0x-1.6x on
// path-traced scenes at 4-64 spp, up to 3.6x on a whitted depth-of-field scene at 64
// spp. A target error is then reached later than needed, never missed.
#pragma once

#include <string>
#include <vector>

#include "runtime/film/film.h"

namespace rt {

struct ErrorEstimate {
  bool valid = false;    // two or more samples per pixel
  double rel_error = 0;  // sqrt(relMSE), a fraction (0.01 is 1%)
};

// per_pixel (optional): the per-pixel, per-channel estimate sqrt(...) above, 3 floats per
// cropped pixel in row order (zeros when not valid).
ErrorEstimate estimate_error(const Film& film, std::vector<float>* per_pixel = nullptr);

// "2.31%": an error estimate (a fraction) as the progress line and --stats print it.
std::string error_percent(double fraction);

}  // namespace rt
