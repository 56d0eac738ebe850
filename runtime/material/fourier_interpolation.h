// runtime/material/fourier_interpolation.h — the interpolation and sampling routines of
// tabulated Fourier BSDFs (book sections 8.6.1-8.6.2 and 14.1.5).
//
// Non-uniform Catmull-Rom splines (catmull_rom.h) interpolate a table over its zenith
// nodes. fourier_series() sums
// a_k cos(k phi) with the Chebyshev recurrence (no trigonometric call per term);
// sample_fourier() draws phi in [0, 2 pi) proportional to that series by Newton-bisection
// on its integral. All are plain functions of arrays: no allocation, thread-safe.
#pragma once

#include "runtime/material/catmull_rom.h"

namespace rt {

// sum_{k < m} a[k] cos(k phi).
float fourier_series(const float* a, int m, double cos_phi);

// Samples phi in [0, 2 pi) with density proportional to fourier_series(ak, m, cos phi) (assumed
// non-negative); recip[k] = 1 / k. Returns the series at phi; *pdf is its density in phi
// (0 when ak[0] <= 0).
float sample_fourier(const float* ak, const float* recip, int m, float u, float* pdf, float* phi);

}  // namespace rt
