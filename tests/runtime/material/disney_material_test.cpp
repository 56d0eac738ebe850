// The "disney" material through MaterialSet, from compiled scene text: the
// lobes pbrt-v3's DisneyMaterial builds for metallic, glassy, thin and
// clearcoated parameters, whole-BSDF sampling against the BSDF's pdf
// (chi-square, world space), sample_f against f/pdf, albedo bounds, mixes,
// bump mapping, and the subsurface cases it refuses.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "chi2_directions.h"
#include "material_test_scene.h"
#include "runtime/core/rng.h"
#include "runtime/material/disney_bxdf.h"
#include "runtime/material/fresnel.h"

namespace rt {
namespace {

using material_test::flat_hit;
using material_test::MaterialScene;

const char* kScene = R"(
Texture "ramp" "float" "bilerp" "float v00" 0 "float v01" 0 "float v10" 1 "float v11" 1
AttributeBegin
  Material "disney" "rgb color" [0.9 0.6 0.2] "float metallic" 1 "float roughness" 0.5
    "float anisotropic" 0.5
  Shape "sphere"
AttributeEnd
AttributeBegin
  Material "disney" "rgb color" [0.9 0.9 0.8] "float spectrans" 1 "float roughness" 0.6
    "float eta" 1.4
  Shape "sphere"
AttributeEnd
AttributeBegin
  Material "disney" "rgb color" [0.7 0.5 0.3] "bool thin" "true" "float difftrans" 0.6
    "float flatness" 0.3 "float roughness" 0.3
  Shape "sphere"
AttributeEnd
AttributeBegin
  Material "disney" "rgb color" [0.3 0.5 0.7] "float clearcoat" 1 "float clearcoatgloss" 0.5
    "float sheen" 0.5 "float roughness" 0.4
  Shape "sphere"
AttributeEnd
AttributeBegin
  MakeNamedMaterial "gold" "string type" "disney" "rgb color" [0.9 0.6 0.2] "float metallic" 1
    "float roughness" 0.5 "float anisotropic" 0.5
  MakeNamedMaterial "chalk" "string type" "matte" "rgb Kd" [0.4 0.5 0.6]
  Material "mix" "string namedmaterial1" "gold" "string namedmaterial2" "chalk"
    "rgb amount" [0.3 0.6 0.8]
  Shape "sphere"
AttributeEnd
AttributeBegin
  Material "matte" "rgb Kd" [0.4 0.5 0.6]
  Shape "sphere"
AttributeEnd
AttributeBegin
  Material "disney" "texture bumpmap" "ramp"
  Shape "sphere"
AttributeEnd
AttributeBegin
  Material "disney"
  Shape "sphere"
AttributeEnd
)";
enum Shape : uint32_t { kMetallic, kGlassy, kThin, kClearcoat, kMix, kChalk, kBumped, kDefault };

class DisneyMaterialTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(scene.load("disney_material", kScene)) << scene.error; }
  Bsdf bsdf_of(Shape s, TransportMode mode = TransportMode::kRadiance,
               SurfaceInteraction si = flat_hit()) {
    Bsdf b;
    EXPECT_TRUE(scene.materials.compute_bsdf(scene.material_of_shape(s), &si, mode, true, &b));
    return b;
  }
  MaterialScene scene;
};

std::vector<DisneyLobeKind> disney_kinds(const Bsdf& b) {
  std::vector<DisneyLobeKind> k;
  for (int i = 0; i < b.num_lobes(); ++i) {
    EXPECT_EQ(b.lobe(i).kind, BxdfKind::kDisney);
    k.push_back(b.lobe(i).disney.kind);
  }
  return k;
}

std::vector<int> flags_of(const Bsdf& b) {
  std::vector<int> f;
  for (int i = 0; i < b.num_lobes(); ++i) f.push_back(b.lobe(i).flags);
  return f;
}

constexpr int kDiffuseR = kReflection | kDiffuse, kGlossyR = kReflection | kGlossy;
constexpr int kGlossyT = kTransmission | kGlossy, kDiffuseT = kTransmission | kDiffuse;

