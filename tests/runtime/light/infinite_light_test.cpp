// Infinite lights: a constant one gives irradiance pi L on a plane, sampled uniformly; an
// environment map's importance sampling has a pdf that integrates to one
// over the sphere and agrees between sample_li and pdf_li, with radiance
// that agrees with infinite_le.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "light_test_scene.h"

namespace rt {
namespace {

TEST(InfiniteLight, ConstantGivesPiLOnAPlane) {
  LightScene s;
  ASSERT_TRUE(load_light_scene("infinite_constant", R"(
LightSource "infinite" "rgb L" [0.5 1 2] "rgb scale" [2 2 2] "integer nsamples" 8
)",
                               box({-1, -1, -1}, {1, 1, 1}), &s));
  ASSERT_EQ(s.lights.count(), 1u);
  EXPECT_EQ(s.lights.kind(0), LightKind::kInfinite);
  EXPECT_FALSE(s.lights.is_delta(0));
  EXPECT_TRUE(s.lights.has_infinite());
  EXPECT_EQ(s.lights.nsamples(0), 8);
  Interaction ref = surface_point({0.2f, 0.1f, 0}, {0.3f, -0.2f, 1});
  int mismatches = 0;
  Rgb e = estimate_irradiance(s.lights, 0, ref, 100000, 5, &mismatches, Vec3{0, 0, 1});
  EXPECT_EQ(mismatches, 0);
  EXPECT_NEAR(e.r, kPi * 1, 0.01 * kPi);
  EXPECT_NEAR(e.b, kPi * 4, 0.01 * 4 * kPi);
  RayDifferential ray;
  ray.d = normalize(Vec3{1, 2, 3});
  EXPECT_EQ(s.lights.infinite_le(ray), Rgb(1, 2, 4));
  float r = std::sqrt(3.f);
  EXPECT_NEAR(s.lights.power(0).g, kPi * r * r * 2, 1e-4);

  // Sampled uniformly over the sphere: half the directions have |z| < 1/2 (a one-texel map's
  // sampling, uniform in theta, puts a third there), each at the density 1 / 4pi that
  // pdf_li gives every direction, and the radiance is L in each.
  Rng rng(7);
  const int n = 40000;
  int band = 0, bad = 0;
  for (int i = 0; i < n; ++i) {
    LightSample ls;
    Rgb li = s.lights.sample_li(0, ref, {rng.next_float(), rng.next_float()}, &ls);
    band += std::fabs(ls.wi.z) < 0.5f;
    bad += li != Rgb(1, 2, 4) || ls.pdf != kInv4Pi ||
           s.lights.pdf_li(0, ref, ls.wi, nullptr) != kInv4Pi;
  }
  EXPECT_EQ(bad, 0);
  EXPECT_NEAR(band / double(n), 0.5, 0.01);
}

class EnvironmentMap : public ::testing::Test {
 protected:
  void SetUp() override {
    s_.dir = testing_support::scratch_dir("infinite_envmap");
    // 16 x 8, a smooth gradient plus a small bright patch near the top.
    const int w = 16, h = 8;
    std::vector<float> rgb(w * h * 3);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        float* p = &rgb[(y * w + x) * 3];
        p[0] = 0.1f + 0.05f * x;
        p[1] = 0.2f + 0.1f * y;
        p[2] = 0.3f;
        if (x == 5 && (y == 1 || y == 2)) p[0] = p[1] = p[2] = 40;
      }
    write_pfm(s_.dir + "/env.pfm", w, h, rgb.data());
    ASSERT_TRUE(load_light_scene("infinite_envmap", R"(
AttributeBegin
  Rotate -90 1 0 0
  Rotate 30 0 0 1
  LightSource "infinite" "string mapname" "env.pfm" "rgb L" [1 0.5 2] "rgb scale" [1.5 1.5 1.5]
AttributeEnd
)",
                                 box({-1, -1, -1}, {1, 1, 1}), &s_));
    ASSERT_EQ(s_.lights.count(), 1u);
  }
  LightScene s_;
};

TEST_F(EnvironmentMap, PdfIntegratesToOneOverTheSphere) {
  // Stratified uniform directions: a quadrature of pdf_li over the sphere.
  const int nz = 600, nphi = 1200;
  double sum = 0;
  Interaction ref = surface_point({0, 0, 0}, {0, 0, 1});
  Rng rng(3);
  for (int i = 0; i < nz; ++i)
    for (int j = 0; j < nphi; ++j) {
      Vec3 w = uniform_sample_sphere({(i + rng.next_float()) / nz, (j + rng.next_float()) / nphi});
      sum += s_.lights.pdf_li(0, ref, w, nullptr) / uniform_sphere_pdf();
    }
  EXPECT_NEAR(sum / (nz * nphi), 1.0, 0.01);
}

