// tests/runtime/material/lobe_checks.h — consistency checks every lobe type must pass.
//
// A lobe (rt::Bxdf, rt::DisneyLobe, ...) has sample_f(wo, &wi, u, &pdf),
// f(wo, wi), pdf(wo, wi) and flags in its local frame. These checks hold for
// any of them: what sample_f returns is f() and pdf() of its own direction,
// and the albedo estimated by importance sampling equals the one estimated
// with uniform sphere directions (f and pdf tell one story). Both also require
// that most samples be real (non-zero pdf): a lobe whose sampling failed on
// every call would otherwise pass them without checking anything.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "runtime/core/rng.h"
#include "runtime/core/sampling.h"
#include "runtime/material/bxdf.h"
#include "runtime/material/microfacet.h"

namespace material_test {

// A microfacet distribution with these alphas (the tests' lobes take them as written).
inline rt::MicrofacetDistribution microfacet(rt::MicrofacetKind kind, float ax, float ay) {
  rt::MicrofacetDistribution d;
  d.kind = kind;
  d.alpha_x = ax;
  d.alpha_y = ay;
  return d;
}

// The least share of sample_f calls that must give a direction with a non-zero pdf. Lobes that
// sample the hemisphere (or a microfacet normal whose reflection may fall below it, which the
// grazing directions of the tests provoke) stay well above it.
constexpr double kMinSampledShare = 0.5;

template <class Lobe>
void expect_sample_matches_evaluation(const Lobe& lobe, rt::Vec3 wo, int n, rt::Rng& rng,
                                      const std::string& name) {
  int sampled = 0;
  for (int i = 0; i < n; ++i) {
    rt::Vec3 wi;
    float pdf;
    rt::Rgb f = lobe.sample_f(wo, &wi, {rng.next_float(), rng.next_float()}, &pdf);
    if (pdf == 0) continue;
    ++sampled;
    rt::Rgb fe = lobe.f(wo, wi);
    float pe = lobe.pdf(wo, wi);
    ASSERT_NEAR(pdf, pe, 2e-3f * std::max(1.f, pe)) << name;
    for (int k = 0; k < 3; ++k) ASSERT_NEAR(f[k], fe[k], 2e-3f * std::max(1.f, fe[k])) << name;
  }
  EXPECT_GE(sampled, kMinSampledShare * n) << name << " wo.z=" << wo.z << ": " << sampled << " of "
                                           << n << " samples had a non-zero pdf";
}

// Checks the two albedo estimates agree (5 sigma + 2e-3) and returns the
// importance-sampled one (green channel).
template <class Lobe>
double expect_albedo_estimates_agree(const Lobe& lobe, rt::Vec3 wo, int n, uint64_t seed,
                                     const std::string& name) {
  rt::Rng rng(seed);
  double is = 0, uni = 0, uni2 = 0;
  int sampled = 0;
  for (int i = 0; i < n; ++i) {
    rt::Vec3 wi;
    float pdf;
    rt::Rgb f = lobe.sample_f(wo, &wi, {rng.next_float(), rng.next_float()}, &pdf);
    if (pdf > 0) {
      is += f.g * std::fabs(wi.z) / pdf;
      ++sampled;
    }
    // Lobes leave the reflection/transmission choice to the BSDF, so count
    // only the side(s) the lobe's flags cover.
    rt::Vec3 wu = rt::uniform_sample_sphere({rng.next_float(), rng.next_float()});
    bool same = wo.z * wu.z > 0;
    bool covered = same ? (lobe.flags & rt::kReflection) : (lobe.flags & rt::kTransmission);
    double v = covered ? lobe.f(wo, wu).g * std::fabs(wu.z) / rt::uniform_sphere_pdf() : 0;
    uni += v;
    uni2 += v * v;
  }
  is /= n;
  uni /= n;
  double sigma = std::sqrt((uni2 / n - uni * uni) / n);
  EXPECT_NEAR(is, uni, 5 * sigma + 2e-3) << name << " wo.z=" << wo.z;
  EXPECT_GE(sampled, kMinSampledShare * n) << name << " wo.z=" << wo.z << ": " << sampled << " of "
                                           << n << " samples had a non-zero pdf";
  return is;
}

}  // namespace material_test
