// The shortcuts the integrators take give bit for bit what the plain calls give:
// Bsdf::f_pdf against f() and pdf(), Bsdf::f_pdf_both against f() and pdf() both ways,
// Bxdf::sample_wi against sample_f(), on both sides of the surface, at grazing, equal and
// opposite directions, for lobes that share work (microfacet reflection) and lobes that do not.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "lobe_checks.h"
#include "runtime/core/rng.h"
#include "runtime/core/sampling.h"
#include "runtime/material/bsdf.h"

namespace rt {
namespace {

MicrofacetDistribution tr(float ax, float ay, MicrofacetKind kind) {
  return material_test::microfacet(kind, ax, ay);
}

bool same_bits(float a, float b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}
bool same_bits(Rgb a, Rgb b) {
  return same_bits(a.r, b.r) && same_bits(a.g, b.g) && same_bits(a.b, b.b);
}
bool same_bits(Vec3 a, Vec3 b) {
  return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}

// Lobe sets as pbrt-v3's materials make them (metal, plastic, rough glass, substrate,
// translucent, matte with sigma, a specular coat over a glossy one), one of them scaled as
// a mix scales it.
std::vector<std::vector<Bxdf>> lobe_sets() {
  const auto trk = MicrofacetKind::kTrowbridgeReitz, bk = MicrofacetKind::kBeckmann;
  return {
      {make_microfacet_reflection(Rgb(1), tr(0.2f, 0.45f, trk),
                                  Fresnel::conductor(Rgb(1), Rgb(0.2f, 0.9f, 1.1f), Rgb(3.9f)))},
      {make_lambertian_reflection(Rgb(0.5f)),
       make_microfacet_reflection(Rgb(0.3f), tr(0.1f, 0.1f, bk), Fresnel::dielectric(1, 1.5f))},
      {make_microfacet_reflection(Rgb(1), tr(0.3f, 0.3f, trk), Fresnel::dielectric(1, 1.5f)),
       make_microfacet_transmission(Rgb(1), tr(0.3f, 0.3f, trk), 1, 1.5f,
                                    TransportMode::kRadiance)},
      {make_fresnel_blend(Rgb(0.5f), Rgb(0.2f), tr(0.3f, 0.1f, trk))},
      {make_lambertian_reflection(Rgb(0.4f)), make_lambertian_transmission(Rgb(0.3f))},
      {make_oren_nayar(Rgb(0.7f), 25)},
      {make_specular_reflection(Rgb(1), Fresnel::dielectric(1, 1.5f)),
       make_microfacet_reflection(Rgb(0.8f), tr(0.05f, 0.05f, trk), Fresnel::no_op())},
  };
}

Bsdf make_bsdf(const std::vector<Bxdf>& lobes, bool scaled) {
  SurfaceInteraction si;
  si.n = normalize(Vec3{0.1f, -0.2f, 1});
  si.shading.n = normalize(Vec3{0.25f, 0.1f, 1});
  si.shading.dpdu = Vec3{1, 0.3f, -0.2f};
  Bsdf bsdf;
  bsdf.init(si);
  for (const Bxdf& b : lobes) bsdf.add(b);
  if (scaled) bsdf.scale_lobes(Rgb(0.25f, 0.5f, 0.75f));
  return bsdf;
}

// Random directions over the whole sphere, then the cases with no half vector or no angle.
std::vector<std::pair<Vec3, Vec3>> direction_pairs(const Bsdf& bsdf, Rng& rng) {
  std::vector<std::pair<Vec3, Vec3>> out;
  for (int i = 0; i < 3000; ++i)
    out.push_back({uniform_sample_sphere({rng.next_float(), rng.next_float()}),
                   uniform_sample_sphere({rng.next_float(), rng.next_float()})});
  const Vec3 n = bsdf.shading_normal(), t = bsdf.local_to_world({1, 0, 0});
  const Vec3 w = normalize(Vec3{0.3f, 0.5f, 0.8f});
  for (Vec3 a : {w, n, -n, t})
    for (Vec3 b : {a, -a, n, t, -t}) out.push_back({a, b});
  return out;
}

TEST(BsdfShortcuts, FPdfGivesWhatFAndPdfGive) {
  Rng rng(11);
  int checked = 0;
  for (const std::vector<Bxdf>& lobes : lobe_sets())
    for (bool scaled : {false, true}) {
      const Bsdf bsdf = make_bsdf(lobes, scaled);
      for (uint8_t flags : {uint8_t(kAllBxdf), uint8_t(kAllBxdf & ~kSpecular)})
        for (const auto& [wo, wi] : direction_pairs(bsdf, rng)) {
          float pdf = -1;
          const Rgb f = bsdf.f_pdf(wo, wi, flags, &pdf);
          ASSERT_TRUE(same_bits(f, bsdf.f(wo, wi, flags)))
              << "lobe 0 kind " << int(lobes[0].kind) << " f " << f.r;
          ASSERT_TRUE(same_bits(pdf, bsdf.pdf(wo, wi, flags)))
              << "lobe 0 kind " << int(lobes[0].kind) << " pdf " << pdf;
          checked += f.r > 0 && pdf > 0;
        }
    }
  EXPECT_GT(checked, 10000);  // most pairs have a value; the comparison is not all zeros
}

TEST(BsdfShortcuts, FPdfBothGivesFAndPdfEachWay) {
  Rng rng(13);
  int checked = 0;
  for (const std::vector<Bxdf>& lobes : lobe_sets())
    for (bool scaled : {false, true}) {
      const Bsdf bsdf = make_bsdf(lobes, scaled);
      for (const auto& [a, b] : direction_pairs(bsdf, rng)) {
        float ab = -1, ba = -1;
        const Rgb f = bsdf.f_pdf_both(a, b, &ab, &ba);
        ASSERT_TRUE(same_bits(f, bsdf.f(a, b))) << "lobe 0 kind " << int(lobes[0].kind);
        ASSERT_TRUE(same_bits(ab, bsdf.pdf(a, b))) << "lobe 0 kind " << int(lobes[0].kind);
        ASSERT_TRUE(same_bits(ba, bsdf.pdf(b, a))) << "lobe 0 kind " << int(lobes[0].kind);
        checked += f.r > 0 && ab > 0 && ba > 0;
      }
    }
  EXPECT_GT(checked, 10000);
}

TEST(BsdfShortcuts, SampleWiGivesSampleFsDirectionPdfAndFlags) {
  Rng rng(5);
  int sampled = 0;
  for (const std::vector<Bxdf>& lobes : lobe_sets())
    for (const Bxdf& b : lobes)
      for (int i = 0; i < 3000; ++i) {
        const Vec3 wo =
            i == 0 ? Vec3{0, 0, 1} : uniform_sample_sphere({rng.next_float(), rng.next_float()});
        const Vec2 u{rng.next_float(), rng.next_float()};
        Vec3 wi_f{7, 7, 7}, wi_s{7, 7, 7};
        float pdf_f = -1, pdf_s = -1;
        uint8_t flags_f = 0, flags_s = 0;
        b.sample_f(wo, &wi_f, u, &pdf_f, &flags_f);
        b.sample_wi(wo, &wi_s, u, &pdf_s, &flags_s);
        ASSERT_TRUE(same_bits(wi_f, wi_s)) << int(b.kind);
        ASSERT_TRUE(same_bits(pdf_f, pdf_s)) << int(b.kind);
        ASSERT_EQ(flags_f, flags_s) << int(b.kind);
        sampled += pdf_s > 0;
      }
  EXPECT_GT(sampled, 15000);
}

}  // namespace
}  // namespace rt