// At and around the map's poles (here world +-y) sin theta is 0 or rounds below it (theta
// = pi as a float has a sine of -8.7e-8): the pdf must stay finite and not negative there.
TEST_F(EnvironmentMap, PdfAtThePolesIsFiniteAndNotNegative) {
  Interaction ref = surface_point({0, 0, 0}, {0, 0, 1});
  Rng rng(12);
  for (float pole : {-1.f, 1.f})
    for (int k = 0; k < 2000; ++k) {
      const float e = k == 0 ? 0 : 1e-3f * rng.next_float();
      const Vec3 w =
          normalize(Vec3{e * (rng.next_float() - .5f), pole, e * (rng.next_float() - .5f)});
      const float pdf = s_.lights.pdf_li(0, ref, w, nullptr);
      ASSERT_TRUE(std::isfinite(pdf) && pdf >= 0)
          << "w " << w.x << " " << w.y << " " << w.z << " pdf " << pdf;
    }
}

TEST_F(EnvironmentMap, SamplesAgreeWithPdfAndRadiance) {
  Interaction ref = surface_point({0.1f, 0.2f, 0.3f}, {0, 1, 0});
  Rng rng(4);
  int pdf_mismatch = 0, le_mismatch = 0, bright = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    LightSample ls;
    Rgb li = s_.lights.sample_li(0, ref, {rng.next_float(), rng.next_float()}, &ls);
    ASSERT_GT(ls.pdf, 0);
    EXPECT_NEAR(length(ls.wi), 1, 1e-5);
    float pdf = s_.lights.pdf_li(0, ref, ls.wi, nullptr);
    // Within a degree of the map's poles (light +z, here world +y) acos
    // loses the precision sin(theta) needs, in pbrt-v3 as here.
    bool near_pole = std::fabs(ls.wi.y) > 0.9998f;
    if (!near_pole && !(std::fabs(pdf - ls.pdf) <= 1e-3f * ls.pdf)) ++pdf_mismatch;
    RayDifferential ray;
    ray.o = ref.p;
    ray.d = ls.wi;
    Rgb le = s_.lights.infinite_le(ray);
    if (!(std::fabs(le.g - li.g) <= 1e-3f * li.g + 1e-6f)) ++le_mismatch;
    if (li.g > 10) ++bright;
  }
  EXPECT_EQ(pdf_mismatch, 0);
  // A sample on a texel boundary may round to the neighbour: allow a handful.
  EXPECT_LE(le_mismatch, 2);
  // The bright patch holds a large share of the power: importance sampling finds it.
  EXPECT_GT(bright, n / 4);
}

TEST_F(EnvironmentMap, ImportanceSampledIrradianceMatchesQuadrature) {
  Interaction ref = surface_point({0, 0, 0}, {0.2f, 0.9f, 0.3f});
  Rgb importance = estimate_irradiance(s_.lights, 0, ref, 100000, 6);
  // Stratified cosine-free quadrature of Le cos over the sphere.
  const int nz = 400, nphi = 800;
  Rng rng(7);
  Rgb sum;
  for (int i = 0; i < nz; ++i)
    for (int j = 0; j < nphi; ++j) {
      Vec3 w = uniform_sample_sphere({(i + rng.next_float()) / nz, (j + rng.next_float()) / nphi});
      float c = dot(w, ref.n);
      if (c <= 0) continue;
      RayDifferential ray;
      ray.d = w;
      sum += s_.lights.infinite_le(ray) * (c / uniform_sphere_pdf());
    }
  Rgb quad = sum / float(nz * nphi);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(importance[k], quad[k], 0.02 * quad[k]) << k;
  // L * scale multiplies the map: blue is 3 x 0.3 where the patch is absent.
  EXPECT_GT(quad.b, 0);
}

// A sample taken with its texel lookup deferred (the surface kernels read the texels only once
// the shadow ray is clear) finishes to exactly the sample taken whole; before finish_li its
// radiance is the light's scale, non-black exactly when the whole sample's can be.
TEST_F(EnvironmentMap, DeferredTexelsFinishToTheWholeSample) {
  Interaction ref = surface_point({0.1f, -0.2f, 0.3f}, {0, 0, 1});
  Rng rng(17);
  for (int i = 0; i < 5000; ++i) {
    const Vec2 u{rng.next_float(), rng.next_float()};
    LightSample whole, deferred;
    const Rgb li = s_.lights.sample_li(0, ref, u, &whole);
    const Rgb scale = s_.lights.sample_li(0, ref, u, &deferred, true);
    ASSERT_EQ(deferred.pdf, whole.pdf);
    ASSERT_EQ(deferred.wi, whole.wi);
    if (whole.pdf == 0) continue;
    EXPECT_EQ(scale, Rgb(1.5f, 0.75f, 3));
    EXPECT_EQ(s_.lights.finish_li(deferred), li) << "u " << u.x << " " << u.y;
    EXPECT_EQ(s_.lights.finish_li(whole), li);
  }
}

}  // namespace
}  // namespace rt
