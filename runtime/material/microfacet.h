// runtime/material/microfacet.h — microfacet distributions (book section 8.4).
//
// Trowbridge-Reitz (GGX) and Beckmann-Spizzichino, anisotropic (alpha_x,
// alpha_y), in the local shading frame. D is the normal distribution, lambda
// the Smith auxiliary function behind the masking terms G1 and G. Sampling
// draws microfacet normals from the distribution of normals visible from wo
// (Heitz and d'Eon 2014), which is what every pbrt-v3 material uses; pdf() is
// the density of that sampling over microfacet normals. roughness_to_alpha is
// pbrt-v3's remapping of the user's "roughness" (the same polynomial for both
// distributions in pbrt-v3).
#pragma once

#include <cstdint>

#include "runtime/core/vec.h"
#include "runtime/material/local_frame.h"

namespace rt {

enum class MicrofacetKind : uint8_t { kTrowbridgeReitz, kBeckmann };

float roughness_to_alpha(float roughness);

struct MicrofacetDistribution {
  MicrofacetKind kind = MicrofacetKind::kTrowbridgeReitz;
  float alpha_x = 1, alpha_y = 1;

  float d(Vec3 wh) const;
  float lambda(Vec3 w) const;
  float g1(Vec3 w) const { return 1 / (1 + lambda(w)); }
  float g(Vec3 wo, Vec3 wi) const { return 1 / (1 + lambda(wo) + lambda(wi)); }
  // A visible microfacet normal, on wo's side of the surface.
  Vec3 sample_wh(Vec3 wo, Vec2 u) const;
  // Density of sample_wh over wh (solid angle).
  float pdf(Vec3 wo, Vec3 wh) const;
  // The same from D(wh) and G1(wo) a caller already has.
  static float pdf_given(float d_wh, float g1_wo, Vec3 wo, Vec3 wh) {
    return d_wh * g1_wo * abs_dot(wo, wh) / abs_cos_theta(wo);
  }
};

}  // namespace rt
