// Materials built from compiled scene text: the lobes each pbrt-v3 material
// creates, full-BSDF sampling against the BSDF's pdf (chi-square, in world
// space), energy conservation, mix weighting, the interface material and
// unsupported types.
#include <gtest/gtest.h>

#include "chi2_directions.h"
#include "material_test_scene.h"
#include "runtime/core/rng.h"

namespace rt {
namespace {

using material_test::flat_hit;
using material_test::MaterialScene;

const char* kScene = R"(
AttributeBegin
  Material "matte" "rgb Kd" [.6 .5 .4] "float sigma" 20
  Shape "sphere"
AttributeEnd
AttributeBegin
  Material "plastic" "rgb Kd" [.5 .5 .5] "rgb Ks" [.5 .5 .5] "float roughness" .2
  Shape "sphere"
AttributeEnd
AttributeBegin
  Material "metal" "float uroughness" .05 "float vroughness" .3
  Shape "sphere"
AttributeEnd
AttributeBegin
  Material "substrate" "rgb Kd" [.5 .4 .3] "rgb Ks" [.3 .3 .3]
  Shape "sphere"
AttributeEnd
AttributeBegin
  Material "uber" "rgb Kd" [.4 .4 .4] "rgb Ks" [.3 .3 .3] "float roughness" .3
  Shape "sphere"
AttributeEnd
AttributeBegin
  MakeNamedMaterial "dull" "string type" "matte" "rgb Kd" [.8 .8 .8]
  MakeNamedMaterial "shiny" "string type" "plastic" "float roughness" .1
  Material "mix" "string namedmaterial1" "dull" "string namedmaterial2" "shiny" "rgb amount" [.3 .3 .3]
  Shape "sphere"
AttributeEnd
AttributeBegin
  Material "translucent" "rgb Kd" [.5 .5 .5] "rgb Ks" [.3 .3 .3]
  Shape "sphere"
AttributeEnd
AttributeBegin
  Material "glass" "float uroughness" .2 "float vroughness" .2 "float index" 1.33
  Shape "sphere"
AttributeEnd
AttributeBegin
  Material "glass"
  Shape "sphere"
AttributeEnd
AttributeBegin
  Material "mirror"
  Shape "sphere"
AttributeEnd
AttributeBegin
  Material "none"
  Shape "sphere"
AttributeEnd
AttributeBegin
  Material "metal"
  Shape "sphere"
AttributeEnd
AttributeBegin
  Material "uber" "rgb opacity" [.5 .5 .5] "rgb Kr" [.2 .2 .2]
  Shape "sphere"
AttributeEnd
)";
enum Shape : uint32_t {
  kMatte,
  kPlastic,
  kMetal,
  kSubstrate,
  kUber,
  kMix,
  kTranslucent,
  kRoughGlass,
  kGlass,
  kMirror,
  kInterface,
  kCopper,
  kUberOpacity
};

class MaterialsTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(scene.load("materials", kScene)) << scene.error; }
  Bsdf bsdf_of(Shape s, bool multiple_lobes = true, TransportMode mode = TransportMode::kRadiance) {
    SurfaceInteraction si = flat_hit();
    Bsdf b;
    EXPECT_TRUE(
        scene.materials.compute_bsdf(scene.material_of_shape(s), &si, mode, multiple_lobes, &b));
    return b;
  }
  MaterialScene scene;
};

std::vector<BxdfKind> kinds(const Bsdf& b) {
  std::vector<BxdfKind> k;
  for (int i = 0; i < b.num_lobes(); ++i) k.push_back(b.lobe(i).kind);
  return k;
}

