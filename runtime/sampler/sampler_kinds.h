// runtime/sampler/sampler_kinds.h — constructors of the concrete samplers,
// for make_sampler() (the classes themselves stay in their .cpp files).
//
// Counts arrive already adjusted (overrides and power-of-two rounding done by
// make_sampler()).
#pragma once

#include <memory>

#include "runtime/sampler/sampler.h"

namespace rt {

std::unique_ptr<Sampler> make_halton_sampler(int64_t spp, uint64_t seed, const Bounds2i& bounds,
                                             bool sample_pixel_center);
std::unique_ptr<Sampler> make_sobol_sampler(int64_t spp, uint64_t seed, const Bounds2i& bounds);
std::unique_ptr<Sampler> make_zero_two_sampler(int64_t spp, int dimensions, uint64_t seed);
// spp: a power of two up to 2^16.
std::unique_ptr<Sampler> make_maxmindist_sampler(int64_t spp, int dimensions, uint64_t seed);
std::unique_ptr<Sampler> make_stratified_sampler(int xsamples, int ysamples, bool jitter,
                                                 int dimensions, uint64_t seed);
std::unique_ptr<Sampler> make_random_sampler(int64_t spp, uint64_t seed);

}  // namespace rt
