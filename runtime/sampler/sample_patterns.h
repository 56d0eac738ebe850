// runtime/sampler/sample_patterns.h — the per-pixel point sets of pbrt-v3's
// pixel samplers: jittered strata, Latin hypercube, shuffles, and scrambled
// (0,2)-sequence points generated in Gray-code order.
//
// All values are clamped below 1. Every function draws from the Rng it is
// given, in a fixed order, so a seeded Rng gives a reproducible pattern.
#pragma once

#include <cstdint>

#include "runtime/core/rng.h"
#include "runtime/core/vec.h"

namespace rt {

// n strata of [0,1), one value each (at the centre when !jitter).
void stratified_1d(float* out, int n, Rng& rng, bool jitter);
// nx * ny strata of [0,1)^2, row by row.
void stratified_2d(Vec2* out, int nx, int ny, Rng& rng, bool jitter);
// n points of [0,1)^dims (dims floats per point): one per stratum on every axis.
void latin_hypercube(float* out, int n, int dims, Rng& rng);
// Shuffles count blocks of `block` consecutive floats.
void shuffle_blocks(float* data, int count, int block, Rng& rng);
void shuffle_points(Vec2* data, int count, int block, Rng& rng);

// Scrambled van der Corput / (0,2)-sequence values, n_per_sample per pixel
// sample for n_samples pixel samples, shuffled within and between pixel
// samples (pbrt-v3's VanDerCorput and Sobol2D helpers).
void van_der_corput_pattern(int n_per_sample, int n_samples, float* out, Rng& rng);
void sobol_2d_pattern(int n_per_sample, int n_samples, Vec2* out, Rng& rng);

}  // namespace rt
