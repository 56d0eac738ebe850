// runtime/material/hair_bxdf.h — pbrt-v3's hair BSDF (HairBSDF): Chiang,
// Bitterli, Tappan and Burley 2016, "A Practical and Controllable Hair and
// Fur Model for Production Path Tracing", on d'Eon et al.'s longitudinal
// function (2011) and importance sampling (2013).
//
// One plain struct, like DisneyLobe (disney_bxdf.h), in the local shading
// frame of a curve hit: x = normalized dp/du (along the fiber), z = the
// shading normal, y = z × x. A direction's longitudinal angle is measured
// from the plane normal to the fiber, sin theta = w.x; its azimuth about the
// fiber is phi = atan2(w.z, w.y). Scattering is the sum of lobes p = 0 (R),
// 1 (TT), 2 (TRT) and the rest folded into one: each is a longitudinal
// M_p (theta_i, theta_o), an attenuation A_p (Fresnel at the entry point, the
// fiber's absorption along each internal chord) and an azimuthal N_p (a
// logistic trimmed to [-pi, pi] around the lobe's exit angle), the last lobe
// azimuthally uniform. The cuticle scales tilt R's cone by -2 alpha, TT's
// by +alpha and TRT's by +4 alpha: theta_o is rotated before M_p, as pbrt-v3
// does since its Dec 2019 fix (pull request 256; the book's printed code
// rotated theta_i after sampling, which the pdf did not match).
//
// f() is divided by |cos theta_i| = |wi.z| (the shading normal's cosine, as
// pbrt-v3's AbsCosTheta) so the integrator's cosine cancels: the model's
// cosine is the fiber's, already inside M_p. The model is not reciprocal in
// general (A_p and the exit angles depend on wo alone); it is for h = 0,
// alpha = 0 and |sin theta_i| = |sin theta_o|, which the tests check.
// sample_f splits each of its two numbers into two by alternate bits (pbrt-
// v3's DemuxFloat) to choose the lobe (by the luminance of A_p), the azimuth,
// and the two angles of the longitudinal cone. The flags are pbrt-v3's
// glossy reflection and transmission: Bsdf's reflect/transmit test against
// the geometric normal never masks the lobe out.
//
// Bxdf's union carries a HairLobe beside DisneyLobe, so it is kept as small:
// make_hair_lobe stores the R lobe's variance v0 (TT's is v0 / 4, TRT's and
// the remainder's 4 v0, both exact in float) and sin/cos alpha; the doubled
// angles 2 alpha and 4 alpha are rebuilt per call from them by the same
// double-angle recurrence pbrt-v3 precomputes with.
#pragma once

#include <cstdint>
#include <type_traits>

#include "runtime/core/rgb.h"
#include "runtime/core/vec.h"
#include "runtime/material/bxdf_flags.h"

namespace rt {

struct HairLobe {
  uint8_t flags = kReflection | kTransmission | kGlossy;
  float h = 0;                         // where the ray crossed the fiber's width, in [-1, 1]
  float gamma_o = 0;                   // asin(h): the incidence angle in the normal plane
  float eta = 1.55f;                   // the fiber's index of refraction
  Rgb sigma_a;                         // absorption per unit of the fiber's radius
  float v0 = 0;                        // R's longitudinal variance (from beta_m)
  float s = 1;                         // the azimuthal logistic's scale (from beta_n)
  float sin_alpha = 0, cos_alpha = 1;  // the cuticle scales' tilt

  bool matches(uint8_t mask) const { return (flags & mask) == flags; }
  Rgb f(Vec3 wo, Vec3 wi) const;
  // As Bxdf::sample_f: *pdf is 0 when no direction was sampled (only for a
  // fiber that neither reflects nor transmits: eta 1 and opaque).
  // *sampled_flags gets the lobe's flags, as pbrt-v3's BSDF reports them.
  Rgb sample_f(Vec3 wo, Vec3* wi, Vec2 u, float* pdf, uint8_t* sampled_flags = nullptr) const;
  float pdf(Vec3 wo, Vec3 wi) const;
};

// Bsdf copies lobes by value through Bxdf's union.
static_assert(std::is_trivially_copyable_v<HairLobe>);

// pbrt-v3's HairBSDF constructor: h in [-1, 1] (clamped), beta_m and beta_n
// in (0, 1] (0 makes a zero variance or logistic scale: undefined, as in
// pbrt-v3), alpha in degrees (HairMaterial's "alpha", converted once).
HairLobe make_hair_lobe(float h, float eta, Rgb sigma_a, float beta_m, float beta_n,
                        float alpha_degrees);

// Absorption of a fiber with the given eumelanin and pheomelanin
// concentrations (pbrt-v3's HairBSDF::SigmaAFromConcentration).
Rgb hair_sigma_a_from_concentration(float eumelanin, float pheomelanin);

// The paper's fitted inverse: the absorption that makes a fiber of azimuthal
// roughness beta_n look colour c after multiple scattering. c in (0, 1]
// (pbrt-v3's material clamps below at 0; 0 gives an infinite absorption).
Rgb hair_sigma_a_from_reflectance(Rgb c, float beta_n);

}  // namespace rt
