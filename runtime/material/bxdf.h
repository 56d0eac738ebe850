// runtime/material/bxdf.h — the reflection models of book chapter 8 as one
// tagged plain struct.
//
// A Bxdf is a lobe in the local shading frame (+z = shading normal): f, a
// sample with its pdf, and pdf. Kinds are dispatched by a switch (no virtual
// calls, no heap): Lambertian reflection and transmission, Oren-Nayar,
// specular reflection and transmission, FresnelSpecular (both, chosen by
// Fresnel), microfacet reflection and transmission, FresnelBlend, and the
// Disney material's lobes (kDisney: f/sample_f/pdf are the carried
// DisneyLobe's, disney_bxdf.h), and the fourier material's tabulated BSDF
// (kFourier: a pointer to its table, fourier_bxdf.h), and the subsurface exit lobe
// (kBssrdfExit), and pbrt-v3's hair BSDF (kHair: the carried HairLobe,
// hair_bxdf.h). Payloads only one kind reads share storage
// in an anonymous union (Bsdf holds 8 Bxdfs inline, so size matters): a new
// kind with its own plain-data payload goes there too. Every lobe
// carries `scale` (1 unless a mix material weighted it: pbrt-v3's ScaledBxDF,
// which scales f and the sampled value but not the pdf). Build lobes with the
// make_* functions; flags follow pbrt-v3's BxDFType.
#pragma once

#include <cstdint>
#include <type_traits>

#include "runtime/core/rgb.h"
#include "runtime/core/vec.h"
#include "runtime/material/bxdf_flags.h"
#include "runtime/material/disney_bxdf.h"
#include "runtime/material/fresnel.h"
#include "runtime/material/hair_bxdf.h"
#include "runtime/material/microfacet.h"

namespace rt {

enum class BxdfKind : uint8_t {
  kLambertianReflection,
  kLambertianTransmission,
  kOrenNayar,
  kSpecularReflection,
  kSpecularTransmission,
  kFresnelSpecular,
  kMicrofacetReflection,
  kMicrofacetTransmission,
  kFresnelBlend,
  kDisney,
  kFourier,
  kBssrdfExit,
  kHair,
};

struct FourierTable;  // runtime/material/fourier_bxdf.h

struct Bxdf {
  // Spelled out: a union member with a non-trivial default constructor
  // deletes the implicit one.
  Bxdf() : fresnel() {}

  BxdfKind kind = BxdfKind::kLambertianReflection;
  uint8_t flags = kReflection | kDiffuse;
  TransportMode mode = TransportMode::kRadiance;
  Rgb r;                       // reflectance (FresnelBlend: Rd)
  Rgb t;                       // transmittance (FresnelBlend: Rs)
  Rgb scale{1};                // mix weight
  float eta_a = 1, eta_b = 1;  // outside (+z) and inside indices
  float oren_a = 1, oren_b = 0;
  union {
    Fresnel fresnel;              // specular and microfacet reflection
    DisneyLobe disney;            // kDisney: the whole lobe (r, t, eta, ... unused)
    const FourierTable* fourier;  // kFourier: the material's table
    HairLobe hair;                // kHair: the whole lobe
  };
  MicrofacetDistribution distribution;

  // True when every flag of this lobe is among `mask`'s.
  bool matches(uint8_t mask) const { return (flags & mask) == flags; }

  Rgb f(Vec3 wo, Vec3 wi) const;
  // Samples wi; *pdf is 0 when no direction could be sampled. *sampled_flags
  // (optional) gets the flags of what was sampled (FresnelSpecular reports
  // the reflection or the transmission it chose).
  Rgb sample_f(Vec3 wo, Vec3* wi, Vec2 u, float* pdf, uint8_t* sampled_flags = nullptr) const;
  // f and pdf at once (the values f() and pdf() give).
  Rgb f_pdf(Vec3 wo, Vec3 wi, float* pdf) const;
  // sample_f's wi, pdf and flags without its value, for a caller that evaluates f itself (a
  // BSDF sums every lobe's f at a non-specular wi).
  void sample_wi(Vec3 wo, Vec3* wi, Vec2 u, float* pdf, uint8_t* sampled_flags) const;
  float pdf(Vec3 wo, Vec3 wi) const;
  // pdf(a, b) and pdf(b, a) at once, the same values: a microfacet reflection lobe makes the
  // half vector and D, which the two share, once (bidirectional MIS asks for both).
  void pdf_both(Vec3 a, Vec3 b, float* pdf_ab, float* pdf_ba) const;
  // f(a, b) with pdf_both(a, b): what a bidirectional connection asks of each joined end.
  Rgb f_pdf_both(Vec3 a, Vec3 b, float* pdf_ab, float* pdf_ba) const;
};

// Bsdf copies lobes by value; the union must keep that a plain byte copy.
static_assert(std::is_trivially_copyable_v<Bxdf>);

Bxdf make_lambertian_reflection(Rgb r);
Bxdf make_lambertian_transmission(Rgb t);
// sigma_degrees: the standard deviation of microfacet angles.
Bxdf make_oren_nayar(Rgb r, float sigma_degrees);
Bxdf make_specular_reflection(Rgb r, const Fresnel& fresnel);
Bxdf make_specular_transmission(Rgb t, float eta_a, float eta_b, TransportMode mode);
Bxdf make_fresnel_specular(Rgb r, Rgb t, float eta_a, float eta_b, TransportMode mode);
Bxdf make_microfacet_reflection(Rgb r, const MicrofacetDistribution& d, const Fresnel& fresnel);
Bxdf make_microfacet_transmission(Rgb t, const MicrofacetDistribution& d, float eta_a, float eta_b,
                                  TransportMode mode);
Bxdf make_fresnel_blend(Rgb rd, Rgb rs, const MicrofacetDistribution& d);
// Where light leaves a subsurface material (pbrt-v3's SeparableBSSRDFAdapter): diffuse
// reflection weighted by the Fresnel transmittance into the outside, normalised by the
// Fresnel moment of 1/eta (and times eta^2 for radiance, which crossed the boundary twice).
Bxdf make_bssrdf_exit(float eta, TransportMode mode);
// Carries one of the Disney material's lobes; flags are the lobe's.
Bxdf make_disney(const DisneyLobe& lobe);
// Carries the hair material's lobe; flags are the lobe's.
Bxdf make_hair(const HairLobe& lobe);
// The fourier material's lobe; the table must outlive it.
Bxdf make_fourier(const FourierTable* table, TransportMode mode);

}  // namespace rt
