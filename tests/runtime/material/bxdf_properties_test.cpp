// Closed-form and physical properties of the lobes: Fresnel values against
// hand and independent complex-arithmetic results, reciprocity, the eta^2
// radiance scaling of refraction, energy conservation, and Lambertian pdf
// proportional to f cos.
#include <gtest/gtest.h>

#include <complex>

#include "lobe_checks.h"
#include "runtime/core/rng.h"
#include "runtime/core/sampling.h"
#include "runtime/material/bxdf.h"
#include "runtime/material/local_frame.h"

namespace rt {
namespace {

MicrofacetDistribution tr(float ax, float ay) {
  return material_test::microfacet(MicrofacetKind::kTrowbridgeReitz, ax, ay);
}

TEST(Fresnel, DielectricNormalIncidenceAndTotalInternalReflection) {
  for (float n : {1.33f, 1.5f, 2.4f})
    EXPECT_NEAR(fr_dielectric(1, 1, n), sqr((n - 1) / (n + 1)), 1e-6f) << n;
  // From inside (cos < 0), past the critical angle asin(1/1.5) = 41.8 degrees.
  EXPECT_EQ(fr_dielectric(std::cos(radians(60)), 1.5f, 1), 1.f);
  EXPECT_EQ(fr_dielectric(-std::cos(radians(60)), 1, 1.5f), 1.f);
  EXPECT_LT(fr_dielectric(-std::cos(radians(30)), 1, 1.5f), 0.2f);
  // Grazing incidence reflects everything.
  EXPECT_NEAR(fr_dielectric(1e-4f, 1, 1.5f), 1.f, 1e-3f);
}

// |r|^2 of s and p waves with complex arithmetic, written independently.
float complex_fresnel(float cos_if, float eta, float k) {
  double cos_i = cos_if;
  std::complex<double> n(eta, k);
  double sin2 = 1 - cos_i * cos_i;
  std::complex<double> ct = std::sqrt(n * n - sin2);
  std::complex<double> rs = (cos_i - ct) / (cos_i + ct);
  std::complex<double> rp = (n * n * cos_i - ct) / (n * n * cos_i + ct);
  return float((std::norm(rs) + std::norm(rp)) / 2);
}

TEST(Fresnel, ConductorMatchesHandAndComplexValues) {
  // Copper-like red channel: ((n-1)^2 + k^2) / ((n+1)^2 + k^2) at normal incidence.
  Rgb r = fr_conductor(1, Rgb(1), Rgb(0.2f, 0.92f, 1.1f), Rgb(3.9f, 2.45f, 2.14f));
  EXPECT_NEAR(r.r, (0.64f + 15.21f) / (1.44f + 15.21f), 1e-5f);
  EXPECT_NEAR(r.r, 0.951952f, 1e-5f);
  for (float deg : {0.f, 30.f, 60.f, 80.f, 89.f}) {
    float c = std::cos(radians(deg));
    Rgb v = fr_conductor(c, Rgb(1), Rgb(0.2f, 0.92f, 1.1f), Rgb(3.9f, 2.45f, 2.14f));
    EXPECT_NEAR(v.r, complex_fresnel(c, 0.2f, 3.9f), 2e-4f) << deg;
    EXPECT_NEAR(v.g, complex_fresnel(c, 0.92f, 2.45f), 2e-4f) << deg;
    EXPECT_NEAR(v.b, complex_fresnel(c, 1.1f, 2.14f), 2e-4f) << deg;
  }
  // A conductor reflects alike from both sides.
  Fresnel f = Fresnel::conductor(Rgb(1), Rgb(0.2f), Rgb(3.9f));
  EXPECT_EQ(f.evaluate(0.3f), f.evaluate(-0.3f));
}

TEST(BxdfProperties, ReflectionLobesAreReciprocal) {
  const Bxdf lobes[] = {
      make_lambertian_reflection(Rgb(0.7f)),
      make_oren_nayar(Rgb(0.7f), 25),
      make_microfacet_reflection(Rgb(1), tr(0.2f, 0.45f), Fresnel::dielectric(1.5f, 1)),
      make_microfacet_reflection(Rgb(1), tr(0.3f, 0.3f),
                                 Fresnel::conductor(Rgb(1), Rgb(0.2f), Rgb(3.9f))),
      make_fresnel_blend(Rgb(0.5f), Rgb(0.2f), tr(0.3f, 0.1f)),
  };
  Rng rng(3);
  for (const Bxdf& b : lobes)
    for (int i = 0; i < 2000; ++i) {
      Vec3 wo = cosine_sample_hemisphere({rng.next_float(), rng.next_float()});
      Vec3 wi = uniform_sample_hemisphere({rng.next_float(), rng.next_float()});
      if (wo.z < 1e-3f || wi.z < 1e-3f) continue;
      Rgb a = b.f(wo, wi), c = b.f(wi, wo);
      ASSERT_NEAR(a.g, c.g, 1e-4f * std::max(1.f, a.g)) << int(b.kind);
    }
}

TEST(BxdfProperties, SpecularTransmissionScalesRadianceByEtaSquared) {
  const float eta = 1.5f, t = 1;
  Bxdf radiance = make_specular_transmission(Rgb(t), 1, eta, TransportMode::kRadiance);
  Bxdf importance = make_specular_transmission(Rgb(t), 1, eta, TransportMode::kImportance);
  for (float deg : {0.f, 30.f, 60.f}) {
    Vec3 wo{std::sin(radians(deg)), 0, std::cos(radians(deg))};
    Vec3 wi, wi2;
    float pdf, pdf2;
    Rgb fr = radiance.sample_f(wo, &wi, {0.5f, 0.5f}, &pdf);
    Rgb fi = importance.sample_f(wo, &wi2, {0.5f, 0.5f}, &pdf2);
    ASSERT_EQ(pdf, 1.f);
    EXPECT_LT(wi.z, 0);
    // Snell: sin_t = sin_i / eta.
    EXPECT_NEAR(sin_theta(wi), std::sin(radians(deg)) / eta, 1e-5f);
    float transmitted = 1 - fr_dielectric(std::cos(radians(deg)), 1, eta);
    EXPECT_NEAR(fi.r * abs_cos_theta(wi2), transmitted, 1e-5f);
    EXPECT_NEAR(fr.r * abs_cos_theta(wi), transmitted / (eta * eta), 1e-5f);
    // Leaving the denser side, radiance grows by eta^2.
    Vec3 back = wi, out;
    Rgb fb = radiance.sample_f(back, &out, {0.5f, 0.5f}, &pdf);
    EXPECT_NEAR(out.x, wo.x, 1e-5f);
    EXPECT_NEAR(fb.r * abs_cos_theta(out), transmitted * eta * eta, 1e-4f);
  }
  // Beyond the critical angle nothing is transmitted.
  Vec3 inside{std::sin(radians(60)), 0, -std::cos(radians(60))}, wi;
  float pdf = 7;
  EXPECT_TRUE(radiance.sample_f(inside, &wi, {0.5f, 0.5f}, &pdf).is_black());
  EXPECT_EQ(pdf, 0.f);
}

TEST(BxdfProperties, FresnelSpecularSplitsByFresnel) {
  Bxdf b = make_fresnel_specular(Rgb(1), Rgb(1), 1, 1.5f, TransportMode::kImportance);
  Vec3 wo = normalize(Vec3{0.5f, 0, 0.8f}), wi;
  float F = fr_dielectric(wo.z, 1, 1.5f), pdf;
  uint8_t flags;
  Rgb f = b.sample_f(wo, &wi, {F * 0.5f, 0.3f}, &pdf, &flags);
  EXPECT_EQ(flags, kSpecular | kReflection);
  EXPECT_NEAR(pdf, F, 1e-6f);
  EXPECT_NEAR(f.r * abs_cos_theta(wi) / pdf, 1, 1e-5f);
  f = b.sample_f(wo, &wi, {(1 + F) * 0.5f, 0.3f}, &pdf, &flags);
  EXPECT_EQ(flags, kSpecular | kTransmission);
  EXPECT_NEAR(pdf, 1 - F, 1e-6f);
  EXPECT_NEAR(f.r * abs_cos_theta(wi) / pdf, 1, 1e-5f);  // importance: no eta^2
  EXPECT_LT(wi.z, 0);
}

// Albedo by importance sampling, over many outgoing directions.
float max_albedo(const Bxdf& b, int n_dirs, int n) {
  Rng rng(5);
  float worst = 0;
  for (int d = 0; d < n_dirs; ++d) {
    float cos_o = (d + 0.5f) / n_dirs;
    Vec3 wo{std::sqrt(1 - cos_o * cos_o), 0, cos_o};
    double sum = 0;
    for (int i = 0; i < n; ++i) {
      Vec3 wi;
      float pdf;
      Rgb f = b.sample_f(wo, &wi, {rng.next_float(), rng.next_float()}, &pdf);
      if (pdf > 0) sum += f.max_component() * abs_cos_theta(wi) / pdf;
    }
    worst = std::max(worst, float(sum / n));
  }
  return worst;
}

TEST(BxdfProperties, PhysicalLobesDoNotCreateEnergy) {
  EXPECT_NEAR(max_albedo(make_lambertian_reflection(Rgb(1)), 8, 5000), 1, 1e-4f);
  EXPECT_LE(max_albedo(make_oren_nayar(Rgb(1), 40), 16, 20000), 1.01f);
  EXPECT_LE(
      max_albedo(make_microfacet_reflection(Rgb(1), tr(0.5f, 0.5f), Fresnel::no_op()), 16, 20000),
      1.01f);
  EXPECT_LE(max_albedo(make_microfacet_transmission(Rgb(1), tr(0.3f, 0.3f), 1, 1.5f,
                                                    TransportMode::kImportance),
                       16, 20000),
            1.01f);
  // Substrate with Kd + Ks <= 1.
  EXPECT_LE(max_albedo(make_fresnel_blend(Rgb(0.6f), Rgb(0.4f), tr(0.2f, 0.2f)), 16, 20000), 1.01f);
  // Lossless smooth glass reflects + transmits exactly everything (importance mode).
  EXPECT_NEAR(max_albedo(make_fresnel_specular(Rgb(1), Rgb(1), 1, 1.5f, TransportMode::kImportance),
                         16, 20000),
              1, 1e-4f);
}

TEST(BxdfProperties, LambertianPdfIsFCosNormalised) {
  Bxdf b = make_lambertian_reflection(Rgb(0.3f));
  Rng rng(9);
  for (int i = 0; i < 100; ++i) {
    Vec3 wo = cosine_sample_hemisphere({rng.next_float(), rng.next_float()});
    Vec3 wi = cosine_sample_hemisphere({rng.next_float(), rng.next_float()});
    EXPECT_NEAR(b.pdf(wo, wi), b.f(wo, wi).g * wi.z / 0.3f, 1e-5f);
    EXPECT_EQ(b.pdf(wo, Vec3{wi.x, wi.y, -wi.z}), 0.f);
  }
}

TEST(Microfacet, RoughnessRemapAndNormalisation) {
  // pbrt-v3's polynomial at roughness 0.5 (x = ln 0.5).
  float x = std::log(0.5f);
  EXPECT_NEAR(roughness_to_alpha(0.5f),
              1.62142f + 0.819955f * x + 0.1734f * x * x + 0.0171201f * x * x * x +
                  0.000640711f * x * x * x * x,
              1e-6f);
  EXPECT_EQ(roughness_to_alpha(0), roughness_to_alpha(1e-3f));
  // Projected microfacet area is the macro surface: integral of D cos = 1.
  for (MicrofacetKind kind : {MicrofacetKind::kTrowbridgeReitz, MicrofacetKind::kBeckmann}) {
    MicrofacetDistribution d = tr(0.3f, 0.6f);
    d.kind = kind;
    const int n = 800;
    double sum = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        double theta = (i + 0.5) / n * (kPi / 2), phi = (j + 0.5) / n * 2 * kPi;
        Vec3 wh{float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                float(std::cos(theta))};
        sum += d.d(wh) * wh.z * std::sin(theta);
      }
    EXPECT_NEAR(sum * (kPi / 2 / n) * (2 * kPi / n), 1, 2e-3) << int(kind);
  }
}

// D and lambda are computed from the direction's components: they must agree with the book's
// formulas in theta and phi (taken here in double) for both distributions, anisotropic, over
// the whole sphere, and give 0 at z = 0 as pbrt-v3 does.
TEST(Microfacet, DAndLambdaAgreeWithTheAngleForms) {
  auto book_d = [](const MicrofacetDistribution& m, double theta, double phi) {
    double ax = m.alpha_x, ay = m.alpha_y, c = std::cos(theta), t = std::tan(theta);
    double e =
        (std::cos(phi) * std::cos(phi) / (ax * ax) + std::sin(phi) * std::sin(phi) / (ay * ay)) *
        t * t;
    if (m.kind == MicrofacetKind::kBeckmann) return std::exp(-e) / (kPi * ax * ay * c * c * c * c);
    return 1 / (kPi * ax * ay * c * c * c * c * (1 + e) * (1 + e));
  };
  auto book_lambda = [](const MicrofacetDistribution& m, double theta, double phi) {
    double ax = m.alpha_x, ay = m.alpha_y, t = std::fabs(std::tan(theta));
    double alpha = std::sqrt(std::cos(phi) * std::cos(phi) * ax * ax +
                             std::sin(phi) * std::sin(phi) * ay * ay);
    if (m.kind == MicrofacetKind::kBeckmann) {
      double a = 1 / (alpha * t);
      if (a >= 1.6) return 0.0;
      return (1 - 1.259 * a + 0.396 * a * a) / (3.535 * a + 2.181 * a * a);
    }
    return (-1 + std::sqrt(1 + alpha * alpha * t * t)) / 2;
  };
  Rng rng(11);
  for (MicrofacetKind kind : {MicrofacetKind::kTrowbridgeReitz, MicrofacetKind::kBeckmann})
    for (Vec2 a : {Vec2{0.3f, 0.6f}, Vec2{0.05f, 0.05f}, Vec2{1.2f, 0.2f}}) {
      MicrofacetDistribution m = tr(a.x, a.y);
      m.kind = kind;
      int bad = 0;
      for (int i = 0; i < 20000; ++i) {
        // theta away from the normal and the horizon by 1e-3, where the float inputs still
        // pin the angles down to a relative 1e-4 of these functions.
        double theta = 1e-3 + (kPi - 2e-3) * rng.next_float(), phi = 2 * kPi * rng.next_float();
        if (std::fabs(theta - kPi / 2) < 1e-3) continue;
        Vec3 w{float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
               float(std::cos(theta))};
        double d0 = book_d(m, theta, phi), l0 = book_lambda(m, theta, phi);
        bad += std::fabs(m.d(w) - d0) > 1e-4 * d0 + 1e-30;
        bad += std::fabs(m.lambda(w) - l0) > 1e-4 * l0 + 1e-6;
      }
      EXPECT_EQ(bad, 0) << int(kind) << " " << a.x << " " << a.y;
      EXPECT_EQ(m.d({1, 0, 0}), 0);
      EXPECT_EQ(m.lambda({0, 1, 0}), 0);
    }
}

}  // namespace
}  // namespace rt
