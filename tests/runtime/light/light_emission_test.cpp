// Emission sampling (sample_le / pdf_le) for every kind of light: the pdfs a
// sample reports agree with pdf_le under pbrt-v3's conventions, the rays start
// on the light (or outside the world sphere, pointing in), and Le |cos| /
// (pdf_pos pdf_dir) averages to the light's power, which is what makes light
// subpaths carry the right energy.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "light_test_scene.h"

namespace rt {
namespace {

constexpr float kTime = 0.25f;

struct EmissionStats {
  Rgb power;               // mean of Le |cos(n_light, d)| / (pdf_pos pdf_dir)
  int pdf_mismatches = 0;  // pdf_le disagreeing with the sample's pdfs
  int not_finite = 0;      // NaN or infinite radiance, pdfs or rays
  int wrong_time = 0;
  int no_sample = 0;  // zero pdfs
};

bool close(float a, float b) {
  return std::fabs(a - b) <= 1e-3f * std::fabs(b) + 1e-7f;
}

// Draws n sample_le rays from `light`, hands each with its normal to
// check_ray, and compares its pdfs with pdf_le's. pbrt-v3's conventions:
// delta positions sample pdf_pos 1 but pdf_le gives 0; a distant light
// samples pdf_dir 1 but pdf_le gives 0. Within a degree of `pole` (an
// environment map's poles) acos cannot give sin(theta) to 1e-3: skipped there.
EmissionStats sample_emission(const LightSet& lights, uint32_t light, int n, uint64_t seed,
                              const std::function<void(const Ray&, Vec3, Rgb)>& check_ray,
                              Vec3 pole = Vec3{}) {
  Rng rng(seed);
  LightKind kind = lights.kind(light);
  bool delta_position = kind == LightKind::kPoint || kind == LightKind::kSpot ||
                        kind == LightKind::kProjection || kind == LightKind::kGoniometric;
  EmissionStats st;
  double sum[3] = {0, 0, 0};
  for (int i = 0; i < n; ++i) {
    Vec2 u1{rng.next_float(), rng.next_float()}, u2{rng.next_float(), rng.next_float()};
    Ray ray;
    Vec3 n_light;
    float pdf_pos = -1, pdf_dir = -1;
    Rgb le = lights.sample_le(light, u1, u2, kTime, &ray, &n_light, &pdf_pos, &pdf_dir);
    if (!le.is_finite() || !std::isfinite(pdf_pos) || !std::isfinite(pdf_dir) || ray.o.has_nan() ||
        ray.d.has_nan() || n_light.has_nan() || le.r < 0 || pdf_pos < 0 || pdf_dir < 0) {
      ++st.not_finite;
      continue;
    }
    if (pdf_pos == 0 || pdf_dir == 0) {
      ++st.no_sample;
      continue;
    }
    if (ray.time != kTime) ++st.wrong_time;
    check_ray(ray, n_light, le);

    float le_pos = -1, le_dir = -1;
    lights.pdf_le(light, ray, n_light, &le_pos, &le_dir);
    float want_pos = delta_position ? 0 : pdf_pos;
    float want_dir = kind == LightKind::kDistant ? 0 : pdf_dir;
    bool near_pole = std::fabs(dot(ray.d, pole)) > 0.9998f;
    if (!near_pole && (!close(le_pos, want_pos) || !close(le_dir, want_dir))) ++st.pdf_mismatches;

    float c = abs_dot(n_light, ray.d) / (pdf_pos * pdf_dir);
    for (int k = 0; k < 3; ++k) sum[k] += le[k] * c;
  }
  st.power = Rgb(float(sum[0] / n), float(sum[1] / n), float(sum[2] / n));
  return st;
}

void expect_rgb_near(Rgb got, Rgb want, float rel, const char* what) {
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(got[k], want[k], rel * std::fabs(want[k]) + 1e-6f) << what << " channel " << k;
}

void expect_clean(const EmissionStats& st) {
  EXPECT_EQ(st.not_finite, 0);
  EXPECT_EQ(st.pdf_mismatches, 0);
  EXPECT_EQ(st.wrong_time, 0);
}

// Delta-position lights: every ray starts at the light, with n_light along it.
std::function<void(const Ray&, Vec3, Rgb)> from_point(Vec3 p, int* bad) {
  return [p, bad](const Ray& ray, Vec3 n, Rgb) {
    if (length(ray.o - p) > 1e-5f || length(n - ray.d) > 1e-6f ||
        std::fabs(length(ray.d) - 1) > 1e-5f)
      ++*bad;
  };
}

TEST(LightEmission, PointAndGoniometricEmitTheirIntensityOverTheSphere) {
  LightScene s;
  ASSERT_TRUE(load_light_scene("emission_point", R"(
AttributeBegin
  Translate 1 2 3
  LightSource "point" "rgb I" [2 4 8] "rgb scale" [0.5 0.5 0.25] "point from" [0 0 1]
AttributeEnd
LightSource "goniometric" "rgb I" [2 1 3]
)",
                               box({-5, -5, -5}, {5, 5, 5}), &s));
  ASSERT_EQ(s.lights.count(), 2u);
  const Vec3 where[2] = {{1, 2, 4}, {0, 0, 0}};
  for (uint32_t light = 0; light < 2; ++light) {
    int bad = 0;
    EmissionStats st =
        sample_emission(s.lights, light, 20000, 11 + light, from_point(where[light], &bad));
    expect_clean(st);
    EXPECT_EQ(st.no_sample, 0);
    EXPECT_EQ(bad, 0);
    expect_rgb_near(st.power, s.lights.power(light), 1e-3f, "power");
  }
  // The sample's own pdfs: the position is a delta, the direction uniform.
  Ray ray;
  Vec3 n;
  float pdf_pos = 0, pdf_dir = 0;
  Rgb le = s.lights.sample_le(0, {0.3f, 0.6f}, {0.1f, 0.9f}, kTime, &ray, &n, &pdf_pos, &pdf_dir);
  EXPECT_EQ(le, Rgb(1, 2, 2));
  EXPECT_EQ(pdf_pos, 1.f);
  EXPECT_FLOAT_EQ(pdf_dir, 1 / (4 * kPi));
}

TEST(LightEmission, SpotSamplesItsConeAndNothingOutside) {
  LightScene s;
  // Aimed along +x by the CTM (the default spot shines along +z); the second
  // one has a falloff ring from 20 to 30 degrees.
  ASSERT_TRUE(load_light_scene("emission_spot", R"(
AttributeBegin
  Translate 0 1 0
  Rotate 90 0 1 0
  LightSource "spot" "rgb I" [1 2 3] "float coneangle" 30 "float conedeltaangle" 0
AttributeEnd
LightSource "spot" "rgb I" [10 10 10] "point from" [0 0 5] "point to" [0 0 0]
  "float coneangle" 30 "float conedeltaangle" 10
)",
                               box({-5, -5, -5}, {5, 5, 5}), &s));
  ASSERT_EQ(s.lights.count(), 2u);
  float c0 = std::cos(radians(30.f)), c1 = std::cos(radians(20.f));
  const Vec3 where[2] = {{0, 1, 0}, {0, 0, 5}}, axis[2] = {{1, 0, 0}, {0, 0, -1}};
  for (uint32_t light = 0; light < 2; ++light) {
    int bad = 0, outside = 0;
    auto point_check = from_point(where[light], &bad);
    EmissionStats st =
        sample_emission(s.lights, light, 50000, 21 + light, [&](const Ray& ray, Vec3 n, Rgb le) {
          point_check(ray, n, le);
          if (dot(ray.d, axis[light]) < c0 - 1e-5f) ++outside;
        });
    expect_clean(st);
    EXPECT_EQ(bad, 0);
    EXPECT_EQ(outside, 0);
    if (light == 0) {
      // No falloff ring: pbrt-v3's Power is exact, I 2 pi (1 - cos 30).
      expect_rgb_near(st.power, s.lights.power(0), 1e-3f, "spot power");
    } else {
      // The ring's (d^4 ramp in cos) exact integral is (c1 - c0) / 5 where
      // pbrt-v3's Power approximates it by (c1 - c0) / 2.
      float exact = 10 * 2 * kPi * ((1 - c1) + (c1 - c0) / 5);
      expect_rgb_near(st.power, Rgb(exact), 0.01f, "spot power with falloff");
      EXPECT_GT(s.lights.power(1).r, st.power.r);
    }
  }
  // pdf_le: the cone pdf within 30 degrees of the axis, 0 beyond and behind.
  auto pdf_dir_at = [&](float deg) {
    Ray ray;
    ray.o = {0, 1, 0};
    ray.d = {std::cos(radians(deg)), 0, std::sin(radians(deg))};
    float pdf_pos = -1, pdf_dir = -1;
    s.lights.pdf_le(0, ray, Vec3{}, &pdf_pos, &pdf_dir);
    EXPECT_EQ(pdf_pos, 0.f);
    return pdf_dir;
  };
  EXPECT_FLOAT_EQ(pdf_dir_at(0), uniform_cone_pdf(c0));
  EXPECT_FLOAT_EQ(pdf_dir_at(29), uniform_cone_pdf(c0));
  EXPECT_EQ(pdf_dir_at(31), 0.f);
  EXPECT_EQ(pdf_dir_at(90), 0.f);
  EXPECT_EQ(pdf_dir_at(180), 0.f);
}