TEST_F(MaterialsTest, LobesAreThoseOfPbrtV3) {
  using K = BxdfKind;
  EXPECT_EQ(kinds(bsdf_of(kMatte)), std::vector<K>{K::kOrenNayar});
  EXPECT_EQ(kinds(bsdf_of(kPlastic)),
            (std::vector<K>{K::kLambertianReflection, K::kMicrofacetReflection}));
  EXPECT_EQ(kinds(bsdf_of(kMetal)), std::vector<K>{K::kMicrofacetReflection});
  EXPECT_EQ(kinds(bsdf_of(kSubstrate)), std::vector<K>{K::kFresnelBlend});
  EXPECT_EQ(kinds(bsdf_of(kUber)),
            (std::vector<K>{K::kLambertianReflection, K::kMicrofacetReflection}));
  EXPECT_EQ(kinds(bsdf_of(kTranslucent)),
            (std::vector<K>{K::kLambertianReflection, K::kLambertianTransmission,
                            K::kMicrofacetReflection, K::kMicrofacetTransmission}));
  EXPECT_EQ(kinds(bsdf_of(kRoughGlass)),
            (std::vector<K>{K::kMicrofacetReflection, K::kMicrofacetTransmission}));
  EXPECT_EQ(kinds(bsdf_of(kGlass, true)), std::vector<K>{K::kFresnelSpecular});
  EXPECT_EQ(kinds(bsdf_of(kGlass, false)),
            (std::vector<K>{K::kSpecularReflection, K::kSpecularTransmission}));
  EXPECT_EQ(kinds(bsdf_of(kMirror)), std::vector<K>{K::kSpecularReflection});
  EXPECT_EQ(kinds(bsdf_of(kUberOpacity)),
            (std::vector<K>{K::kSpecularTransmission, K::kLambertianReflection,
                            K::kMicrofacetReflection, K::kSpecularReflection}));
  // Relative index: glass's eta ("index" is its alias), uber with partial
  // opacity passes light undeviated (eta 1), translucent is fixed at 1.5.
  EXPECT_FLOAT_EQ(bsdf_of(kRoughGlass).eta, 1.33f);
  EXPECT_FLOAT_EQ(bsdf_of(kGlass).eta, 1.5f);
  EXPECT_FLOAT_EQ(bsdf_of(kUberOpacity).eta, 1.f);
  EXPECT_FLOAT_EQ(bsdf_of(kUber).eta, 1.5f);
  EXPECT_FLOAT_EQ(bsdf_of(kTranslucent).eta, 1.5f);
  // Roughness remapped: metal's u and v roughness through pbrt-v3's polynomial.
  const Bxdf metal = bsdf_of(kMetal).lobe(0);
  EXPECT_FLOAT_EQ(metal.distribution.alpha_x, roughness_to_alpha(.05f));
  EXPECT_FLOAT_EQ(metal.distribution.alpha_y, roughness_to_alpha(.3f));
  // Metal without eta/k: pbrt-v3's measured copper.
  const Bxdf copper = bsdf_of(kCopper).lobe(0);
  EXPECT_NEAR(copper.fresnel.cond_eta_t.r, 0.2f, 1e-3f);
  EXPECT_NEAR(copper.fresnel.cond_k.r, 3.9046f, 1e-3f);
  EXPECT_FLOAT_EQ(copper.distribution.alpha_x, roughness_to_alpha(.01f));
}

TEST_F(MaterialsTest, FullBsdfSamplingMatchesPdf) {
  const Shape shapes[] = {kMatte, kPlastic, kMetal, kSubstrate, kUber, kMix};
  const Vec3 n = flat_hit().n;
  const Vec3 outgoing[] = {n, normalize(n + Vec3{0.8f, 0.3f, 0}), normalize(n + Vec3{-2, 1, 0.5f})};
  uint64_t seed = 100;
  for (Shape s : shapes)
    for (Vec3 wo : outgoing) {
      Bsdf b = bsdf_of(s);
      ASSERT_GT(dot(wo, n), 0);
      auto sample = [&](Vec2 u, Vec3* wi) {
        float pdf;
        b.sample_f(wo, wi, u, &pdf);
        return pdf > 0;
      };
      auto pdf = [&](Vec3 wi) { return double(b.pdf(wo, wi)); };
      auto r = material_test::chi2_directions(sample, pdf, 100000, seed++);
      EXPECT_GT(r.p_value, 1e-3 / 18) << "shape " << s << ": " << r.message;
      EXPECT_LT(r.total_mass_error, 5e-3 + 4 * r.total_mass_sigma)
          << "shape " << s << ": " << r.message;
    }
}

