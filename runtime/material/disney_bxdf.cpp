// runtime/material/disney_bxdf.cpp — see disney_bxdf.h.
#include "runtime/material/disney_bxdf.h"

#include <algorithm>
#include <cmath>

#include "runtime/core/sampling.h"
#include "runtime/material/fresnel.h"
#include "runtime/material/local_frame.h"

namespace rt {

namespace {

Rgb lerp_rgb(float t, Rgb a, Rgb b) {
  return a * (1 - t) + b * t;
}

bool is_zero(Vec3 v) {
  return v.x == 0 && v.y == 0 && v.z == 0;
}

// Burley's clearcoat masking: a GGX Smith term at a fixed roughness, in the
// form that already divides by the cosine (hence the / 4 without cosines).
float smith_g_ggx(float cos_theta, float alpha) {
  float a2 = alpha * alpha, c2 = cos_theta * cos_theta;
  return 1 / (cos_theta + std::sqrt(a2 + c2 - a2 * c2));
}

float masking(const DisneyLobe& b, Vec3 wo, Vec3 wi) {
  if (b.separable_g) return b.distribution.g1(wo) * b.distribution.g1(wi);
  return b.distribution.g(wo, wi);
}

// The half vector of a refraction pair (facing +z); false when none exists.
bool refraction_half_vector(const DisneyLobe& b, Vec3 wo, Vec3 wi, float* eta, Vec3* wh) {
  *eta = cos_theta(wo) > 0 ? b.eta : 1 / b.eta;
  Vec3 h = wo + wi * *eta;
  if (is_zero(h)) return false;
  h = normalize(h);
  if (h.z < 0) h = -h;
  if (dot(wo, h) * dot(wi, h) > 0) return false;
  *wh = h;
  return true;
}

Rgb transmission_f(const DisneyLobe& b, Vec3 wo, Vec3 wi) {
  if (same_hemisphere(wo, wi)) return Rgb(0);
  float cos_o = cos_theta(wo), cos_i = cos_theta(wi);
  if (cos_i == 0 || cos_o == 0) return Rgb(0);
  float eta;
  Vec3 wh;
  if (!refraction_half_vector(b, wo, wi, &eta, &wh)) return Rgb(0);
  float fr = fr_dielectric(dot(wo, wh), 1, b.eta);
  float denom = dot(wo, wh) + eta * dot(wi, wh);
  // Radiance is compressed by 1/eta^2 entering the denser side.
  float factor = b.mode == TransportMode::kRadiance ? 1 / eta : 1;
  float v = b.distribution.d(wh) * masking(b, wo, wi) * eta * eta * abs_dot(wi, wh) *
            abs_dot(wo, wh) * factor * factor / (cos_i * cos_o * denom * denom);
  return b.r * ((1 - fr) * std::fabs(v));
}

float transmission_pdf(const DisneyLobe& b, Vec3 wo, Vec3 wi) {
  if (same_hemisphere(wo, wi)) return 0;
  float eta;
  Vec3 wh;
  if (!refraction_half_vector(b, wo, wi, &eta, &wh)) return 0;
  float denom = dot(wo, wh) + eta * dot(wi, wh);
  return b.distribution.pdf(wo, wh) * std::fabs(eta * eta * dot(wi, wh) / (denom * denom));
}

Rgb specular_f(const DisneyLobe& b, Vec3 wo, Vec3 wi) {
  float cos_o = abs_cos_theta(wo), cos_i = abs_cos_theta(wi);
  if (cos_i == 0 || cos_o == 0) return Rgb(0);
  Vec3 wh = wi + wo;
  if (is_zero(wh)) return Rgb(0);
  wh = normalize(wh);
  Rgb fr = disney_fresnel(b.r, b.metallic, b.eta, dot(wi, face_forward(wh, Vec3{0, 0, 1})));
  return fr * (b.distribution.d(wh) * masking(b, wo, wi) / (4 * cos_i * cos_o));
}

Rgb clearcoat_f(const DisneyLobe& b, Vec3 wo, Vec3 wi) {
  Vec3 wh = wi + wo;
  if (is_zero(wh)) return Rgb(0);
  wh = normalize(wh);
  float dr = disney_gtr1(abs_cos_theta(wh), b.clearcoat_alpha);
  float fr = 0.04f + (1 - 0.04f) * schlick_weight(dot(wo, wh));
  float gr = smith_g_ggx(abs_cos_theta(wo), .25f) * smith_g_ggx(abs_cos_theta(wi), .25f);
  return b.r * (gr * fr * dr / 4);
}

float clearcoat_pdf(const DisneyLobe& b, Vec3 wo, Vec3 wi) {
  if (!same_hemisphere(wo, wi)) return 0;
  Vec3 wh = wi + wo;
  if (is_zero(wh)) return 0;
  wh = normalize(wh);
  // GTR1 is sampled as a distribution of normals (D cos), not of visible ones.
  float dr = disney_gtr1(abs_cos_theta(wh), b.clearcoat_alpha);
  return dr * abs_cos_theta(wh) / (4 * dot(wo, wh));
}

}  // namespace

float schlick_weight(float cos_theta) {
  float m = clamp(1 - cos_theta, 0.f, 1.f);
  return (m * m) * (m * m) * m;
}

float disney_gtr1(float cos_theta_h, float alpha) {
  float a2 = alpha * alpha;
  return (a2 - 1) / (kPi * std::log(a2) * (1 + (a2 - 1) * cos_theta_h * cos_theta_h));
}

Rgb disney_fresnel(Rgb r0, float metallic, float eta, float cos_theta_i) {
  Rgb dielectric(fr_dielectric(cos_theta_i, 1, eta));
  Rgb schlick = lerp_rgb(schlick_weight(cos_theta_i), r0, Rgb(1));
  return lerp_rgb(metallic, dielectric, schlick);
}

Rgb DisneyLobe::f(Vec3 wo, Vec3 wi) const {
  switch (kind) {
    case DisneyLobeKind::kDiffuse: {
      float fo = schlick_weight(abs_cos_theta(wo)), fi = schlick_weight(abs_cos_theta(wi));
      // Lambert with the grazing darkening of a Fresnel-like factor on each side.
      return r * (kInvPi * (1 - fo / 2) * (1 - fi / 2));
    }
    case DisneyLobeKind::kFakeSubsurface: {
      Vec3 wh = wi + wo;
      if (is_zero(wh)) return Rgb(0);
      wh = normalize(wh);
      float cos_d = dot(wi, wh);
      float fss90 = cos_d * cos_d * roughness;
      float fo = schlick_weight(abs_cos_theta(wo)), fi = schlick_weight(abs_cos_theta(wi));
      float fss = lerp(fo, 1.f, fss90) * lerp(fi, 1.f, fss90);
      // Hanrahan-Krueger-like flattening; 1.25 keeps the albedo near Lambert's.
      float ss = 1.25f * (fss * (1 / (abs_cos_theta(wo) + abs_cos_theta(wi)) - .5f) + .5f);
      return r * (kInvPi * ss);
    }
    case DisneyLobeKind::kRetro: {
      Vec3 wh = wi + wo;
      if (is_zero(wh)) return Rgb(0);
      wh = normalize(wh);
      float cos_d = dot(wi, wh);
      float fo = schlick_weight(abs_cos_theta(wo)), fi = schlick_weight(abs_cos_theta(wi));
      float rr = 2 * roughness * cos_d * cos_d;
      return r * (kInvPi * rr * (fo + fi + fo * fi * (rr - 1)));
    }
    case DisneyLobeKind::kSheen: {
      Vec3 wh = wi + wo;
      if (is_zero(wh)) return Rgb(0);
      wh = normalize(wh);
      return r * schlick_weight(dot(wi, wh));
    }
    case DisneyLobeKind::kClearcoat:
      return clearcoat_f(*this, wo, wi);
    case DisneyLobeKind::kSpecular:
      return specular_f(*this, wo, wi);
    case DisneyLobeKind::kTransmission:
      return transmission_f(*this, wo, wi);
    case DisneyLobeKind::kDiffuseTransmission:
      return r * kInvPi;
  }
  return Rgb(0);
}

float DisneyLobe::pdf(Vec3 wo, Vec3 wi) const {
  switch (kind) {
    case DisneyLobeKind::kDiffuse:
    case DisneyLobeKind::kFakeSubsurface:
    case DisneyLobeKind::kRetro:
    case DisneyLobeKind::kSheen:
      return same_hemisphere(wo, wi) ? abs_cos_theta(wi) * kInvPi : 0;
    case DisneyLobeKind::kDiffuseTransmission:
      return same_hemisphere(wo, wi) ? 0 : abs_cos_theta(wi) * kInvPi;
    case DisneyLobeKind::kClearcoat:
      return clearcoat_pdf(*this, wo, wi);
    case DisneyLobeKind::kSpecular: {
      if (!same_hemisphere(wo, wi)) return 0;
      Vec3 wh = normalize(wo + wi);
      return distribution.pdf(wo, wh) / (4 * dot(wo, wh));
    }
    case DisneyLobeKind::kTransmission:
      return transmission_pdf(*this, wo, wi);
  }
  return 0;
}

Rgb DisneyLobe::sample_f(Vec3 wo, Vec3* wi, Vec2 u, float* pdf_out) const {
  *pdf_out = 0;
  switch (kind) {
    case DisneyLobeKind::kDiffuse:
    case DisneyLobeKind::kFakeSubsurface:
    case DisneyLobeKind::kRetro:
    case DisneyLobeKind::kSheen:
      *wi = cosine_sample_hemisphere(u);
      if (wo.z < 0) wi->z *= -1;
      break;
    case DisneyLobeKind::kDiffuseTransmission:
      *wi = cosine_sample_hemisphere(u);
      if (wo.z > 0) wi->z *= -1;
      break;
    case DisneyLobeKind::kClearcoat: {
      if (wo.z == 0) return Rgb(0);
      // Inverse CDF of GTR1's D cos over cos theta_h.
      float a2 = clearcoat_alpha * clearcoat_alpha;
      float cos_t = std::sqrt(std::max(0.f, (1 - std::pow(a2, 1 - u.x)) / (1 - a2)));
      float sin_t = std::sqrt(std::max(0.f, 1 - cos_t * cos_t));
      float phi = 2 * kPi * u.y;
      Vec3 wh{sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t};
      if (!same_hemisphere(wo, wh)) wh = -wh;
      *wi = reflect(wo, wh);
      if (!same_hemisphere(wo, *wi)) return Rgb(0);
      break;
    }
    case DisneyLobeKind::kSpecular: {
      if (wo.z == 0) return Rgb(0);
      Vec3 wh = distribution.sample_wh(wo, u);
      if (dot(wo, wh) < 0) return Rgb(0);
      *wi = reflect(wo, wh);
      if (!same_hemisphere(wo, *wi)) return Rgb(0);
      break;
    }
    case DisneyLobeKind::kTransmission: {
      if (wo.z == 0) return Rgb(0);
      Vec3 wh = distribution.sample_wh(wo, u);
      if (dot(wo, wh) < 0) return Rgb(0);
      float e = cos_theta(wo) > 0 ? 1 / eta : eta;
      if (!refract(wo, wh, e, wi)) return Rgb(0);
      break;
    }
  }
  *pdf_out = pdf(wo, *wi);
  return f(wo, *wi);
}

int make_disney_lobes(const DisneyParams& p, TransportMode mode, DisneyLobe out[kMaxDisneyLobes],
                      bool* subsurface) {
  int n = 0;
  if (subsurface) *subsurface = false;
  auto add = [&](DisneyLobeKind kind, uint8_t flags, Rgb r) -> DisneyLobe& {
    DisneyLobe& b = out[n++];
    b = DisneyLobe();
    b.kind = kind;
    b.flags = flags;
    b.r = r;
    b.mode = mode;
    return b;
  };
  const uint8_t kDiffuseReflection = kReflection | kDiffuse;
  Rgb c(std::max(0.f, p.color.r), std::max(0.f, p.color.g), std::max(0.f, p.color.b));
  float diffuse_weight = (1 - p.metallic) * (1 - p.spec_trans);
  float dt = p.diff_trans / 2;  // difftrans 1 splits thin diffuse evenly
  float lum = c.luminance();
  Rgb tint = lum > 0 ? c / lum : Rgb(1);  // hue and saturation only
  Rgb sheen_color = lerp_rgb(p.sheen_tint, Rgb(1), tint);

  if (diffuse_weight > 0) {
    if (p.thin) {
      add(DisneyLobeKind::kDiffuse, kDiffuseReflection,
          c * (diffuse_weight * (1 - p.flatness) * (1 - dt)));
      add(DisneyLobeKind::kFakeSubsurface, kDiffuseReflection,
          c * (diffuse_weight * p.flatness * (1 - dt)))
          .roughness = p.roughness;
    } else {
      if (!p.scatter_distance.is_black()) {
        if (subsurface) *subsurface = true;
      } else {
        add(DisneyLobeKind::kDiffuse, kDiffuseReflection, c * diffuse_weight);
      }
    }
    add(DisneyLobeKind::kRetro, kDiffuseReflection, c * diffuse_weight).roughness = p.roughness;
    if (p.sheen > 0)
      add(DisneyLobeKind::kSheen, kDiffuseReflection, sheen_color * (diffuse_weight * p.sheen));
  }

  float aspect = std::sqrt(1 - p.anisotropic * .9f);
  MicrofacetDistribution d;
  d.kind = MicrofacetKind::kTrowbridgeReitz;
  d.alpha_x = std::max(.001f, sqr(p.roughness) / aspect);
  d.alpha_y = std::max(.001f, sqr(p.roughness) * aspect);

  float r0 = sqr(p.eta - 1) / sqr(p.eta + 1);
  Rgb spec0 = lerp_rgb(p.metallic, r0 * lerp_rgb(p.specular_tint, Rgb(1), tint), c);
  DisneyLobe& spec = add(DisneyLobeKind::kSpecular, kReflection | kGlossy, spec0);
  spec.distribution = d;
  spec.separable_g = true;
  spec.metallic = p.metallic;
  spec.eta = p.eta;

  if (p.clearcoat > 0)
    add(DisneyLobeKind::kClearcoat, kReflection | kGlossy, Rgb(p.clearcoat)).clearcoat_alpha =
        lerp(p.clearcoat_gloss, .1f, .001f);

  if (p.spec_trans > 0) {
    // sqrt(color): two refractions through a solid give back the colour.
    DisneyLobe& t =
        add(DisneyLobeKind::kTransmission, kTransmission | kGlossy, p.spec_trans * sqrt(c));
    t.eta = p.eta;
    if (p.thin) {
      // Burley 2015, figure 15: a thin sheet looks rougher with a higher index.
      float rs = (0.65f * p.eta - 0.35f) * p.roughness;
      t.distribution = d;
      t.distribution.alpha_x = std::max(.001f, sqr(rs) / aspect);
      t.distribution.alpha_y = std::max(.001f, sqr(rs) * aspect);
    } else {
      t.distribution = d;
      t.separable_g = true;
    }
  }
  if (p.thin) add(DisneyLobeKind::kDiffuseTransmission, kTransmission | kDiffuse, c * dt);
  return n;
}

}  // namespace rt