TEST(LightEmission, ProjectionSamplesTheConeAroundItsScreen) {
  LightScene s;
  ASSERT_TRUE(load_light_scene("emission_projection", R"(
AttributeBegin
  Translate 0.5 0 0
  LightSource "projection" "rgb I" [4 2 1] "float fov" 45
AttributeEnd
)",
                               box({-5, -5, -5}, {5, 5, 5}), &s));
  ASSERT_EQ(s.lights.count(), 1u);
  // A square screen of half-angle 22.5 degrees; pbrt-v3's cone goes through
  // its corners: tan(half angle) = tan(22.5) sqrt(2).
  float half = radians(22.5f);
  float cos_total = std::cos(std::atan(std::tan(half) * std::sqrt(2.f)));
  int bad = 0, outside = 0, lit_outside_screen = 0;
  auto point_check = from_point({0.5f, 0, 0}, &bad);
  EmissionStats st = sample_emission(s.lights, 0, 100000, 31, [&](const Ray& ray, Vec3 n, Rgb le) {
    point_check(ray, n, le);
    if (ray.d.z < cos_total - 1e-5f) ++outside;
    bool in_screen = std::fabs(ray.d.x / ray.d.z) <= std::tan(half) * (1 + 1e-4f) &&
                     std::fabs(ray.d.y / ray.d.z) <= std::tan(half) * (1 + 1e-4f);
    if (!in_screen && !le.is_black()) ++lit_outside_screen;
  });
  expect_clean(st);
  EXPECT_EQ(bad, 0);
  EXPECT_EQ(outside, 0);
  EXPECT_EQ(lit_outside_screen, 0);
  // The light reaches only the screen's pyramid, of solid angle
  // 4 asin(sin^2 22.5); pbrt-v3's Power counts the whole circumscribing cone.
  float pyramid = 4 * std::asin(std::sin(half) * std::sin(half));
  expect_rgb_near(st.power, Rgb(4, 2, 1) * pyramid, 0.01f, "projection power");
  expect_rgb_near(s.lights.power(0), Rgb(4, 2, 1) * (2 * kPi * (1 - cos_total)), 1e-4f,
                  "pbrt-v3 power");
  // pdf_le: the cone pdf inside the cone (even off the screen), 0 outside.
  auto pdf_dir_at = [&](float deg) {
    Ray ray;
    ray.o = {0.5f, 0, 0};
    ray.d = {std::sin(radians(deg)), 0, std::cos(radians(deg))};
    float pdf_pos = -1, pdf_dir = -1;
    s.lights.pdf_le(0, ray, Vec3{}, &pdf_pos, &pdf_dir);
    EXPECT_EQ(pdf_pos, 0.f);
    return pdf_dir;
  };
  EXPECT_FLOAT_EQ(pdf_dir_at(10), uniform_cone_pdf(cos_total));
  EXPECT_FLOAT_EQ(pdf_dir_at(25), uniform_cone_pdf(cos_total));  // off the screen, in the cone
  EXPECT_EQ(pdf_dir_at(32), 0.f);
  EXPECT_EQ(pdf_dir_at(180), 0.f);
}

