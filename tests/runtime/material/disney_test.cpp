// The Disney material's lobes: values at hand-computed configurations,
// sampling against pdf (chi-square), sample_f against f/pdf, importance vs
// uniform albedo, energy bounds, and which lobes the parameters make.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "chi2_directions.h"
#include "lobe_checks.h"
#include "material_test_scene.h"
#include "runtime/core/sampling.h"
#include "runtime/material/bxdf.h"
#include "runtime/material/disney_bxdf.h"
#include "runtime/material/disney_material.h"
#include "runtime/material/fresnel.h"

namespace rt {
namespace {

using material_test::chi2_directions;
using material_test::expect_albedo_estimates_agree;
using material_test::expect_sample_matches_evaluation;

struct Case {
  std::string name;
  DisneyLobe lobe;
};

// Every lobe kind the material makes, from the material's own construction.
std::vector<Case> cases() {
  std::vector<Case> out;
  auto take = [&](const std::string& name, const DisneyParams& p) {
    DisneyLobe lobes[kMaxDisneyLobes];
    int n = make_disney_lobes(p, TransportMode::kRadiance, lobes);
    EXPECT_GT(n, 0) << name;
    for (int i = 0; i < n; ++i)
      out.push_back({name + "/" + std::to_string(int(lobes[i].kind)), lobes[i]});
  };
  DisneyParams thin;
  thin.thin = true;
  thin.color = Rgb(0.8f, 0.5f, 0.3f);
  // Rough enough for the chi-square grid to resolve the transmission lobes.
  thin.roughness = 0.8f;
  thin.flatness = 0.5f;
  thin.sheen = 1;
  thin.clearcoat = 1;
  thin.clearcoat_gloss = 0.5f;
  thin.spec_trans = 0.5f;
  thin.anisotropic = 0.6f;
  take("thin", thin);  // diffuse, fake ss, retro, sheen, specular, clearcoat, transmission, diffuse
                       // transmission
  DisneyParams solid;
  solid.roughness = 0.6f;
  solid.spec_trans = 0.7f;
  solid.eta = 1.33f;
  take("solid", solid);  // diffuse, retro, specular (isotropic), transmission (separable G)
  return out;
}

const Vec3 kOutgoing[] = {
    normalize(Vec3{0.3f, -0.2f, 0.93f}), normalize(Vec3{0.8f, 0.1f, 0.4f}),
    normalize(Vec3{-0.5f, 0.6f, 0.2f}), normalize(Vec3{0.2f, 0.4f, -0.7f}),  // from below
};

// As pbrt-v3's MicrofacetTransmission, the transmission lobe's pdf gives
// density to half vectors wo sees from behind, which sampling never makes
// (bxdf_sampling_test.cpp keeps the same for the same reason); the
// chi-square test compares on the configurations sampling can produce.
bool sampled_domain(const DisneyLobe& b, Vec3 wo, Vec3 wi) {
  if (b.kind != DisneyLobeKind::kTransmission) return true;
  float eta = wo.z > 0 ? b.eta : 1 / b.eta;
  Vec3 wh = normalize(wo + wi * eta);
  if (wh.z < 0) wh = -wh;
  return dot(wo, wh) * wo.z > 0;
}

TEST(Disney, LobesTheParametersMake) {
  DisneyLobe lobes[kMaxDisneyLobes];
  DisneyParams p;
  // The default solid dielectric: diffuse, retro-reflection, specular.
  ASSERT_EQ(make_disney_lobes(p, TransportMode::kRadiance, lobes), 3);
  EXPECT_EQ(lobes[0].kind, DisneyLobeKind::kDiffuse);
  EXPECT_EQ(lobes[1].kind, DisneyLobeKind::kRetro);
  EXPECT_EQ(lobes[2].kind, DisneyLobeKind::kSpecular);
  // roughness 0.5: alpha 0.25; R0 of eta 1.5 is 0.04.
  EXPECT_FLOAT_EQ(lobes[2].distribution.alpha_x, 0.25f);
  EXPECT_NEAR(lobes[2].r.g, 0.04f, 1e-6f);
  // A metal has only the specular lobe, its R0 the colour.
  p.metallic = 1;
  p.color = Rgb(0.9f, 0.6f, 0.2f);
  ASSERT_EQ(make_disney_lobes(p, TransportMode::kRadiance, lobes), 1);
  EXPECT_EQ(lobes[0].r, p.color);
  // The thin surface with everything on fills all eight.
  DisneyParams t;
  t.thin = true;
  t.sheen = t.clearcoat = t.spec_trans = 0.5f;
  ASSERT_EQ(make_disney_lobes(t, TransportMode::kRadiance, lobes), 8);
  // difftrans 1 (default) halves the thin diffuse between reflection and transmission.
  EXPECT_EQ(lobes[7].kind, DisneyLobeKind::kDiffuseTransmission);
  EXPECT_NEAR(lobes[7].r.g, 0.5f * 0.5f, 1e-6f);
  EXPECT_NEAR(lobes[0].r.g + lobes[1].r.g, 0.5f * 0.5f * 0.5f, 1e-6f);
  // A solid surface with a scatter distance trades its diffuse lobe for a BSSRDF.
  DisneyParams s;
  s.scatter_distance = Rgb(0.1f);
  bool subsurface = false;
  int n = make_disney_lobes(s, TransportMode::kRadiance, lobes, &subsurface);
  EXPECT_TRUE(subsurface);
  for (int i = 0; i < n; ++i) EXPECT_NE(lobes[i].kind, DisneyLobeKind::kDiffuse);
  s.scatter_distance = Rgb(0.f);
  n = make_disney_lobes(s, TransportMode::kRadiance, lobes, &subsurface);
  EXPECT_FALSE(subsurface);
  EXPECT_EQ(lobes[0].kind, DisneyLobeKind::kDiffuse);
}

TEST(Disney, ValuesByHand) {
  DisneyLobe b;
  b.r = Rgb(1);
  b.roughness = 0.5f;
  Vec3 n{0, 0, 1};
  Vec3 w60 = normalize(Vec3{std::sqrt(3.f), 0, 1});  // cos theta = 0.5
  float fw = 1 / 32.f;                               // schlick_weight(0.5)
  EXPECT_FLOAT_EQ(schlick_weight(0.5f), fw);
  // Diffuse: Lambert at normal incidence, darkened by (1 - F/2) per side.
  b.kind = DisneyLobeKind::kDiffuse;
  EXPECT_NEAR(b.f(n, n).g, kInvPi, 1e-6f);
  EXPECT_NEAR(b.f(w60, w60).g, kInvPi * (1 - fw / 2) * (1 - fw / 2), 1e-6f);
  // Retro-reflection: none at normal incidence; back toward a 60-degree
  // viewer R_R = 2 roughness, times (F_o + F_i + F_o F_i (R_R - 1)) / pi.
  b.kind = DisneyLobeKind::kRetro;
  EXPECT_NEAR(b.f(n, n).g, 0, 1e-7f);
  EXPECT_NEAR(b.f(w60, w60).g, kInvPi * 1.0f * (2 * fw + fw * fw * (1.0f - 1)), 1e-6f);
  // Sheen: Schlick weight of the angle to the half vector.
  b.kind = DisneyLobeKind::kSheen;
  Vec3 a = normalize(Vec3{1, 0, 1}), c = normalize(Vec3{-1, 0, 1});
  EXPECT_NEAR(b.f(a, c).g, std::pow(1 - std::sqrt(0.5f), 5.f), 1e-6f);
  EXPECT_NEAR(b.f(a, a).g, 0, 1e-7f);
  // Fake subsurface at normal incidence: Fss = 1, ss = 1.25 (1/2 - 1/2 + 1/2).
  b.kind = DisneyLobeKind::kFakeSubsurface;
  EXPECT_NEAR(b.f(n, n).g, kInvPi * 1.25f * 0.5f, 1e-6f);
  // Disney Fresnel: the dielectric's for metallic 0, Schlick's from R0 for metallic 1.
  EXPECT_NEAR(disney_fresnel(Rgb(0.3f), 0, 1.5f, 0.5f).g, fr_dielectric(0.5f, 1, 1.5f), 1e-6f);
  EXPECT_NEAR(disney_fresnel(Rgb(0.3f), 1, 1.5f, 0.5f).g, 0.3f + 0.7f * fw, 1e-6f);
  // GTR1 is a normalised distribution of normals: integral of D cos = 1.
  for (float alpha : {0.05f, 0.1f, 0.3f}) {
    double sum = 0;
    const int steps = 200000;
    for (int i = 0; i < steps; ++i) {
      double ct = (i + 0.5) / steps;  // d(omega) = 2 pi d(cos)
      sum += disney_gtr1(float(ct), alpha) * ct * 2 * kPi / steps;
    }
    EXPECT_NEAR(sum, 1, 2e-3) << alpha;
  }
}

TEST(Disney, ChiSquareMatchesPdf) {
  auto cs = cases();
  const double kLevel = 1e-3 / (cs.size() * std::size(kOutgoing));
  uint64_t seed = 1;
  for (const Case& c : cs)
    for (Vec3 wo : kOutgoing) {
      const DisneyLobe& b = c.lobe;
      auto sample = [&](Vec2 u, Vec3* wi) {
        float pdf;
        Rgb f = b.sample_f(wo, wi, u, &pdf);
        return pdf > 0 && !f.is_black();
      };
      auto pdf = [&](Vec3 wi) { return sampled_domain(b, wo, wi) ? double(b.pdf(wo, wi)) : 0.0; };
      // Transmission: see bxdf_sampling_test.cpp on the rational visible-slope fit.
      int n = b.kind == DisneyLobeKind::kTransmission ? 25000 : 60000;
      auto r = chi2_directions(sample, pdf, n, seed++);
      EXPECT_GT(r.p_value, kLevel) << c.name << " wo.z=" << wo.z << ": " << r.message;
      EXPECT_LT(r.total_mass_error, 5e-3 + 4 * r.total_mass_sigma)
          << c.name << " wo.z=" << wo.z << ": " << r.message;
    }
}

TEST(Disney, SampleAgreesWithEvaluation) {
  Rng rng(7);
  for (const Case& c : cases())
    for (Vec3 wo : kOutgoing) expect_sample_matches_evaluation(c.lobe, wo, 1000, rng, c.name);
}

// Importance-sampled and uniformly sampled albedo agree, and no lobe of a
// white material reflects more than it receives (retro-reflection aside:
// Burley's diffuse is allowed above 1 at grazing angles; checked on the sum).
TEST(Disney, AlbedoAgreesAndConservesEnergy) {
  for (const Case& c : cases())
    for (Vec3 wo : kOutgoing) {
      double is = expect_albedo_estimates_agree(c.lobe, wo, 60000, 11, c.name);
      EXPECT_LT(is, 1.0) << c.name << " wo.z=" << wo.z;
    }
}

// The material's parameters from real scene text: defaults, constants,
// textures, and the subsurface case it cannot render.
TEST(Disney, ReadsTheMaterialFromTheArchive) {
  pbrta::SceneArchive a;
  ASSERT_TRUE(testing_support::compile_text(testing_support::scratch_dir("disney_read"), R"(
Camera "perspective"
WorldBegin
Texture "rough" "float" "constant" "float value" 0.3
Material "disney" "rgb color" [0.8 0.2 0.1] "float metallic" 0.25 "texture roughness" "rough"
  "float sheen" 0.5 "bool thin" "true" "float flatness" 0.4
Shape "sphere"
Material "disney"
Shape "sphere"
Material "disney" "rgb scatterdistance" [0.1 0.1 0.1]
Shape "sphere"
WorldEnd
)",
                                            &a));
  TextureSet textures;
  std::string error;
  ASSERT_TRUE(textures.build(a, &error)) << error;
  SurfaceInteraction si = material_test::flat_hit();
  DisneyInputs in;
  read_disney_inputs(a, a.materials[a.shapes[0].material].entity, &in);
  DisneyParams p = evaluate_disney(in, textures, si);
  EXPECT_EQ(p.color, Rgb(0.8f, 0.2f, 0.1f));
  EXPECT_FLOAT_EQ(p.metallic, 0.25f);
  EXPECT_FLOAT_EQ(p.roughness, 0.3f);  // through the texture
  EXPECT_FLOAT_EQ(p.sheen, 0.5f);
  EXPECT_FLOAT_EQ(p.flatness, 0.4f);
  EXPECT_TRUE(p.thin);
  EXPECT_FLOAT_EQ(p.eta, 1.5f);  // defaults
  EXPECT_FLOAT_EQ(p.diff_trans, 1);
  EXPECT_FLOAT_EQ(p.clearcoat_gloss, 1);
  read_disney_inputs(a, a.materials[a.shapes[1].material].entity, &in);
  p = evaluate_disney(in, textures, si);
  EXPECT_EQ(p.color, Rgb(0.5f));
  EXPECT_FLOAT_EQ(p.roughness, 0.5f);
  EXPECT_FLOAT_EQ(p.sheen_tint, 0.5f);
  EXPECT_FALSE(p.thin);
  read_disney_inputs(a, a.materials[a.shapes[2].material].entity, &in);
  EXPECT_EQ(evaluate_disney(in, textures, si).scatter_distance, Rgb(0.1f));
}

}  // namespace
}  // namespace rt