// pbrt-v3's DisneyMaterial::ComputeScatteringFunctions for each setup.
TEST_F(DisneyMaterialTest, LobesAndFlagsAreThoseOfPbrtV3) {
  using K = DisneyLobeKind;
  // Metallic 1: no diffuse part, only the specular lobe, R0 the colour (its
  // reflectance on top of the Fresnel term is 1: pbrt-v3 renders a black
  // dielectric disney sphere in a white furnace at 0.0151, not 0).
  Bsdf metal = bsdf_of(kMetallic);
  EXPECT_EQ(disney_kinds(metal), std::vector<K>{K::kSpecular});
  EXPECT_EQ(flags_of(metal), std::vector<int>{kGlossyR});
  EXPECT_EQ(metal.lobe(0).disney.r, Rgb(0.9f, 0.6f, 0.2f));
  // anisotropic 0.5: aspect sqrt(1 - 0.45), alpha = roughness^2 / aspect, * aspect.
  float aspect = std::sqrt(1 - 0.45f);
  EXPECT_FLOAT_EQ(metal.lobe(0).disney.distribution.alpha_x, 0.25f / aspect);
  EXPECT_FLOAT_EQ(metal.lobe(0).disney.distribution.alpha_y, 0.25f * aspect);
  EXPECT_FLOAT_EQ(metal.eta, 1);

  // spectrans 1: no diffuse; specular and the rough transmission, its
  // weight sqrt(colour). pbrt-v3 leaves the BSDF's eta at 1.
  Bsdf glass = bsdf_of(kGlassy);
  EXPECT_EQ(disney_kinds(glass), (std::vector<K>{K::kSpecular, K::kTransmission}));
  EXPECT_EQ(flags_of(glass), (std::vector<int>{kGlossyR, kGlossyT}));
  EXPECT_NEAR(glass.lobe(1).disney.r.b, std::sqrt(0.8f), 1e-6f);
  EXPECT_FLOAT_EQ(glass.lobe(1).disney.eta, 1.4f);
  EXPECT_TRUE(glass.lobe(1).disney.separable_g);
  EXPECT_FLOAT_EQ(glass.eta, 1);

  // Thin: diffuse and fake subsurface split by flatness, each scaled by
  // 1 - difftrans / 2; retro-reflection; specular; diffuse transmission
  // weighted difftrans / 2.
  Bsdf thin = bsdf_of(kThin);
  EXPECT_EQ(disney_kinds(thin), (std::vector<K>{K::kDiffuse, K::kFakeSubsurface, K::kRetro,
                                                K::kSpecular, K::kDiffuseTransmission}));
  EXPECT_EQ(flags_of(thin),
            (std::vector<int>{kDiffuseR, kDiffuseR, kDiffuseR, kGlossyR, kDiffuseT}));
  EXPECT_NEAR(thin.lobe(0).disney.r.r, 0.7f * 0.7f * 0.7f, 1e-6f);
  EXPECT_NEAR(thin.lobe(1).disney.r.r, 0.7f * 0.3f * 0.7f, 1e-6f);
  EXPECT_NEAR(thin.lobe(4).disney.r.r, 0.7f * 0.3f, 1e-6f);
  EXPECT_EQ(thin.num_components(kTransmission | kDiffuse), 1);

  // Clearcoat and sheen on a dielectric: diffuse, retro, sheen, specular, clearcoat.
  Bsdf coat = bsdf_of(kClearcoat);
  EXPECT_EQ(disney_kinds(coat),
            (std::vector<K>{K::kDiffuse, K::kRetro, K::kSheen, K::kSpecular, K::kClearcoat}));
  EXPECT_EQ(flags_of(coat),
            (std::vector<int>{kDiffuseR, kDiffuseR, kDiffuseR, kGlossyR, kGlossyR}));
  EXPECT_FLOAT_EQ(coat.lobe(4).disney.clearcoat_alpha, lerp(0.5f, 0.1f, 0.001f));
  EXPECT_EQ(coat.lobe(4).disney.r, Rgb(1));

  // The defaults: diffuse, retro, specular.
  EXPECT_EQ(disney_kinds(bsdf_of(kDefault)),
            (std::vector<K>{K::kDiffuse, K::kRetro, K::kSpecular}));
}

