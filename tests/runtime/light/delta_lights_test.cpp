// Point, spot and distant lights: exact radiance, directions and powers,
// placed by the scene's transforms exactly as pbrt-v3 places them.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "light_test_scene.h"

namespace rt {
namespace {

TEST(DeltaLights, PointLightIrradianceIsIOverRSquaredTimesCos) {
  LightScene s;
  // pbrt-v3 translates by `from` after the CTM: the light sits at the CTM's
  // origin (1 2 3) plus from (0 0 1), not at CTM(from) = (1 2 5).
  ASSERT_TRUE(load_light_scene("point_light", R"(
AttributeBegin
  Translate 1 2 3
  Scale 2 2 2
  LightSource "point" "rgb I" [2 4 8] "rgb scale" [0.5 0.5 0.25] "point from" [0 0 1]
AttributeEnd
)",
                               box({-5, -5, -5}, {5, 5, 5}), &s));
  ASSERT_EQ(s.lights.count(), 1u);
  EXPECT_EQ(s.lights.kind(0), LightKind::kPoint);
  EXPECT_TRUE(s.lights.is_delta(0));
  EXPECT_EQ(s.lights.nsamples(0), 1);

  Interaction ref = surface_point({4, 2, 0}, {0, 0, 1});  // 3 across, 4 below: r = 5
  LightSample ls;
  Rgb li = s.lights.sample_li(0, ref, {0.3f, 0.7f}, &ls);
  EXPECT_EQ(ls.pdf, 1.f);
  EXPECT_TRUE(ls.delta);
  EXPECT_EQ(li, ls.li);
  EXPECT_FLOAT_EQ(ls.p_light.p.x, 1);
  EXPECT_FLOAT_EQ(ls.p_light.p.y, 2);
  EXPECT_FLOAT_EQ(ls.p_light.p.z, 4);
  EXPECT_NEAR(ls.wi.x, -0.6f, 1e-6);
  EXPECT_NEAR(ls.wi.z, 0.8f, 1e-6);
  Rgb e = li * dot(ref.n, ls.wi);  // irradiance I / r^2 cos
  EXPECT_NEAR(e.r, 1.f / 25 * 0.8f, 1e-7);
  EXPECT_NEAR(e.g, 2.f / 25 * 0.8f, 1e-7);
  EXPECT_NEAR(e.b, 2.f / 25 * 0.8f, 1e-7);
  EXPECT_EQ(s.lights.pdf_li(0, ref, ls.wi, nullptr), 0.f);
  EXPECT_FLOAT_EQ(s.lights.power(0).g, 4 * kPi * 2);
}

TEST(DeltaLights, SpotLightCentreInsideFalloffOutside) {
  LightScene s;
  // Aimed straight down from height 5: cone 30 degrees, falloff from 20.
  ASSERT_TRUE(load_light_scene("spot_light", R"(
LightSource "spot" "rgb I" [10 10 10] "point from" [0 0 5] "point to" [0 0 0]
  "float coneangle" 30 "float conedeltaangle" 10
AttributeBegin
  Rotate 90 0 1 0
  LightSource "spot" "rgb I" [1 1 1] "rgb scale" [3 3 3]
AttributeEnd
)",
                               box({-5, -5, -5}, {5, 5, 5}), &s));
  ASSERT_EQ(s.lights.count(), 2u);
  EXPECT_EQ(s.lights.kind(0), LightKind::kSpot);
  auto li_at_angle = [&](float deg) {
    float x = 5 * std::tan(radians(deg));
    LightSample ls;
    Rgb li = s.lights.sample_li(0, surface_point({x, 0, 0}, {0, 0, 1}), {0.5f, 0.5f}, &ls);
    EXPECT_EQ(ls.pdf, 1.f);
    return li.r * (25 + x * x) / 10;  // the falloff factor
  };
  EXPECT_FLOAT_EQ(li_at_angle(0), 1);
  EXPECT_FLOAT_EQ(li_at_angle(15), 1);
  float c = std::cos(radians(25.f)), c0 = std::cos(radians(30.f)), c1 = std::cos(radians(20.f));
  float d = (c - c0) / (c1 - c0);
  EXPECT_NEAR(li_at_angle(25), d * d * d * d, 1e-4);
  EXPECT_GT(li_at_angle(25), 0.01f);
  EXPECT_LT(li_at_angle(25), 0.99f);
  EXPECT_EQ(li_at_angle(35), 0);
  EXPECT_NEAR(s.lights.power(0).r, 10 * 2 * kPi * (1 - .5f * (c1 + c0)), 1e-4);

  // The second spot (default cone along +z) is turned by the CTM to shine along +x.
  LightSample ls;
  EXPECT_FLOAT_EQ(s.lights.sample_li(1, surface_point({2, 0, 0}, {-1, 0, 0}), {}, &ls).r, 3.f / 4);
  EXPECT_EQ(s.lights.sample_li(1, surface_point({0, 0, 2}, {0, 0, -1}), {}, &ls).r, 0.f);
}