// Distant and infinite lights: rays start outside the world sphere, head
// into it and cross the disk of its radius.
std::function<void(const Ray&, Vec3, Rgb)> into_world(Vec3 c, float r, int* bad) {
  return [c, r, bad](const Ray& ray, Vec3 n, Rgb) {
    Vec3 to_c = c - ray.o;
    float along = dot(to_c, ray.d);
    float miss = length(to_c - along * ray.d);  // the ray's distance from the centre
    if (length(to_c) < r * (1 - 1e-5f) || along <= 0 || miss > r * (1 + 1e-4f) ||
        length(n - ray.d) > 1e-6f || std::fabs(length(ray.d) - 1) > 1e-5f)
      ++*bad;
  };
}

TEST(LightEmission, DistantLightRaysCrossTheWorldDisk) {
  LightScene s;
  Bounds3 world = box({-1, 0, -2}, {3, 2, 1});
  ASSERT_TRUE(load_light_scene("emission_distant", R"(
AttributeBegin
  Rotate 90 0 0 1
  LightSource "distant" "point from" [0 0 0] "point to" [1 0 0] "rgb L" [1 2 3]
AttributeEnd
)",
                               world, &s));
  ASSERT_EQ(s.lights.count(), 1u);
  Vec3 c;
  float r = 0;
  world.bounding_sphere(&c, &r);
  int bad = 0, wrong_dir = 0;
  auto world_check = into_world(c, r, &bad);
  EmissionStats st = sample_emission(s.lights, 0, 20000, 41, [&](const Ray& ray, Vec3 n, Rgb le) {
    world_check(ray, n, le);
    // from - to = -x, turned to -y: the light travels along +y.
    if (length(ray.d - Vec3{0, 1, 0}) > 1e-6f) ++wrong_dir;
  });
  expect_clean(st);
  EXPECT_EQ(bad, 0);
  EXPECT_EQ(wrong_dir, 0);
  // pbrt-v3's Power is L pi r^2, the flux through the disk: the estimate's too.
  expect_rgb_near(st.power, s.lights.power(0), 1e-3f, "distant power");
  expect_rgb_near(st.power, Rgb(1, 2, 3) * (kPi * r * r), 1e-3f, "L pi r^2");
}