// The specular lobe's value is pbrt-v3's MicrofacetReflection(1, ...) with
// the Disney Fresnel, whose R0 carries the colour of a metal: check one
// direction pair by hand. (An older pbrt-v3 multiplied the lobe by the colour
// too; the pbrt-v3 of ../shared/peers renders a black dielectric disney
// sphere in a white furnace at 0.0151, its specular reflection alone.)
TEST_F(DisneyMaterialTest, MetalSpecularIsColouredByItsFresnel) {
  Bsdf b = bsdf_of(kMetallic);
  const DisneyLobe& l = b.lobe(0).disney;
  Vec3 wo = normalize(Vec3{0.3f, 0.1f, 0.9f}), wi = normalize(Vec3{-0.2f, -0.3f, 0.8f});
  Vec3 wh = normalize(wo + wi);
  Rgb fr = disney_fresnel(l.r, 1, 1.5f, dot(wi, wh));
  float g = l.distribution.g1(wo) * l.distribution.g1(wi);
  Rgb expected = fr * (l.distribution.d(wh) * g / (4 * wo.z * wi.z));
  Rgb f = b.lobe(0).f(wo, wi);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(f[k], expected[k], 1e-5f * expected[k]) << k;
}

// pbrt-v3's MicrofacetReflection hands its Fresnel the cosine against the
// half vector turned to +z, so from the back of a thin surface the Disney
// specular lobe sees the inside of a dielectric (indices swapped, total
// internal reflection) and the Schlick blend's weight of 1: much brighter
// than from the front. Kept, since pbrt-v3 renders it so.
TEST_F(DisneyMaterialTest, BackSideSpecularSeesTheInsideFresnel) {
  Bsdf b = bsdf_of(kThin);
  const Bxdf& spec = b.lobe(3);
  ASSERT_EQ(spec.disney.kind, DisneyLobeKind::kSpecular);
  const DisneyLobe& l = spec.disney;
  auto expected = [&](Vec3 wo, Vec3 wi) {
    Vec3 wh = normalize(wo + wi);
    float cos_i = dot(wi, wh.z < 0 ? -wh : wh);
    float g = l.distribution.g1(wo) * l.distribution.g1(wi);
    return Rgb(fr_dielectric(cos_i, 1, 1.5f)) *
           (l.distribution.d(wh) * g / (4 * std::fabs(wo.z * wi.z)));
  };
  Vec3 wo = normalize(Vec3{0.6f, 0, 0.5f}), wi = normalize(Vec3{-0.55f, 0.1f, 0.5f});
  Vec3 wo_b{wo.x, wo.y, -wo.z}, wi_b{wi.x, wi.y, -wi.z};
  Rgb front = spec.f(wo, wi), back = spec.f(wo_b, wi_b);
  EXPECT_NEAR(front.r, expected(wo, wi).r, 1e-5f * front.r);
  EXPECT_NEAR(back.r, expected(wo_b, wi_b).r, 1e-5f * back.r);
  EXPECT_GT(back.r, 5 * front.r);  // beyond the critical angle inside: F = 1
}

// As in disney_test.cpp: pbrt-v3's microfacet transmission pdf gives
// density to half vectors wo sees from behind, which its sampling never
// makes; the chi-square test compares the BSDF on what sampling can produce.
double sampled_pdf(const Bsdf& b, Vec3 wo_world, Vec3 wi_world) {
  Vec3 wo = b.world_to_local(wo_world), wi = b.world_to_local(wi_world);
  double sum = 0;
  for (int i = 0; i < b.num_lobes(); ++i) {
    const Bxdf& l = b.lobe(i);
    if (l.kind == BxdfKind::kDisney && l.disney.kind == DisneyLobeKind::kTransmission &&
        wo.z * wi.z < 0) {
      float eta = wo.z > 0 ? l.disney.eta : 1 / l.disney.eta;
      Vec3 wh = normalize(wo + wi * eta);
      if (wh.z < 0) wh = -wh;
      if (dot(wo, wh) * wo.z <= 0) continue;
    }
    sum += l.pdf(wo, wi);
  }
  return b.num_lobes() > 0 ? sum / b.num_lobes() : 0;
}

const Shape kAll[] = {kMetallic, kGlassy, kThin, kClearcoat, kMix};

std::vector<Vec3> outgoing(bool from_below) {
  Vec3 n = flat_hit().n;
  std::vector<Vec3> w = {n, normalize(n + Vec3{0.8f, 0.3f, 0}), normalize(n + Vec3{-2, 1, 0.5f})};
  if (from_below) w.push_back(normalize(-n + Vec3{0.3f, 0.5f, 0}));
  return w;
}