// sample_f in world space returns the BSDF's f and pdf of the chosen direction
// (all matching lobes summed/averaged), for every material with smooth lobes.
TEST_F(MaterialsTest, SampleAgreesWithEvaluation) {
  const Shape shapes[] = {kMatte, kPlastic, kMetal,       kSubstrate,
                          kUber,  kMix,     kTranslucent, kRoughGlass};
  Rng rng(4);
  const Vec3 n = flat_hit().n;
  for (Shape s : shapes) {
    Bsdf b = bsdf_of(s);
    for (Vec3 wo : {normalize(n + Vec3{0.5f, 0.2f, 0}), normalize(-n + Vec3{0.1f, 0.4f, 0})})
      for (int i = 0; i < 3000; ++i) {
        Vec3 wi;
        float pdf;
        Rgb f = b.sample_f(wo, &wi, {rng.next_float(), rng.next_float()}, &pdf);
        if (pdf == 0) continue;
        float pe = b.pdf(wo, wi);
        Rgb fe = b.f(wo, wi);
        ASSERT_NEAR(pdf, pe, 2e-3f * std::max(1.f, pe)) << "shape " << s;
        ASSERT_NEAR(f.g, fe.g, 2e-3f * std::max(1.f, fe.g)) << "shape " << s;
      }
  }
}

TEST_F(MaterialsTest, PhysicalMaterialsDoNotCreateEnergy) {
  // Kd + Ks <= 1 everywhere; importance transport so refraction adds no eta^2.
  const Shape shapes[] = {kMatte, kPlastic,     kMetal,      kSubstrate, kUber,
                          kMix,   kTranslucent, kRoughGlass, kGlass};
  Rng rng(8);
  const Vec3 n = flat_hit().n;
  for (Shape s : shapes) {
    Bsdf b = bsdf_of(s, true, TransportMode::kImportance);
    for (int d = 0; d < 12; ++d) {
      float c = (d + 0.5f) / 12;
      Vec3 t, bt;
      coordinate_system(n, &t, &bt);
      Vec3 wo = normalize(n * c + t * std::sqrt(1 - c * c));
      double sum = 0;
      const int count = 20000;
      for (int i = 0; i < count; ++i) {
        Vec3 wi;
        float pdf;
        Rgb f = b.sample_f(wo, &wi, {rng.next_float(), rng.next_float()}, &pdf);
        if (pdf > 0) sum += f.max_component() * abs_dot(wi, n) / pdf;
      }
      EXPECT_LE(sum / count, 1.02) << "shape " << s << " cos " << c;
    }
  }
}