TEST(LightEmission, ConstantInfiniteLightRaysComeFromEverywhere) {
  LightScene s;
  Bounds3 world = box({-1, -1, -1}, {1, 1, 1});
  ASSERT_TRUE(load_light_scene("emission_infinite", R"(
LightSource "infinite" "rgb L" [0.5 1 2] "rgb scale" [2 2 2]
)",
                               world, &s));
  ASSERT_EQ(s.lights.count(), 1u);
  Vec3 c;
  float r = 0;
  world.bounding_sphere(&c, &r);
  int bad = 0;
  EmissionStats st =
      sample_emission(s.lights, 0, 100000, 51, into_world(c, r, &bad), Vec3{0, 0, 1});
  expect_clean(st);
  EXPECT_EQ(bad, 0);
  // Flux through the disk from every direction: L pi r^2 times 4 pi.
  // pbrt-v3's Power is L pi r^2 alone (it leaves out the sphere of
  // directions), so the estimate is 4 pi times power().
  expect_rgb_near(st.power, Rgb(1, 2, 4) * (kPi * r * r * 4 * kPi), 0.01f, "infinite flux");
  expect_rgb_near(st.power, s.lights.power(0) * (4 * kPi), 0.01f, "4 pi power()");
}

TEST(LightEmission, EnvironmentMapRaysFollowTheMap) {
  LightScene s;
  s.dir = testing_support::scratch_dir("emission_envmap");
  // 16 x 8, a gradient and a bright patch near the top (as infinite_light_test).
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
  write_pfm(s.dir + "/env.pfm", w, h, rgb.data());
  Bounds3 world = box({-1, -2, -1}, {1, 1, 2});
  ASSERT_TRUE(load_light_scene("emission_envmap", R"(
AttributeBegin
  Rotate -90 1 0 0
  Rotate 30 0 0 1
  LightSource "infinite" "string mapname" "env.pfm" "rgb L" [1 0.5 2] "rgb scale" [1.5 1.5 1.5]
AttributeEnd
)",
                               world, &s));
  ASSERT_EQ(s.lights.count(), 1u);
  Vec3 c;
  float r = 0;
  world.bounding_sphere(&c, &r);
  int bad = 0, le_mismatch = 0;
  auto world_check = into_world(c, r, &bad);
  // The map's pole (light +z) is world +y here.
  EmissionStats st = sample_emission(
      s.lights, 0, 100000, 61,
      [&](const Ray& ray, Vec3 n, Rgb le) {
        world_check(ray, n, le);
        // The radiance carried is what a camera ray looking back sees.
        RayDifferential back;
        back.d = -ray.d;
        Rgb env = s.lights.infinite_le(back);
        if (!(std::fabs(env.g - le.g) <= 1e-3f * le.g + 1e-6f)) ++le_mismatch;
      },
      Vec3{0, 1, 0});
  expect_clean(st);
  EXPECT_EQ(bad, 0);
  EXPECT_LE(le_mismatch, 5);  // a sample on a texel boundary may round to the neighbour
  // The flux: pi r^2 times the integral of L over the sphere, by quadrature.
  const int nz = 400, nphi = 800;
  Rng rng(62);
  Rgb sum;
  for (int i = 0; i < nz; ++i)
    for (int j = 0; j < nphi; ++j) {
      RayDifferential ray;
      ray.d = uniform_sample_sphere({(i + rng.next_float()) / nz, (j + rng.next_float()) / nphi});
      sum += s.lights.infinite_le(ray) / uniform_sphere_pdf();
    }
  Rgb flux = sum / float(nz * nphi) * (kPi * r * r);
  expect_rgb_near(st.power, flux, 0.02f, "environment flux");
}

