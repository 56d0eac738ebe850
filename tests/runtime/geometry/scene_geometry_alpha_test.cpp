// Alpha cut-outs: hits where alpha (or, for shadow rays, shadowalpha) is
// exactly 0 are skipped, as pbrt-v3's Triangle::Intersect / IntersectP do.
#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "runtime/core/rng.h"
#include "scene_geometry_test_support.h"

namespace rt {
namespace {

// A floor at z = 0 and a unit quad at z = 1 whose alpha is a 2x2
// checkerboard: 0 in the cells (u < .5, v < .5) and (u > .5, v > .5).
const char* kCheckerQuad = R"(
Texture "cut" "float" "checkerboard" "float uscale" 2 "float vscale" 2
  "float tex1" 0 "float tex2" 1 "string aamode" "none"
Shape "trianglemesh" "integer indices" [0 1 2  0 2 3] "point P" [-10 -10 0  10 -10 0  10 10 0  -10 10 0]
)";
const char* kQuad = R"(
Shape "trianglemesh" "integer indices" [0 1 2  0 2 3] "point P" [0 0 1  1 0 1  1 1 1  0 1 1]
  "float uv" [0 0  1 0  1 1  0 1] )";

struct Probe {
  float x, y;
  bool cut;
};
const Probe kProbes[] = {{0.25f, 0.25f, true},  {0.75f, 0.25f, false}, {0.75f, 0.75f, true},
                         {0.25f, 0.75f, false}, {0.1f, 0.4f, true},    {0.6f, 0.1f, false}};

void expect_checker(const LoadedScene& s, Vec3 offset, uint32_t quad_shape) {
  for (const Probe& p : kProbes) {
    Vec3 o = offset + Vec3{p.x, p.y, 3};
    SurfaceInteraction si;
    ASSERT_TRUE(s.geometry.intersect(make_ray(o, {0, 0, -1}), &si));
    EXPECT_EQ(si.shape, p.cut ? 0u : quad_shape) << p.x << " " << p.y;
    EXPECT_NEAR(si.p.z, p.cut ? 0 : offset.z + 1, 1e-5f);
    // A shadow ray from the floor up through the quad.
    EXPECT_EQ(s.geometry.occluded(make_ray(offset + Vec3{p.x, p.y, 0.5f}, {0, 0, 1})), !p.cut)
        << p.x << " " << p.y;
  }
}

TEST(SceneGeometryAlpha, TextureCutOut) {
  auto s =
      load_world("sg_alpha_tex", std::string(kCheckerQuad) + kQuad + "\"texture alpha\" \"cut\"\n");
  ASSERT_TRUE(s->built) << s->error;
  expect_checker(*s, {0, 0, 0}, 1);
}

TEST(SceneGeometryAlpha, TextureCutOutInInstance) {
  auto s = load_world("sg_alpha_inst", std::string(kCheckerQuad) + "ObjectBegin \"q\"\n" + kQuad +
                                           "\"texture alpha\" \"cut\"\nObjectEnd\n"
                                           "Translate 5 0 0.5\nObjectInstance \"q\"\n");
  ASSERT_TRUE(s->built) << s->error;
  expect_checker(*s, {5, 0, 0.5f}, 1);
}

TEST(SceneGeometryAlpha, ConstantAlphaAndShadowAlpha) {
  const std::string floor = R"(
Shape "trianglemesh" "integer indices" [0 1 2  0 2 3] "point P" [-10 -10 0  10 -10 0  10 10 0  -10 10 0]
)";
  SurfaceInteraction si;
  Ray down = make_ray({0.5f, 0.5f, 3}, {0, 0, -1});
  Ray up = make_ray({0.5f, 0.5f, 0.5f}, {0, 0, 1});

  // alpha 0: invisible to camera and shadow rays.
  auto zero = load_world("sg_alpha_zero", floor + kQuad + "\"float alpha\" 0\n");
  ASSERT_TRUE(zero->built) << zero->error;
  ASSERT_TRUE(zero->geometry.intersect(down, &si));
  EXPECT_EQ(si.shape, 0u);
  EXPECT_FALSE(zero->geometry.occluded(up));

  // Any other constant is no mask in pbrt-v3.
  auto half = load_world("sg_alpha_half", floor + kQuad + "\"float alpha\" 0.5\n");
  ASSERT_TRUE(half->built) << half->error;
  ASSERT_TRUE(half->geometry.intersect(down, &si));
  EXPECT_EQ(si.shape, 1u);
  EXPECT_TRUE(half->geometry.occluded(up));

  // shadowalpha 0: seen by camera rays, not by shadow rays.
  auto shadow = load_world("sg_alpha_shadow", floor + kQuad + "\"float shadowalpha\" 0\n");
  ASSERT_TRUE(shadow->built) << shadow->error;
  ASSERT_TRUE(shadow->geometry.intersect(down, &si));
  EXPECT_EQ(si.shape, 1u);
  EXPECT_FALSE(shadow->geometry.occluded(up));
}

// The filters run inside Embree on the caller's thread with only stack
// state: concurrent queries give exactly the serial answers.
TEST(SceneGeometryAlpha, FiltersAreDeterministicAcrossThreads) {
  auto s = load_world("sg_alpha_threads",
                      std::string(kCheckerQuad) + kQuad + "\"texture alpha\" \"cut\"\n");
  ASSERT_TRUE(s->built) << s->error;
  const int n = 20000;
  std::vector<Ray> rays;
  Rng rng(3);
  for (int i = 0; i < n; ++i) {
    Vec3 o{rng.next_float() * 1.2f - 0.1f, rng.next_float() * 1.2f - 0.1f, 3};
    rays.push_back(make_ray(o, {0.05f * (rng.next_float() - 0.5f), 0, -1}));
  }
  auto run = [&](std::vector<float>* out) {
    out->resize(2 * n);
    for (int i = 0; i < n; ++i) {
      SurfaceInteraction si;
      (*out)[2 * i] = s->geometry.intersect(rays[i], &si) ? si.shape + 0.5f * si.uv.x : -1;
      Ray up = make_ray(rays[i].o - Vec3{0, 0, 2.5f}, {0, 0, 1});
      (*out)[2 * i + 1] = s->geometry.occluded(up);
    }
  };
  std::vector<float> serial;
  run(&serial);
  int floor = 0, quad = 0;
  for (int i = 0; i < n; ++i) (serial[2 * i] < 1 ? floor : quad)++;
  EXPECT_GT(floor, n / 4);  // around the quad, and half its area cut away
  EXPECT_GT(quad, n / 4);
  std::vector<std::vector<float>> results(4);
  std::vector<std::thread> threads;
  for (auto& r : results) threads.emplace_back(run, &r);
  for (auto& t : threads) t.join();
  for (const auto& r : results) EXPECT_TRUE(r == serial);
}

}  // namespace
}  // namespace rt
