// runtime/material/bxdf.cpp — f, sampling and pdf of each lobe kind (book
// sections 8.2-8.5 and 14.1), dispatched by a switch on the kind.
#include "runtime/material/bxdf.h"

#include "format/bssrdf_table.h"
#include "runtime/core/sampling.h"
#include "runtime/material/fourier_bxdf.h"
#include "runtime/material/local_frame.h"

namespace rt {

namespace {

float pow5(float v) {
  return (v * v) * (v * v) * v;
}

Rgb oren_nayar_f(const Bxdf& b, Vec3 wo, Vec3 wi) {
  float sin_i = sin_theta(wi), sin_o = sin_theta(wo);
  float max_cos = 0;
  if (sin_i > 1e-4f && sin_o > 1e-4f) {  // phi is undefined at the pole
    float d_cos = cos_phi(wi) * cos_phi(wo) + sin_phi(wi) * sin_phi(wo);
    max_cos = std::max(0.f, d_cos);
  }
  float sin_alpha, tan_beta;
  if (abs_cos_theta(wi) > abs_cos_theta(wo)) {
    sin_alpha = sin_o;
    tan_beta = sin_i / abs_cos_theta(wi);
  } else {
    sin_alpha = sin_i;
    tan_beta = sin_o / abs_cos_theta(wo);
  }
  return b.r * kInvPi * (b.oren_a + b.oren_b * max_cos * sin_alpha * tan_beta);
}

Rgb microfacet_reflection_f(const Bxdf& b, Vec3 wo, Vec3 wi) {
  float cos_o = abs_cos_theta(wo), cos_i = abs_cos_theta(wi);
  Vec3 wh = wi + wo;
  if (cos_i == 0 || cos_o == 0) return Rgb(0);
  if (wh.x == 0 && wh.y == 0 && wh.z == 0) return Rgb(0);
  wh = normalize(wh);
  // wh faces the +z side so a dielectric Fresnel sees which side the light is
  // on (total internal reflection from inside), as pbrt-v3's final code does.
  Rgb fr = b.fresnel.evaluate(dot(wi, face_forward(wh, Vec3{0, 0, 1})));
  return b.r * fr * (b.distribution.d(wh) * b.distribution.g(wo, wi) / (4 * cos_i * cos_o));
}

// The generalised half vector of a refraction pair; false for configurations
// no microfacet can produce (wo and wi on the same side of wh).
bool transmission_half_vector(const Bxdf& b, Vec3 wo, Vec3 wi, float* eta, Vec3* wh) {
  *eta = cos_theta(wo) > 0 ? b.eta_b / b.eta_a : b.eta_a / b.eta_b;
  Vec3 h = wo + wi * *eta;
  if (h.x == 0 && h.y == 0 && h.z == 0) return false;
  h = normalize(h);
  if (h.z < 0) h = -h;
  if (dot(wo, h) * dot(wi, h) > 0) return false;
  *wh = h;
  return true;
}

Rgb microfacet_transmission_f(const Bxdf& b, Vec3 wo, Vec3 wi) {
  if (same_hemisphere(wo, wi)) return Rgb(0);
  float cos_o = cos_theta(wo), cos_i = cos_theta(wi);
  if (cos_i == 0 || cos_o == 0) return Rgb(0);
  float eta;
  Vec3 wh;
  if (!transmission_half_vector(b, wo, wi, &eta, &wh)) return Rgb(0);
  Rgb fr = Fresnel::dielectric(b.eta_a, b.eta_b).evaluate(dot(wo, wh));
  float sqrt_denom = dot(wo, wh) + eta * dot(wi, wh);
  float factor = b.mode == TransportMode::kRadiance ? 1 / eta : 1;
  float v = b.distribution.d(wh) * b.distribution.g(wo, wi) * eta * eta * abs_dot(wi, wh) *
            abs_dot(wo, wh) * factor * factor / (cos_i * cos_o * sqrt_denom * sqrt_denom);
  return (Rgb(1) - fr) * b.t * std::fabs(v);
}

float microfacet_transmission_pdf(const Bxdf& b, Vec3 wo, Vec3 wi) {
  if (same_hemisphere(wo, wi)) return 0;
  float eta;
  Vec3 wh;
  if (!transmission_half_vector(b, wo, wi, &eta, &wh)) return 0;
  float sqrt_denom = dot(wo, wh) + eta * dot(wi, wh);
  float dwh_dwi = std::fabs((eta * eta * dot(wi, wh)) / (sqrt_denom * sqrt_denom));
  return b.distribution.pdf(wo, wh) * dwh_dwi;
}

Rgb fresnel_blend_f(const Bxdf& b, Vec3 wo, Vec3 wi) {
  const Rgb& rd = b.r;
  const Rgb& rs = b.t;
  Rgb diffuse = (28.f / (23.f * kPi)) * rd * (Rgb(1) - rs) *
                ((1 - pow5(1 - .5f * abs_cos_theta(wi))) * (1 - pow5(1 - .5f * abs_cos_theta(wo))));
  Vec3 wh = wi + wo;
  if (wh.x == 0 && wh.y == 0 && wh.z == 0) return Rgb(0);
  wh = normalize(wh);
  // Schlick's approximation of the Fresnel term, with Rs as normal reflectance.
  Rgb schlick = rs + pow5(1 - dot(wi, wh)) * (Rgb(1) - rs);
  Rgb specular = schlick * (b.distribution.d(wh) /
                            (4 * abs_dot(wi, wh) * std::max(abs_cos_theta(wi), abs_cos_theta(wo))));
  return diffuse + specular;
}

float half_vector_reflection_pdf(const Bxdf& b, Vec3 wo, Vec3 wi) {
  Vec3 wh = normalize(wo + wi);
  return b.distribution.pdf(wo, wh) / (4 * dot(wo, wh));
}

Rgb raw_f(const Bxdf& b, Vec3 wo, Vec3 wi) {
  switch (b.kind) {
    case BxdfKind::kLambertianReflection:
      return b.r * kInvPi;
    case BxdfKind::kLambertianTransmission:
      return b.t * kInvPi;
    case BxdfKind::kOrenNayar:
      return oren_nayar_f(b, wo, wi);
    case BxdfKind::kMicrofacetReflection:
      return microfacet_reflection_f(b, wo, wi);
    case BxdfKind::kMicrofacetTransmission:
      return microfacet_transmission_f(b, wo, wi);
    case BxdfKind::kFresnelBlend:
      return fresnel_blend_f(b, wo, wi);
    case BxdfKind::kDisney:
      return b.disney.f(wo, wi);
    case BxdfKind::kHair:
      return b.hair.f(wo, wi);
    case BxdfKind::kFourier:
      return FourierLobe{b.fourier, b.mode}.f(wo, wi);
    case BxdfKind::kBssrdfExit:
      return b.r * (1 - fr_dielectric(cos_theta(wi), 1, b.eta_b));
    case BxdfKind::kSpecularReflection:
    case BxdfKind::kSpecularTransmission:
    case BxdfKind::kFresnelSpecular:
      break;  // deltas: zero for any given pair of directions
  }
  return Rgb(0);
}

float raw_pdf(const Bxdf& b, Vec3 wo, Vec3 wi) {
  switch (b.kind) {
    case BxdfKind::kLambertianReflection:
    case BxdfKind::kOrenNayar:
    case BxdfKind::kBssrdfExit:
      return same_hemisphere(wo, wi) ? abs_cos_theta(wi) * kInvPi : 0;
    case BxdfKind::kLambertianTransmission:
      return !same_hemisphere(wo, wi) ? abs_cos_theta(wi) * kInvPi : 0;
    case BxdfKind::kMicrofacetReflection:
      if (!same_hemisphere(wo, wi)) return 0;
      return half_vector_reflection_pdf(b, wo, wi);
    case BxdfKind::kMicrofacetTransmission:
      return microfacet_transmission_pdf(b, wo, wi);
    case BxdfKind::kFresnelBlend:
      if (!same_hemisphere(wo, wi)) return 0;
      return .5f * (abs_cos_theta(wi) * kInvPi + half_vector_reflection_pdf(b, wo, wi));
    case BxdfKind::kDisney:
      return b.disney.pdf(wo, wi);
    case BxdfKind::kHair:
      return b.hair.pdf(wo, wi);
    case BxdfKind::kFourier:
      return FourierLobe{b.fourier, b.mode}.pdf(wo, wi);
    case BxdfKind::kSpecularReflection:
    case BxdfKind::kSpecularTransmission:
    case BxdfKind::kFresnelSpecular:
      break;
  }
  return 0;
}

// A microfacet reflection lobe's f at (wo, wi), its pdf from wo to wi and, when pdf_io is
// given, from wi to wo: the half vector, D and the lambdas made once for all, each value in the
// same arithmetic as raw_f, raw_pdf and Bxdf::pdf_both make it apart (same values).
Rgb microfacet_reflection_f_pdfs(const Bxdf& b, Vec3 wo, Vec3 wi, float* pdf_oi, float* pdf_io) {
  const Vec3 sum = wi + wo;
  const bool same_side = same_hemisphere(wo, wi);
  const float cos_o = abs_cos_theta(wo), cos_i = abs_cos_theta(wi);
  const bool f_zero = cos_i == 0 || cos_o == 0 || (sum.x == 0 && sum.y == 0 && sum.z == 0);
  *pdf_oi = 0;
  if (pdf_io) *pdf_io = 0;
  if (!same_side && f_zero) return Rgb(0);
  const Vec3 wh = normalize(sum);
  const MicrofacetDistribution& d = b.distribution;
  const float dh = d.d(wh), lambda_o = d.lambda(wo);
  const float lambda_i = !f_zero || (pdf_io && same_side) ? d.lambda(wi) : 0;
  if (same_side) {
    *pdf_oi = MicrofacetDistribution::pdf_given(dh, 1 / (1 + lambda_o), wo, wh) / (4 * dot(wo, wh));
    if (pdf_io)
      *pdf_io =
          MicrofacetDistribution::pdf_given(dh, 1 / (1 + lambda_i), wi, wh) / (4 * dot(wi, wh));
  }
  if (f_zero) return Rgb(0);
  Rgb fr = b.fresnel.evaluate(dot(wi, face_forward(wh, Vec3{0, 0, 1})));
  return b.r * fr * (dh * (1 / (1 + lambda_o + lambda_i)) / (4 * cos_i * cos_o));
}

// raw_f and raw_pdf together (same values).
Rgb raw_f_pdf(const Bxdf& b, Vec3 wo, Vec3 wi, float* pdf) {
  if (b.kind != BxdfKind::kMicrofacetReflection) {
    *pdf = raw_pdf(b, wo, wi);
    return raw_f(b, wo, wi);
  }
  return microfacet_reflection_f_pdfs(b, wo, wi, pdf, nullptr);
}

// Refraction through the +z interface; which side wo is on picks the indices.
bool specular_refract(const Bxdf& b, Vec3 wo, Vec3* wi, float* eta_i, float* eta_t) {
  bool entering = cos_theta(wo) > 0;
  *eta_i = entering ? b.eta_a : b.eta_b;
  *eta_t = entering ? b.eta_b : b.eta_a;
  return refract(wo, face_forward(Vec3{0, 0, 1}, wo), *eta_i / *eta_t, wi);
}

// with_f false: the direction and its pdf only; a non-specular lobe's f comes back 0 (where
// its f is not part of sampling).
Rgb raw_sample_f(const Bxdf& b, Vec3 wo, Vec3* wi, Vec2 u, float* pdf, uint8_t* sampled,
                 bool with_f) {
  *sampled = b.flags;
  switch (b.kind) {
    case BxdfKind::kLambertianReflection:
    case BxdfKind::kOrenNayar:
    case BxdfKind::kBssrdfExit:
      *wi = cosine_sample_hemisphere(u);
      if (wo.z < 0) wi->z *= -1;
      break;
    case BxdfKind::kLambertianTransmission:
      *wi = cosine_sample_hemisphere(u);
      if (wo.z > 0) wi->z *= -1;
      break;
    case BxdfKind::kSpecularReflection:
      *wi = Vec3{-wo.x, -wo.y, wo.z};
      *pdf = 1;
      return b.fresnel.evaluate(cos_theta(*wi)) * b.r / abs_cos_theta(*wi);
    case BxdfKind::kSpecularTransmission: {
      float eta_i, eta_t;
      if (!specular_refract(b, wo, wi, &eta_i, &eta_t)) return Rgb(0);
      *pdf = 1;
      Rgb ft = b.t * (Rgb(1) - Fresnel::dielectric(b.eta_a, b.eta_b).evaluate(cos_theta(*wi)));
      // Radiance is compressed into a smaller solid angle on the denser side.
      if (b.mode == TransportMode::kRadiance) ft *= (eta_i * eta_i) / (eta_t * eta_t);
      return ft / abs_cos_theta(*wi);
    }
    case BxdfKind::kFresnelSpecular: {
      float fr = fr_dielectric(cos_theta(wo), b.eta_a, b.eta_b);
      if (u.x < fr) {
        *wi = Vec3{-wo.x, -wo.y, wo.z};
        *sampled = kSpecular | kReflection;
        *pdf = fr;
        return fr * b.r / abs_cos_theta(*wi);
      }
      float eta_i, eta_t;
      if (!specular_refract(b, wo, wi, &eta_i, &eta_t)) return Rgb(0);
      Rgb ft = b.t * (1 - fr);
      if (b.mode == TransportMode::kRadiance) ft *= (eta_i * eta_i) / (eta_t * eta_t);
      *sampled = kSpecular | kTransmission;
      *pdf = 1 - fr;
      return ft / abs_cos_theta(*wi);
    }
    case BxdfKind::kMicrofacetReflection: {
      if (wo.z == 0) return Rgb(0);
      Vec3 wh = b.distribution.sample_wh(wo, u);
      if (dot(wo, wh) < 0) return Rgb(0);  // rare, from round-off
      *wi = reflect(wo, wh);
      if (!same_hemisphere(wo, *wi)) return Rgb(0);
      *pdf = b.distribution.pdf(wo, wh) / (4 * dot(wo, wh));
      return with_f ? microfacet_reflection_f(b, wo, *wi) : Rgb(0);
    }
    case BxdfKind::kMicrofacetTransmission: {
      if (wo.z == 0) return Rgb(0);
      Vec3 wh = b.distribution.sample_wh(wo, u);
      if (dot(wo, wh) < 0) return Rgb(0);
      float eta = cos_theta(wo) > 0 ? b.eta_a / b.eta_b : b.eta_b / b.eta_a;
      if (!refract(wo, wh, eta, wi)) return Rgb(0);
      *pdf = microfacet_transmission_pdf(b, wo, *wi);
      return with_f ? microfacet_transmission_f(b, wo, *wi) : Rgb(0);
    }
    case BxdfKind::kFresnelBlend:
      // Half the samples go to the diffuse term, half to the glossy one.
      if (u.x < .5f) {
        u.x = std::min(2 * u.x, kOneMinusEpsilon);
        *wi = cosine_sample_hemisphere(u);
        if (wo.z < 0) wi->z *= -1;
      } else {
        u.x = std::min(2 * (u.x - .5f), kOneMinusEpsilon);
        Vec3 wh = b.distribution.sample_wh(wo, u);
        *wi = reflect(wo, wh);
        if (!same_hemisphere(wo, *wi)) return Rgb(0);
      }
      break;
    case BxdfKind::kDisney:
      // Each Disney lobe is one kind of scattering: what was sampled is its flags.
      return b.disney.sample_f(wo, wi, u, pdf);
    case BxdfKind::kHair:
      return b.hair.sample_f(wo, wi, u, pdf);
    case BxdfKind::kFourier:
      return FourierLobe{b.fourier, b.mode}.sample_f(wo, wi, u, pdf);
  }
  *pdf = raw_pdf(b, wo, *wi);
  return with_f ? raw_f(b, wo, *wi) : Rgb(0);
}

}  // namespace

Rgb Bxdf::f(Vec3 wo, Vec3 wi) const {
  return scale * raw_f(*this, wo, wi);
}

float Bxdf::pdf(Vec3 wo, Vec3 wi) const {
  return raw_pdf(*this, wo, wi);
}

void Bxdf::pdf_both(Vec3 a, Vec3 b, float* pdf_ab, float* pdf_ba) const {
  if (kind != BxdfKind::kMicrofacetReflection) {
    *pdf_ab = raw_pdf(*this, a, b);
    *pdf_ba = raw_pdf(*this, b, a);
    return;
  }
  if (!same_hemisphere(a, b)) {
    *pdf_ab = *pdf_ba = 0;
    return;
  }
  // half_vector_reflection_pdf's arithmetic for each order; a + b and b + a are the same bits.
  const Vec3 wh = normalize(a + b);
  const float d = distribution.d(wh);
  *pdf_ab = MicrofacetDistribution::pdf_given(d, distribution.g1(a), a, wh) / (4 * dot(a, wh));
  *pdf_ba = MicrofacetDistribution::pdf_given(d, distribution.g1(b), b, wh) / (4 * dot(b, wh));
}

Rgb Bxdf::f_pdf_both(Vec3 a, Vec3 b, float* pdf_ab, float* pdf_ba) const {
  if (kind != BxdfKind::kMicrofacetReflection) {
    pdf_both(a, b, pdf_ab, pdf_ba);
    return f(a, b);
  }
  return scale * microfacet_reflection_f_pdfs(*this, a, b, pdf_ab, pdf_ba);
}

Rgb Bxdf::f_pdf(Vec3 wo, Vec3 wi, float* pdf) const {
  return scale * raw_f_pdf(*this, wo, wi, pdf);
}

Rgb Bxdf::sample_f(Vec3 wo, Vec3* wi, Vec2 u, float* pdf, uint8_t* sampled_flags) const {
  uint8_t sampled = flags;
  *pdf = 0;
  Rgb v = raw_sample_f(*this, wo, wi, u, pdf, &sampled, true);
  if (sampled_flags) *sampled_flags = sampled;
  return scale * v;
}

void Bxdf::sample_wi(Vec3 wo, Vec3* wi, Vec2 u, float* pdf, uint8_t* sampled_flags) const {
  *sampled_flags = flags;
  *pdf = 0;
  raw_sample_f(*this, wo, wi, u, pdf, sampled_flags, false);
}

Bxdf make_lambertian_reflection(Rgb r) {
  Bxdf b;
  b.kind = BxdfKind::kLambertianReflection;
  b.flags = kReflection | kDiffuse;
  b.r = r;
  return b;
}

Bxdf make_lambertian_transmission(Rgb t) {
  Bxdf b;
  b.kind = BxdfKind::kLambertianTransmission;
  b.flags = kTransmission | kDiffuse;
  b.t = t;
  return b;
}

Bxdf make_oren_nayar(Rgb r, float sigma_degrees) {
  Bxdf b;
  b.kind = BxdfKind::kOrenNayar;
  b.flags = kReflection | kDiffuse;
  b.r = r;
  float sigma = radians(sigma_degrees), sigma2 = sigma * sigma;
  b.oren_a = 1 - sigma2 / (2 * (sigma2 + 0.33f));
  b.oren_b = 0.45f * sigma2 / (sigma2 + 0.09f);
  return b;
}

Bxdf make_specular_reflection(Rgb r, const Fresnel& fresnel) {
  Bxdf b;
  b.kind = BxdfKind::kSpecularReflection;
  b.flags = kReflection | kSpecular;
  b.r = r;
  b.fresnel = fresnel;
  return b;
}

Bxdf make_specular_transmission(Rgb t, float eta_a, float eta_b, TransportMode mode) {
  Bxdf b;
  b.kind = BxdfKind::kSpecularTransmission;
  b.flags = kTransmission | kSpecular;
  b.t = t;
  b.eta_a = eta_a;
  b.eta_b = eta_b;
  b.mode = mode;
  return b;
}

Bxdf make_fresnel_specular(Rgb r, Rgb t, float eta_a, float eta_b, TransportMode mode) {
  Bxdf b;
  b.kind = BxdfKind::kFresnelSpecular;
  b.flags = kReflection | kTransmission | kSpecular;
  b.r = r;
  b.t = t;
  b.eta_a = eta_a;
  b.eta_b = eta_b;
  b.mode = mode;
  return b;
}

Bxdf make_microfacet_reflection(Rgb r, const MicrofacetDistribution& d, const Fresnel& fresnel) {
  Bxdf b;
  b.kind = BxdfKind::kMicrofacetReflection;
  b.flags = kReflection | kGlossy;
  b.r = r;
  b.distribution = d;
  b.fresnel = fresnel;
  return b;
}

Bxdf make_microfacet_transmission(Rgb t, const MicrofacetDistribution& d, float eta_a, float eta_b,
                                  TransportMode mode) {
  Bxdf b;
  b.kind = BxdfKind::kMicrofacetTransmission;
  b.flags = kTransmission | kGlossy;
  b.t = t;
  b.distribution = d;
  b.eta_a = eta_a;
  b.eta_b = eta_b;
  b.mode = mode;
  return b;
}

Bxdf make_fresnel_blend(Rgb rd, Rgb rs, const MicrofacetDistribution& d) {
  Bxdf b;
  b.kind = BxdfKind::kFresnelBlend;
  b.flags = kReflection | kGlossy;
  b.r = rd;
  b.t = rs;
  b.distribution = d;
  return b;
}

Bxdf make_hair(const HairLobe& lobe) {
  Bxdf b;
  b.kind = BxdfKind::kHair;
  b.flags = lobe.flags;
  b.hair = lobe;
  return b;
}

Bxdf make_disney(const DisneyLobe& lobe) {
  Bxdf b;
  b.kind = BxdfKind::kDisney;
  b.flags = lobe.flags;
  b.mode = lobe.mode;
  b.disney = lobe;
  return b;
}

Bxdf make_bssrdf_exit(float eta, TransportMode mode) {
  Bxdf b;
  b.kind = BxdfKind::kBssrdfExit;
  b.flags = kReflection | kDiffuse;
  b.mode = mode;
  b.eta_b = eta;
  float c = 1 - 2 * float(pbrta::fresnel_moment1(1 / eta));
  b.r = Rgb(mode == TransportMode::kRadiance ? eta * eta / (c * kPi) : 1 / (c * kPi));
  return b;
}

Bxdf make_fourier(const FourierTable* table, TransportMode mode) {
  Bxdf b;
  b.kind = BxdfKind::kFourier;
  b.flags = kReflection | kTransmission | kGlossy;
  b.mode = mode;
  b.fourier = table;
  return b;
}

}  // namespace rt