TEST(DeltaLights, DistantLightComesFromBeyondTheWorld) {
  LightScene s;
  ASSERT_TRUE(load_light_scene("distant_light", R"(
AttributeBegin
  Rotate 90 0 0 1
  LightSource "distant" "rgb L" [1 2 3] "rgb scale" [2 2 2] "point from" [0 0 0] "point to" [1 0 0]
AttributeEnd
)",
                               box({-1, -1, -1}, {1, 1, 1}), &s));
  ASSERT_EQ(s.lights.count(), 1u);
  EXPECT_EQ(s.lights.kind(0), LightKind::kDistant);
  Interaction ref = surface_point({0.5f, 0, 0}, {0, -1, 0});
  LightSample ls;
  Rgb li = s.lights.sample_li(0, ref, {0.1f, 0.9f}, &ls);
  // from - to = -x, turned 90 degrees about z: the light arrives from -y.
  EXPECT_NEAR(ls.wi.x, 0, 1e-6);
  EXPECT_NEAR(ls.wi.y, -1, 1e-6);
  EXPECT_EQ(li, Rgb(2, 4, 6));
  EXPECT_EQ(ls.pdf, 1.f);
  float r = std::sqrt(3.f);
  EXPECT_NEAR(ls.p_light.p.y, -2 * r, 1e-5);
  EXPECT_NEAR(s.lights.power(0).b, 6 * kPi * r * r, 1e-4);
}

TEST(DeltaLights, ProjectionAndGoniometricWithoutMapsAreMaskedPointLights) {
  LightScene s;
  ASSERT_TRUE(load_light_scene("projection_light", R"(
LightSource "projection" "rgb I" [4 4 4] "float fov" 90
LightSource "goniometric" "rgb I" [2 2 2]
)",
                               box({-1, -1, -1}, {1, 1, 1}), &s));
  ASSERT_EQ(s.lights.count(), 2u);
  EXPECT_EQ(s.lights.kind(0), LightKind::kProjection);
  EXPECT_EQ(s.lights.kind(1), LightKind::kGoniometric);
  LightSample ls;
  // fov 90, square screen: +z within 45 degrees of the axis in x and y is lit.
  EXPECT_FLOAT_EQ(s.lights.sample_li(0, surface_point({0, 0, 2}, {0, 0, -1}), {}, &ls).r, 1);
  EXPECT_FLOAT_EQ(s.lights.sample_li(0, surface_point({1.9f, 0, 2}, {0, 0, -1}), {}, &ls).r,
                  4 / (4 + 1.9f * 1.9f));
  EXPECT_EQ(s.lights.sample_li(0, surface_point({2.1f, 0, 2}, {0, 0, -1}), {}, &ls).r, 0);
  EXPECT_EQ(s.lights.sample_li(0, surface_point({0, 0, -2}, {0, 0, 1}), {}, &ls).r, 0);
  EXPECT_FLOAT_EQ(s.lights.sample_li(1, surface_point({0, 0, -2}, {0, 0, 1}), {}, &ls).r, 0.5f);
  EXPECT_FLOAT_EQ(s.lights.power(1).r, 8 * kPi);
}

// A 4 x 2 map: top row 1, bottom row 5 (light maps are not flipped: t = 0 is the top).
TEST(DeltaLights, GoniometricAndProjectionMaps) {
  LightScene s;
  s.dir = testing_support::scratch_dir("light_maps");
  std::vector<float> rgb(4 * 2 * 3, 1.f);
  for (int i = 12; i < 24; ++i) rgb[i] = 5;
  write_pfm(s.dir + "/map.pfm", 4, 2, rgb.data());
  ASSERT_TRUE(load_light_scene("light_maps", R"(
LightSource "goniometric" "rgb I" [2 2 2] "string mapname" "map.pfm"
LightSource "projection" "rgb I" [1 1 1] "float fov" 90 "string mapname" "map.pfm"
)",
                               box({-1, -1, -1}, {1, 1, 1}), &s));
  ASSERT_EQ(s.lights.count(), 2u);
  LightSample ls;
  // Goniometric: theta measured from light +y. At 45 degrees (t = 1/4) the
  // bilinear lookup lands on the top row's centres; at 135 degrees, the bottom's.
  float r = std::sqrt(2.f);
  EXPECT_NEAR(s.lights.sample_li(0, surface_point({1, 1, 0}, {-1, -1, 0}), {}, &ls).r, 2 / 2.f,
              1e-5);
  EXPECT_NEAR(s.lights.sample_li(0, surface_point({1, -1, 0}, {-1, 1, 0}), {}, &ls).r,
              5 * 2 / (r * r), 1e-5);
  // Its power: 4 pi I times the map's average.
  EXPECT_NEAR(s.lights.power(0).r, 4 * kPi * 2 * 3, 1e-3);
  // Projection: screen y up is t up, so the file's bottom row lights +y;
  // the 2:1 aspect widens the screen to x in [-2, 2].
  EXPECT_NEAR(s.lights.sample_li(1, surface_point({0, 0.5f, 1}, {0, 0, -1}), {}, &ls).r, 5 / 1.25f,
              1e-5);
  EXPECT_NEAR(s.lights.sample_li(1, surface_point({0, -0.5f, 1}, {0, 0, -1}), {}, &ls).r, 1 / 1.25f,
              1e-5);
  EXPECT_GT(s.lights.sample_li(1, surface_point({1.9f, 0, 1}, {0, 0, -1}), {}, &ls).r, 0);
  EXPECT_EQ(s.lights.sample_li(1, surface_point({2.1f, 0, 1}, {0, 0, -1}), {}, &ls).r, 0);
}

}  // namespace
}  // namespace rt
