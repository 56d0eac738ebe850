// runtime/material/disney_bxdf.h — the lobes of pbrt-v3's Disney material
// (Burley 2012 and 2015, "Physically Based Shading at Disney" and "Extending
// the Disney BRDF to a BSDF with Integrated Subsurface Scattering").
//
// One tagged plain struct, like Bxdf (bxdf.h), in the local shading frame:
// Fresnel-shaped diffuse, its flat fake-subsurface variant, retro-
// reflection, sheen, clearcoat (GTR1 lobe, Schlick Fresnel at 0.04, fixed
// 0.25-roughness GGX masking), the specular lobe (anisotropic Trowbridge-
// Reitz with the Disney Fresnel blend of dielectric and Schlick-metal), rough
// transmission, and the thin surface's Lambertian transmission. As in
// pbrt-v3, the specular lobe and the solid surface's transmission mask with
// the separable Smith term G1(wo) G1(wi) (its DisneyMicrofacetDistribution);
// the thin surface's transmission uses the standard one. Like pbrt-v3's
// BxDFs, the reflection lobes' f() does not test the hemispheres: Bsdf
// decides reflection vs transmission with the geometric normal, so under a
// shading normal they may be asked about directions on opposite local sides.
//
// make_disney_lobes() is pbrt-v3's DisneyMaterial::ComputeScatteringFunctions
// after texture lookup: which lobes with which weights. The solid surface
// with a non-black scatterdistance scatters by a BSSRDF instead of its
// diffuse lobe; it reports that.
//
// Bxdf's kDisney kind carries a DisneyLobe and delegates to it; MaterialSet's
// "disney" material builds the lobes with make_disney_lobes().
#pragma once

#include <cstdint>

#include "runtime/core/rgb.h"
#include "runtime/core/vec.h"
#include "runtime/material/bxdf_flags.h"
#include "runtime/material/microfacet.h"

namespace rt {

enum class DisneyLobeKind : uint8_t {
  kDiffuse,
  kFakeSubsurface,
  kRetro,
  kSheen,
  kClearcoat,
  kSpecular,
  kTransmission,
  kDiffuseTransmission,
};

struct DisneyLobe {
  DisneyLobeKind kind = DisneyLobeKind::kDiffuse;
  uint8_t flags = kReflection | kDiffuse;
  TransportMode mode = TransportMode::kRadiance;
  bool separable_g = false;  // specular and solid transmission
  Rgb r;                     // weight: reflectance, specular's R0, transmittance
  float roughness = 0;       // fake subsurface, retro
  float clearcoat_alpha = 0.1f;
  float metallic = 0, eta = 1.5f;  // specular's Fresnel; transmission's index (inside)
  MicrofacetDistribution distribution;

  bool matches(uint8_t mask) const { return (flags & mask) == flags; }
  Rgb f(Vec3 wo, Vec3 wi) const;
  // As Bxdf::sample_f: *pdf is 0 when no direction was sampled.
  Rgb sample_f(Vec3 wo, Vec3* wi, Vec2 u, float* pdf) const;
  float pdf(Vec3 wo, Vec3 wi) const;
};

// The material's inputs at a point (textures already evaluated), with
// pbrt-v3's parameter meanings and defaults.
struct DisneyParams {
  Rgb color{0.5f};
  float metallic = 0, eta = 1.5f, roughness = 0.5f, specular_tint = 0, anisotropic = 0;
  float sheen = 0, sheen_tint = 0.5f, clearcoat = 0, clearcoat_gloss = 1, spec_trans = 0;
  Rgb scatter_distance;
  bool thin = false;
  float flatness = 0, diff_trans = 1;
};

inline constexpr int kMaxDisneyLobes = 8;

// Fills out[0..n) and returns n. A solid surface with a scatter distance has
// no diffuse lobe: light enters by specular transmission into a BSSRDF
// (pbrt-v3's DisneyBSSRDF); *subsurface is then set and the caller adds that
// transmission lobe (make_specular_transmission(1, 1, eta)) itself.
int make_disney_lobes(const DisneyParams& p, TransportMode mode, DisneyLobe out[kMaxDisneyLobes],
                      bool* subsurface = nullptr);

// Pieces the tests check against hand computation.
float schlick_weight(float cos_theta);              // (1 - cos)^5, clamped
float disney_gtr1(float cos_theta_h, float alpha);  // clearcoat's normal distribution
Rgb disney_fresnel(Rgb r0, float metallic, float eta, float cos_theta_i);

}  // namespace rt