TEST(LightEmission, AreaLightsStartOnTheirSurfaceAndCarryTheirPower) {
  LightScene s;
  ASSERT_TRUE(load_light_scene("emission_area", R"(
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [1 2 3]
  Translate 0 0 2
  Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
    "point P" [-1 -1 0  1 -1 0  1 1 0  -1 1 0]
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [2 2 2] "bool twosided" "true"
  Translate 1 1 -1
  Shape "sphere" "float radius" 0.5
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [3 1 1]
  Translate 0 0 3
  ReverseOrientation
  Shape "disk" "float radius" 1.5
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [0.5 0.5 1]
  Translate -2 0 0
  Shape "cylinder" "float radius" 0.3 "float zmin" -0.5 "float zmax" 0.5
AttributeEnd
)",
                               box({-3, -3, -3}, {3, 3, 4}), &s));
  ASSERT_EQ(s.lights.count(), 5u);
  // Per light: is the point on the surface, and is n_light its normal there
  // (pointing the way sample_li's normals point)?
  auto on_surface = [](uint32_t light, Vec3 p, Vec3 n) {
    switch (light) {
      case 0:
      case 1:  // the quad's triangles, counter-clockwise seen from +z: normal +z
        return std::fabs(p.z - 2) < 1e-5f && std::fabs(p.x) <= 1 + 1e-5f &&
               std::fabs(p.y) <= 1 + 1e-5f && length(n - Vec3{0, 0, 1}) < 1e-5f;
      case 2: {  // the sphere, normal outwards
        Vec3 d = p - Vec3{1, 1, -1};
        return std::fabs(length(d) - 0.5f) < 1e-5f && length(n - d / 0.5f) < 1e-4f;
      }
      case 3:  // the disk, turned over by ReverseOrientation: normal -z
        return std::fabs(p.z - 3) < 1e-5f && p.x * p.x + p.y * p.y <= 1.5f * 1.5f + 1e-4f &&
               length(n - Vec3{0, 0, -1}) < 1e-5f;
      default: {  // the cylinder, normal outwards
        Vec3 d = p - Vec3{-2, 0, 0};
        Vec3 radial{d.x, d.y, 0};
        return std::fabs(length(radial) - 0.3f) < 1e-5f && std::fabs(d.z) <= 0.5f + 1e-5f &&
               length(n - radial / 0.3f) < 1e-4f;
      }
    }
  };
  for (uint32_t light = 0; light < s.lights.count(); ++light) {
    SCOPED_TRACE(light);
    EXPECT_EQ(s.lights.kind(light), LightKind::kArea);
    int off_surface = 0, front = 0, back = 0, unlit = 0;
    const int n = 50000;
    EmissionStats st =
        sample_emission(s.lights, light, n, 71 + light, [&](const Ray& ray, Vec3 nl, Rgb le) {
          // The origin is pushed off the surface by its error bound only.
          if (!on_surface(light, ray.o, nl)) ++off_surface;
          (dot(ray.d, nl) >= 0 ? front : back)++;
          if (le.is_black()) ++unlit;
        });
    expect_clean(st);
    EXPECT_EQ(off_surface, 0);
    EXPECT_EQ(unlit, 0);
    // Cosine-weighted directions make Le cos / (pdf_pos pdf_dir) constant:
    // L A pi per lit side, pbrt-v3's Power.
    expect_rgb_near(st.power, s.lights.power(light), 1e-3f, "area power");
    if (light == 2) {
      EXPECT_NEAR(back, n / 2, n / 50);  // two-sided: half the rays leave inwards
    } else {
      EXPECT_EQ(back, 0);
    }
  }
  // n_light follows sample_li's orientation: from below, the reversed disk
  // faces the reference point and its sampled normal is -z too.
  LightSample ls;
  s.lights.sample_li(3, surface_point({0.2f, 0.1f, 0}, {0, 0, 1}), {0.4f, 0.7f}, &ls);
  EXPECT_GT(ls.pdf, 0);
  EXPECT_NEAR(ls.p_light.n.z, -1, 1e-6);

  // Two-sided: u2.x below one half picks the front, above it the back; the
  // pdf halves for the choice, and the normal never flips.
  Ray ray;
  Vec3 nl;
  float pdf_pos = 0, pdf_dir = 0;
  s.lights.sample_le(2, {0.3f, 0.3f}, {0.25f, 0.4f}, kTime, &ray, &nl, &pdf_pos, &pdf_dir);
  EXPECT_GT(dot(ray.d, nl), 0);
  EXPECT_FLOAT_EQ(pdf_dir, 0.5f * dot(ray.d, nl) / kPi);
  s.lights.sample_le(2, {0.3f, 0.3f}, {0.75f, 0.4f}, kTime, &ray, &nl, &pdf_pos, &pdf_dir);
  EXPECT_LT(dot(ray.d, nl), 0);
  EXPECT_FLOAT_EQ(pdf_dir, 0.5f * -dot(ray.d, nl) / kPi);
  EXPECT_FLOAT_EQ(pdf_pos, 1 / (4 * kPi * 0.25f));
  // One-sided: no density behind the light.
  ray.o = {0, 0, 2};
  ray.d = {0, 0, -1};
  s.lights.pdf_le(0, ray, Vec3{0, 0, 1}, &pdf_pos, &pdf_dir);
  EXPECT_EQ(pdf_dir, 0.f);
  EXPECT_FLOAT_EQ(pdf_pos, 1 / 2.f);  // each triangle of the 2 x 2 quad has area 2
}

}  // namespace
}  // namespace rt
