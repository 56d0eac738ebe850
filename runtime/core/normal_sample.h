// runtime/core/normal_sample.h — standard normal numbers from an Rng, by the ziggurat method.
//
// Metropolis light transport draws one normal number per primary-sample coordinate per small
// step (mlt_sampler.cpp). Through the inverse error function that is a logarithm and a chain
// of eighteen dependent multiply-adds per number (12% of an mlt render, perf); the ziggurat
// (G. Marsaglia and W. W. Tsang, "The Ziggurat Method for Generating Random Variables", J.
// Statistical Software 5(8), 2000) answers 98.8% of draws with one integer, a table lookup
// and a multiplication. The layer and the value take different bits of the integer (J. A.
// Doornik's remark on the original, 2005). Deterministic for a given Rng state; thread-safe
// (the tables are built once, on first use).
#pragma once

#include "runtime/core/rng.h"

namespace rt {

// A standard normal number (mean 0, variance 1), untruncated; consumes one or more of rng's
// numbers.
float normal_sample(Rng& rng);

}  // namespace rt