TEST_F(DisneyMaterialTest, FullBsdfSamplingMatchesPdf) {
  const double kLevel = 1e-3 / 18;
  uint64_t seed = 300;
  for (Shape s : kAll) {
    Bsdf b = bsdf_of(s);
    for (Vec3 wo : outgoing(s == kGlassy || s == kThin)) {
      // The filtered pdf is the BSDF's own where no lobe was filtered.
      Vec3 probe = normalize(flat_hit().n + Vec3{0.1f, -0.2f, 0.3f});
      EXPECT_NEAR(sampled_pdf(b, wo, probe), b.pdf(wo, probe), 1e-5 * b.pdf(wo, probe));
      auto sample = [&](Vec2 u, Vec3* wi) {
        float pdf;
        b.sample_f(wo, wi, u, &pdf);
        return pdf > 0;
      };
      auto pdf = [&](Vec3 wi) { return sampled_pdf(b, wo, wi); };
      auto r = material_test::chi2_directions(sample, pdf, 100000, seed++);
      EXPECT_GT(r.p_value, kLevel)
          << "shape " << s << " wo " << wo.x << "," << wo.y << "," << wo.z << ": " << r.message;
      EXPECT_LT(r.total_mass_error, 5e-3 + 4 * r.total_mass_sigma)
          << "shape " << s << ": " << r.message;
    }
  }
}

// What sample_f returns is the BSDF's f and pdf of the chosen direction
// (all matching lobes summed and averaged), on both sides.
TEST_F(DisneyMaterialTest, SampleAgreesWithEvaluation) {
  Rng rng(41);
  const Vec3 n = flat_hit().n;
  for (Shape s : kAll) {
    Bsdf b = bsdf_of(s);
    for (Vec3 wo : {normalize(n + Vec3{0.5f, 0.2f, 0}), normalize(-n + Vec3{0.1f, 0.4f, 0})}) {
      int accepted = 0;
      for (int i = 0; i < 3000; ++i) {
        Vec3 wi;
        float pdf;
        uint8_t sampled = 0;
        Rgb f = b.sample_f(wo, &wi, {rng.next_float(), rng.next_float()}, &pdf, kAllBxdf, &sampled);
        if (pdf == 0) continue;
        ++accepted;
        // What was sampled is the kind of scattering the direction shows.
        bool reflected = dot(wo, n) * dot(wi, n) > 0;
        ASSERT_EQ(bool(sampled & kReflection), reflected) << "shape " << s;
        ASSERT_FALSE(sampled & kSpecular);
        float pe = b.pdf(wo, wi);
        Rgb fe = b.f(wo, wi);
        ASSERT_NEAR(pdf, pe, 2e-3f * std::max(1.f, pe)) << "shape " << s;
        for (int k = 0; k < 3; ++k)
          ASSERT_NEAR(f[k], fe[k], 2e-3f * std::max(1.f, fe[k])) << "shape " << s;
      }
      EXPECT_GT(accepted, 1000) << "shape " << s;
    }
  }
}

// No setup reflects and transmits more than it receives (importance
// transport, so refraction adds no eta^2), within 4 sigma of the estimate;
// and each one scatters a good part of it (not silently black). Burley's
// retro-reflection is not energy conserving at grazing angles on rough
// surfaces (pbrt-v3 adds it at the full diffuse weight even on thin ones:
// roughness 0.7 on the thin setup reaches 1.09 at cos 0.05), so the setups
// keep the roughness where the model itself stays below 1, but for the thin
// one at grazing angles.
TEST_F(DisneyMaterialTest, AlbedoIsAtMostOne) {
  Rng rng(9);
  const Vec3 n = flat_hit().n;
  Vec3 t, bt;
  coordinate_system(n, &t, &bt);
  for (Shape s : kAll) {
    Bsdf b = bsdf_of(s, TransportMode::kImportance);
    double lowest = 1e9;
    for (int d = 0; d < 10; ++d) {
      float c = (d + 0.5f) / 10;
      Vec3 wo = normalize(n * c + t * std::sqrt(1 - c * c));
      double sum = 0, sum2 = 0;
      const int count = 40000;
      for (int i = 0; i < count; ++i) {
        Vec3 wi;
        float pdf;
        Rgb f = b.sample_f(wo, &wi, {rng.next_float(), rng.next_float()}, &pdf);
        double v = pdf > 0 ? f.max_component() * abs_dot(wi, n) / pdf : 0;
        sum += v;
        sum2 += v * v;
      }
      double mean = sum / count, sigma = std::sqrt((sum2 / count - mean * mean) / count);
      // The thin setup's untinted specular and full-weight retro reach 1.11 at cos 0.05 and
      // 1.05 at 0.15 (pbrt-v3's model): it is held to the bound from cos 0.25 on.
      if (s == kThin && c < 0.25f) continue;
      EXPECT_LE(mean, 1 + 4 * sigma) << "shape " << s << " cos " << c;
      lowest = std::min(lowest, mean);
    }
    EXPECT_GT(lowest, 0.2) << "shape " << s;
  }
}