TEST_F(MaterialsTest, MixOfTwoMattesIsTheWeightedAverage) {
  MaterialScene mix;
  ASSERT_TRUE(mix.load("mix_mattes", R"(
MakeNamedMaterial "a" "string type" "matte" "rgb Kd" [.8 .6 .4]
MakeNamedMaterial "b" "string type" "matte" "rgb Kd" [.2 .3 .1]
Material "mix" "string namedmaterial1" "a" "string namedmaterial2" "b" "rgb amount" [.25 .5 .75]
Shape "sphere"
)")) << mix.error;
  SurfaceInteraction si = flat_hit();
  Bsdf b;
  ASSERT_TRUE(mix.materials.compute_bsdf(mix.material_of_shape(0), &si, TransportMode::kRadiance,
                                         true, &b));
  Vec3 wo = normalize(si.n + Vec3{0.3f, 0, 0}), wi = normalize(si.n + Vec3{0, -0.4f, 0.1f});
  Rgb f = b.f(wo, wi);
  // pbrt-v3's MixMaterial: namedmaterial1 weighted by amount, namedmaterial2 by 1 - amount.
  EXPECT_NEAR(f.r, (.25f * .8f + .75f * .2f) * kInvPi, 1e-6f);
  EXPECT_NEAR(f.g, (.5f * .6f + .5f * .3f) * kInvPi, 1e-6f);
  EXPECT_NEAR(f.b, (.75f * .4f + .25f * .1f) * kInvPi, 1e-6f);
  EXPECT_EQ(b.num_lobes(), 2);
}

TEST_F(MaterialsTest, InterfaceMaterialHasNoBsdf) {
  uint32_t m = scene.material_of_shape(kInterface);
  EXPECT_TRUE(scene.materials.is_interface(m));
  EXPECT_FALSE(scene.materials.is_interface(scene.material_of_shape(kMatte)));
  SurfaceInteraction si = flat_hit();
  Bsdf b;
  EXPECT_FALSE(scene.materials.compute_bsdf(m, &si, TransportMode::kRadiance, true, &b));
}

// The hair material: one hair lobe whose offset h is -1 + 2 v, its absorption from sigma_a,
// color or melanin in pbrt-v3's order of precedence, brown hair (eumelanin 1.3) by default.
TEST(Materials, HairTakesAbsorptionInPbrtsOrder) {
  MaterialScene s;
  ASSERT_TRUE(s.load("hair_materials", R"(
Material "hair" "rgb sigma_a" [0.5 1 2] "rgb color" [0.1 0.1 0.1] "float eumelanin" 8
Shape "sphere"
Material "hair" "rgb color" [0.3 0.2 0.1] "float eumelanin" 8 "float beta_n" 0.5
Shape "sphere"
Material "hair" "float pheomelanin" 2
Shape "sphere"
Material "hair" "float alpha" 0 "float eta" 1.4 "float beta_m" 0.2
Shape "sphere"
)")) << s.error;
  const Rgb expected[] = {
      Rgb(0.5f, 1, 2), hair_sigma_a_from_reflectance(Rgb(0.3f, 0.2f, 0.1f), 0.5f),
      hair_sigma_a_from_concentration(0, 2), hair_sigma_a_from_concentration(1.3f, 0)};
  for (uint32_t shape = 0; shape < 4; ++shape) {
    SCOPED_TRACE(shape);
    SurfaceInteraction si = flat_hit();
    si.uv = {0.3f, 0.8f};
    Bsdf b;
    ASSERT_TRUE(s.materials.compute_bsdf(s.material_of_shape(shape), &si, TransportMode::kRadiance,
                                         true, &b));
    ASSERT_EQ(b.num_lobes(), 1);
    const Bxdf& lobe = b.lobe(0);
    ASSERT_EQ(lobe.kind, BxdfKind::kHair);
    EXPECT_NEAR(lobe.hair.h, 0.6f, 1e-6f);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(lobe.hair.sigma_a[k], expected[shape][k], 1e-5f);
  }
  SurfaceInteraction si = flat_hit();
  Bsdf b;
  ASSERT_TRUE(
      s.materials.compute_bsdf(s.material_of_shape(3), &si, TransportMode::kRadiance, true, &b));
  EXPECT_NEAR(b.lobe(0).hair.eta, 1.4f, 1e-6f);
  EXPECT_EQ(b.lobe(0).hair.sin_alpha, 0.f);
  EXPECT_NEAR(b.eta, 1.4f, 1e-6f);
}

TEST(Materials, MixWithTheInterfaceMaterialFails) {
  MaterialScene s;
  EXPECT_FALSE(s.load("mix_none", R"(
MakeNamedMaterial "a" "string type" "matte"
MakeNamedMaterial "b" "string type" "none"
Material "mix" "string namedmaterial1" "a" "string namedmaterial2" "b"
Shape "sphere"
)"));
  EXPECT_NE(s.error.find("not supported yet: mix material with the interface material"),
            std::string::npos)
      << s.error;
}

}  // namespace
}  // namespace rt
