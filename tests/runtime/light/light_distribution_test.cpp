// Light selection: uniform, power (in proportion to luminance of power) and
// spatial (valid distributions, the nearby light favoured, the same result
// from two builds and from concurrent lookups; sample() equal to lookup()).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include "light_test_scene.h"
#include "runtime/light/light_distribution.h"

namespace rt {
namespace {

const char* kTwoPoints = R"(
LightSource "point" "rgb I" [1 1 1] "point from" [-9 0 0]
LightSource "point" "rgb I" [3 3 3] "point from" [9 0 0]
LightSource "distant" "rgb L" [0.01 0.02 0.03]
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [2 2 2]
  Translate 0 0 0.9
  ReverseOrientation
  Shape "disk" "float radius" 0.5
AttributeEnd
)";

Bounds3 world() {
  return box({-10, -1, -1}, {10, 1, 1});
}

TEST(LightDistribution, UniformAndPower) {
  LightScene s;
  ASSERT_TRUE(load_light_scene("distribution_power", kTwoPoints, world(), &s));
  ASSERT_EQ(s.lights.count(), 4u);
  std::string error;
  LightDistribution uniform;
  ASSERT_TRUE(uniform.build(s.lights, world(), "uniform", &error)) << error;
  const Distribution1D& u = uniform.lookup({0, 0, 0});
  ASSERT_EQ(u.count(), 4);
  for (int i = 0; i < 4; ++i) EXPECT_FLOAT_EQ(u.discrete_pdf(i), 0.25f);

  LightDistribution power;
  ASSERT_TRUE(power.build(s.lights, world(), "power", &error)) << error;
  const Distribution1D& p = power.lookup({5, 0, 0});
  float total = 0;
  for (int i = 0; i < 4; ++i) total += s.lights.power(i).luminance();
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(p.discrete_pdf(i), s.lights.power(i).luminance() / total, 1e-6) << i;
  EXPECT_NEAR(p.discrete_pdf(1) / p.discrete_pdf(0), 3, 1e-5);

  LightDistribution bad;
  EXPECT_FALSE(bad.build(s.lights, world(), "nearest", &error));
  EXPECT_NE(error.find("nearest"), std::string::npos);
}

TEST(LightDistribution, SpatialIsValidLocalAndDeterministic) {
  LightScene s;
  ASSERT_TRUE(load_light_scene("distribution_spatial", kTwoPoints, world(), &s));
  std::string error;
  LightDistribution a, b;
  ASSERT_TRUE(a.build(s.lights, world(), "spatial", &error)) << error;
  ASSERT_TRUE(b.build(s.lights, world(), "spatial", &error)) << error;
  EXPECT_EQ(a.voxels()[0], 64);
  EXPECT_EQ(a.voxels()[1], 6);  // round(2 / 20 * 64)
  EXPECT_EQ(a.voxels()[2], 6);

  // Near each point light, that light dominates; every light keeps some chance.
  const Distribution1D& left = a.lookup({-8.9f, 0.1f, 0});
  const Distribution1D& right = a.lookup({8.9f, -0.1f, 0});
  EXPECT_GT(left.discrete_pdf(0), 0.9f);
  EXPECT_GT(right.discrete_pdf(1), 0.9f);
  for (int i = 0; i < 4; ++i) {
    EXPECT_GT(left.discrete_pdf(i), 0) << i;
    EXPECT_GT(right.discrete_pdf(i), 0) << i;
  }
  // Under the disk, the disk matters most after the (far) point lights fade.
  EXPECT_GT(a.lookup({0, 0, 0.5f}).discrete_pdf(3), 0.5f);

  // Points along a line through many voxels: valid, and identical between the
  // two builds and between serial and concurrent first lookups.
  std::vector<Vec3> pts;
  for (int i = 0; i < 300; ++i)
    pts.push_back({-10.5f + 0.07f * i, -1.2f + 0.008f * i, 1.1f - 0.0075f * i});
  LightDistribution c;
  ASSERT_TRUE(c.build(s.lights, world(), "spatial", &error));
  std::vector<std::thread> threads;
  for (int t = 0; t < 2; ++t)
    threads.emplace_back([&, t] {
      for (size_t i = t; i < pts.size(); i += 2) c.lookup(pts[i]);
    });
  for (auto& th : threads) th.join();
  for (const Vec3& p : pts) {
    const Distribution1D& da = a.lookup(p);
    const Distribution1D& db = b.lookup(p);
    const Distribution1D& dc = c.lookup(p);
    ASSERT_EQ(da.count(), 4);
    float sum = 0;
    for (int i = 0; i < 4; ++i) {
      sum += da.discrete_pdf(i);
      EXPECT_EQ(da.discrete_pdf(i), db.discrete_pdf(i));
      EXPECT_EQ(da.discrete_pdf(i), dc.discrete_pdf(i));
    }
    EXPECT_NEAR(sum, 1, 1e-5);
  }
}

TEST(LightDistribution, NoLightsAndOneLight) {
  LightScene none;
  ASSERT_TRUE(load_light_scene("distribution_none", "Shape \"sphere\"", world(), &none));
  std::string error;
  LightDistribution d;
  ASSERT_TRUE(d.build(none.lights, world(), "spatial", &error)) << error;
  EXPECT_EQ(d.lookup({0, 0, 0}).count(), 0);

  LightScene one;
  ASSERT_TRUE(load_light_scene("distribution_one", "LightSource \"point\"", world(), &one));
  ASSERT_TRUE(d.build(one.lights, world(), "spatial", &error)) << error;
  EXPECT_FLOAT_EQ(d.lookup({3, 0, 0}).discrete_pdf(0), 1);
}

// sample() reads a compact copy of each voxel's distribution (up to kFlatLights lights: each
// light's pmf and the cdf between its ends), made by the first sample() there; with more
// lights it reads the distribution itself. Either way, by point or by a Site found beforehand
// (the path integrator's prefetch), its choice and pmf are lookup(p).sample_discrete's, bit
// for bit, also for a u on a cdf entry or just beside one.
TEST(LightDistribution, SampleMatchesLookupByPointAndBySite) {
  auto points = [](int k) {
    std::string text;
    for (int i = 0; i < k; ++i)
      text += "LightSource \"point\" \"rgb I\" [0.5 1 " + std::to_string(1 + i) +
              "] \"point from\" [" + std::to_string(-7 + 3 * i) + " 0.5 -0.5]\n";
    return text;
  };
  const std::string many = kTwoPoints + points(6);
  const std::string two = points(2), three = points(3), five = points(5), six = points(6);
  for (const std::string* scene : {&two, &three, &five, &six, &many}) {
    LightScene s;
    ASSERT_TRUE(load_light_scene("distribution_sample", *scene, world(), &s));
    std::string error;
    LightDistribution d;
    ASSERT_TRUE(d.build(s.lights, world(), "spatial", &error)) << error;
    for (int i = 0; i < 300; ++i) {
      const Vec3 p{-10.5f + 0.07f * i, -1.2f + 0.008f * i, 1.1f - 0.0075f * i};
      std::vector<float> us = {0.f, 0.013f * float(i % 71), 0.37f, 0.999999f};
      const Distribution1D& at_p = d.lookup(p);
      for (int k = 1; k < at_p.count(); ++k) {
        const float c = at_p.cdf_data()[k];
        us.insert(us.end(), {c, std::nextafter(c, 0.f), std::nextafter(c, 1.f)});
      }
      // pmf() before the voxel's flat record exists (read from its distribution) and after.
      const int first = i % at_p.count();
      EXPECT_EQ(d.pmf(d.site(p), first), at_p.discrete_pdf(first)) << s.lights.count() << " " << i;
      for (float u : us) {
        float pmf_lookup = -1, pmf_point = -1, pmf_site = -1;
        const int expected = d.lookup(p).sample_discrete(u, &pmf_lookup);
        EXPECT_EQ(d.sample(p, u, &pmf_point), expected) << s.lights.count() << " " << i << " " << u;
        EXPECT_EQ(d.sample(d.site(p), u, &pmf_site), expected) << s.lights.count() << " " << i;
        EXPECT_EQ(pmf_point, pmf_lookup);
        EXPECT_EQ(pmf_site, pmf_lookup);
        EXPECT_EQ(d.pmf(d.site(p), expected), pmf_lookup);
      }
      for (int j = 0; j < at_p.count(); ++j)
        EXPECT_EQ(d.pmf(d.site(p), j), at_p.discrete_pdf(j)) << s.lights.count() << " " << i;
    }
    for (const char* strategy : {"uniform", "power"}) {
      LightDistribution single;
      ASSERT_TRUE(single.build(s.lights, world(), strategy, &error)) << error;
      const Vec3 p{0.5f, 0.25f, 0.f};
      for (int j = 0; j < int(s.lights.count()); ++j)
        EXPECT_EQ(single.pmf(single.site(p), j), single.lookup(p).discrete_pdf(j)) << strategy;
    }
  }
}

}  // namespace
}  // namespace rt