// pbrt-v3's MixMaterial over a disney material: its lobes weighted by
// amount, the matte's by 1 - amount.
TEST_F(DisneyMaterialTest, MixWeightsTheDisneyLobes) {
  Bsdf mix = bsdf_of(kMix), gold = bsdf_of(kMetallic), chalk = bsdf_of(kChalk);
  ASSERT_EQ(mix.num_lobes(), 2);
  EXPECT_EQ(mix.lobe(0).kind, BxdfKind::kDisney);
  EXPECT_EQ(mix.lobe(0).scale, Rgb(0.3f, 0.6f, 0.8f));
  const Vec3 n = flat_hit().n;
  Vec3 wo = normalize(n + Vec3{0.3f, 0, 0.1f}), wi = normalize(n + Vec3{-0.2f, 0.3f, 0});
  Rgb expected = gold.f(wo, wi) * Rgb(0.3f, 0.6f, 0.8f) + chalk.f(wo, wi) * Rgb(0.7f, 0.4f, 0.2f);
  Rgb f = mix.f(wo, wi);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(f[k], expected[k], 1e-5f * expected[k]) << k;
  // Sampled values carry the weight too.
  Rng rng(3);
  for (int i = 0; i < 200; ++i) {
    Vec3 w;
    float pdf;
    Rgb fs = mix.sample_f(wo, &w, {rng.next_float(), rng.next_float()}, &pdf);
    if (pdf == 0) continue;
    Rgb fe = gold.f(wo, w) * Rgb(0.3f, 0.6f, 0.8f) + chalk.f(wo, w) * Rgb(0.7f, 0.4f, 0.2f);
    for (int k = 0; k < 3; ++k) ASSERT_NEAR(fs[k], fe[k], 1e-4f * std::max(1.f, fe[k]));
  }
}

// pbrt-v3's DisneyMaterial supports a bump map: the shading normal tilts
// and the lobes live in the tilted frame.
TEST_F(DisneyMaterialTest, BumpMapTiltsTheShadingFrame) {
  Vec3 n = flat_hit().n;
  Bsdf plain = bsdf_of(kDefault), bumped = bsdf_of(kBumped);
  EXPECT_NEAR(dot(plain.shading_normal(), n), 1, 1e-6f);
  EXPECT_LT(dot(bumped.shading_normal(), n), 0.99f);
  EXPECT_EQ(bumped.num_lobes(), 3);
}

TEST(DisneyMaterial, TooManyLobesFailAtBuild) {
  struct Case {
    const char* name;
    const char* body;
    const char* message;
  } cases[] = {
      {"disney_mix_too_many",
       "MakeNamedMaterial \"a\" \"string type\" \"disney\" \"bool thin\" \"true\" "
       "\"float sheen\" 0.5\n"
       "MakeNamedMaterial \"b\" \"string type\" \"disney\"\n"
       "Material \"mix\" \"string namedmaterial1\" \"a\" \"string namedmaterial2\" \"b\"\n"
       "Shape \"sphere\"",
       "not supported yet: mix material with more than 8 BSDF lobes (scene.pbrt:"},
  };
  for (const Case& c : cases) {
    MaterialScene s;
    EXPECT_FALSE(s.load(c.name, c.body)) << c.name;
    EXPECT_NE(s.error.find(c.message), std::string::npos) << c.name << ": " << s.error;
  }
  // pbrt-v3 reads scatterdistance only for the solid surface's diffuse part:
  // thin or fully metallic surfaces render without subsurface scattering.
  // A mix of a thin (5 lobes: no sheen, clearcoat or spectrans) and a
  // default disney (3) fits in 8.
  MaterialScene ok;
  EXPECT_TRUE(ok.load("disney_sss_ignored", R"(
Material "disney" "rgb scatterdistance" [0.1 0.2 0.3] "bool thin" "true"
Shape "sphere"
Material "disney" "rgb scatterdistance" [0.1 0.2 0.3] "float metallic" 1
Shape "sphere"
MakeNamedMaterial "a" "string type" "disney" "bool thin" "true"
MakeNamedMaterial "b" "string type" "disney"
Material "mix" "string namedmaterial1" "a" "string namedmaterial2" "b"
Shape "sphere"
)")) << ok.error;
}

}  // namespace
}  // namespace rt
