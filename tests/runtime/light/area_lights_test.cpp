// Diffuse area lights on disks, spheres and triangles: sample_li's pdf agrees
// with pdf_li, and the irradiance it estimates matches closed forms and a
// brute-force hemisphere integral; emission is one-sided unless twosided.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "light_test_scene.h"

namespace rt {
namespace {

// Lambert's formula: the irradiance at p (normal n) from a polygon of
// constant radiance L lying wholly above p's horizon.
float polygon_irradiance(Vec3 p, Vec3 n, const Vec3* v, int count, float l) {
  float sum = 0;
  for (int i = 0; i < count; ++i) {
    Vec3 a = normalize(v[i] - p), b = normalize(v[(i + 1) % count] - p);
    float angle = std::acos(clamp(dot(a, b), -1.f, 1.f));
    sum += angle * dot(n, normalize(cross(a, b)));
  }
  return std::fabs(sum) * l / 2;
}

// Moller-Trumbore: the distance along d to triangle abc, or infinity.
float hit_triangle(Vec3 o, Vec3 d, Vec3 a, Vec3 b, Vec3 c) {
  Vec3 e1 = b - a, e2 = c - a, pv = cross(d, e2);
  float det = dot(e1, pv);
  if (std::fabs(det) < 1e-12f) return kInfinity;
  Vec3 tv = o - a;
  float u = dot(tv, pv) / det;
  if (u < 0 || u > 1) return kInfinity;
  Vec3 qv = cross(tv, e1);
  float v = dot(d, qv) / det;
  if (v < 0 || u + v > 1) return kInfinity;
  float t = dot(e2, qv) / det;
  return t > 0 ? t : kInfinity;
}

TEST(AreaLights, DiskOnAxisMatchesClosedFormAndIsOneSided) {
  LightScene s;
  ASSERT_TRUE(load_light_scene("disk_light", R"(
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [2 1 0.5] "integer nsamples" 4
  Translate 0 0 3
  ReverseOrientation
  Shape "disk" "float radius" 1.5
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [1 1 1] "bool twosided" "true"
  Translate 0 0 -3
  Shape "disk" "float radius" 1.5
AttributeEnd
)",
                               box({-2, -2, -4}, {2, 2, 4}), &s));
  ASSERT_EQ(s.lights.count(), 2u);
  EXPECT_EQ(s.lights.kind(0), LightKind::kArea);
  EXPECT_FALSE(s.lights.is_delta(0));
  EXPECT_EQ(s.lights.nsamples(0), 4);
  EXPECT_EQ(s.lights.nsamples(1), 1);

  float r2 = 1.5f * 1.5f, d2 = 9, expected = kPi * r2 / (r2 + d2);
  int mismatches = 0;
  Rgb e =
      estimate_irradiance(s.lights, 0, surface_point({0, 0, 0}, {0, 0, 1}), 40000, 7, &mismatches);
  EXPECT_EQ(mismatches, 0);
  EXPECT_NEAR(e.r, 2 * expected, 0.01 * 2 * expected);
  EXPECT_NEAR(e.b, 0.5 * expected, 0.01 * 0.5 * expected);
  // Above it, the first disk shows its back: nothing.
  Rgb back = estimate_irradiance(s.lights, 0, surface_point({0, 0, 6}, {0, 0, -1}), 1000, 8);
  EXPECT_EQ(back, Rgb(0));
  // The twosided disk lights both sides alike.
  Rgb below = estimate_irradiance(s.lights, 1, surface_point({0, 0, -6}, {0, 0, 1}), 40000, 9);
  Rgb above = estimate_irradiance(s.lights, 1, surface_point({0, 0, 0}, {0, 0, -1}), 40000, 10);
  EXPECT_NEAR(below.g, expected, 0.01 * expected);
  EXPECT_NEAR(above.g, expected, 0.01 * expected);
  // Power: L * area * pi, twice for two sides.
  EXPECT_NEAR(s.lights.power(0).r, 2 * kPi * r2 * kPi, 1e-3);
  EXPECT_NEAR(s.lights.power(1).r, 2 * kPi * r2 * kPi, 1e-3);
}

TEST(AreaLights, SphereSeenFromOutsideAndInside) {
  LightScene s;
  ASSERT_TRUE(load_light_scene("sphere_light", R"(
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [1 3 5]
  Translate 0 0 4
  Shape "sphere" "float radius" 1
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [1 1 1]
  ReverseOrientation
  Shape "sphere" "float radius" 2
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [1 1 1]
  Shape "sphere" "float radius" 2
AttributeEnd
)",
                               box({-2, -2, -2}, {2, 2, 5}), &s));
  ASSERT_EQ(s.lights.count(), 3u);
  // Outside: a sphere of radius R at distance d on the normal gives pi L (R/d)^2.
  int mismatches = 0;
  Rgb e =
      estimate_irradiance(s.lights, 0, surface_point({0, 0, 0}, {0, 0, 1}), 20000, 11, &mismatches);
  EXPECT_EQ(mismatches, 0);
  EXPECT_NEAR(e.b, 5 * kPi / 16, 0.01 * 5 * kPi / 16);
  // Inside a sphere emitting inwards every direction sees it: pi L.
  Interaction inside = surface_point({0.3f, 0.2f, -0.5f}, {1, 1, 1});
  e = estimate_irradiance(s.lights, 1, inside, 80000, 12, &mismatches);
  EXPECT_EQ(mismatches, 0);
  EXPECT_NEAR(e.r, kPi, 0.02 * kPi);
  // The outward-facing sphere is dark inside.
  EXPECT_EQ(estimate_irradiance(s.lights, 2, inside, 1000, 13), Rgb(0));
}

TEST(AreaLights, TrianglesMatchLambertAndBruteForce) {
  LightScene s;
  // A 3 x 3 square at z = 2 facing down, as two triangles: one light each.
  ASSERT_TRUE(load_light_scene("triangle_light", R"(
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [4 4 4]
  Shape "trianglemesh" "integer indices" [0 2 1 0 3 2]
    "point P" [-1 -1 2  2 -1 2  2 2 2  -1 2 2]
AttributeEnd
)",
                               box({-1, -1, 0}, {2, 2, 2}), &s));
  ASSERT_EQ(s.lights.count(), 2u);
  Vec3 v[4] = {{-1, -1, 2}, {2, -1, 2}, {2, 2, 2}, {-1, 2, 2}};
  Vec3 tri[2][3] = {{v[0], v[2], v[1]}, {v[0], v[3], v[2]}};
  Interaction ref = surface_point({0.3f, 0.2f, 0}, {0.2f, 0, 1});
  for (int t = 0; t < 2; ++t) {
    int mismatches = 0;
    Rgb e = estimate_irradiance(s.lights, t, ref, 40000, 20 + t, &mismatches);
    EXPECT_EQ(mismatches, 0);
    float lambert = polygon_irradiance(ref.p, ref.n, tri[t], 3, 4);
    EXPECT_NEAR(e.r, lambert, 0.01 * lambert) << "triangle " << t;
    EXPECT_NEAR(s.lights.power(t).r, 4 * 4.5f * kPi, 1e-3);
  }
  // Brute force: uniform directions over the hemisphere, rays against both triangles.
  Vec3 t1, t2;
  coordinate_system(ref.n, &t1, &t2);
  Rng rng(99);
  double sum = 0;
  const int n = 400000;
  for (int i = 0; i < n; ++i) {
    Vec3 l = uniform_sample_hemisphere({rng.next_float(), rng.next_float()});
    Vec3 d = t1 * l.x + t2 * l.y + ref.n * l.z;
    for (auto& tr : tri)
      if (hit_triangle(ref.p, d, tr[0], tr[1], tr[2]) < kInfinity && d.z > 0) sum += 4 * l.z;
  }
  float brute = float(sum / n / uniform_hemisphere_pdf());
  Rgb both = estimate_irradiance(s.lights, 0, ref, 40000, 30) +
             estimate_irradiance(s.lights, 1, ref, 40000, 31);
  EXPECT_NEAR(both.g, brute, 0.02 * brute);
  EXPECT_NEAR(brute, polygon_irradiance(ref.p, ref.n, v, 4, 4), 0.02 * brute);
}

TEST(AreaLights, EmissionAtHitsIsOneSidedAndPerTriangle) {
  LightScene s;
  ASSERT_TRUE(load_light_scene("area_le", R"(
LightSource "point" "rgb I" [1 1 1]
Shape "sphere"
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [4 5 6]
  Shape "trianglemesh" "integer indices" [0 2 1 0 3 2]
    "point P" [-1 -1 2  2 -1 2  2 2 2  -1 2 2]
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [1 1 1] "bool twosided" "true"
  Shape "disk"
AttributeEnd
)",
                               box({-1, -1, -1}, {2, 2, 2}), &s));
  ASSERT_EQ(s.lights.count(), 4u);  // the point light, two triangles, the disk
  SurfaceInteraction hit;
  hit.shape = 1;
  hit.prim = 1;
  hit.n = {0, 0, -1};
  EXPECT_EQ(s.lights.area_light_at(hit), 2u);
  EXPECT_EQ(s.lights.area_le(hit, {0, 0, -1}), Rgb(4, 5, 6));
  EXPECT_EQ(s.lights.area_le(hit, {0, 0, 1}), Rgb(0));
  hit.prim = 0;
  EXPECT_EQ(s.lights.area_light_at(hit), 1u);
  hit.shape = 2;
  hit.prim = 0;
  EXPECT_EQ(s.lights.area_light_at(hit), 3u);
  EXPECT_EQ(s.lights.area_le(hit, {0, 0, -1}), Rgb(1));
  EXPECT_EQ(s.lights.area_le(hit, {0, 0, 1}), Rgb(1));
  hit.shape = 0;  // the plain sphere emits nothing
  EXPECT_EQ(s.lights.area_light_at(hit), kNone);
  EXPECT_EQ(s.lights.area_le(hit, {0, 0, 1}), Rgb(0));
  EXPECT_FALSE(s.lights.has_infinite());
  // Without the traced hit an area light's pdf is unknown: 0.
  EXPECT_EQ(s.lights.pdf_li(1, surface_point({0, 0, 0}, {0, 0, 1}), {0, 0, 1}, nullptr), 0.f);
}

TEST(AreaLights, ShapesPbrtCannotSampleAreNotSupported) {
  for (const char* shape : {"cone", "paraboloid", "hyperboloid"}) {
    LightScene s;
    s.dir = testing_support::scratch_dir(std::string("area_") + shape);
    ASSERT_TRUE(testing_support::compile_text(
        s.dir,
        light_scene_text(std::string("AreaLightSource \"diffuse\"\nShape \"") + shape + "\"\n"),
        &s.archive));
    std::string error;
    ASSERT_TRUE(s.shapes.build(s.archive, &error)) << error;
    EXPECT_FALSE(s.lights.build(s.archive, s.shapes, box({-1, -1, -1}, {1, 1, 1}), &error));
    EXPECT_NE(error.find(std::string("not supported yet: area light on a ") + shape + " ("),
              std::string::npos)
        << error;
    EXPECT_NE(error.find("scene.pbrt:4"), std::string::npos) << error;
  }
}

}  // namespace
}  // namespace rt

namespace rt {
namespace {

bool same_bits(const void* a, const void* b, size_t n) {
  return std::memcmp(a, b, n) == 0;
}

// The light grid samples a triangle light's point once per sample value
// (LightSet::triangle_point) and finishes each voxel's sample from it: that must be sample_li,
// bit for bit, from every reference point (the point may not depend on ref); other lights
// have no such point; triangle_point_weight is the sample's luminance over its pdf. (The
// irradiance tests above check sample_li itself.)
TEST(AreaLights, TrianglePointThenLiIsSampleLi) {
  LightScene s;
  ASSERT_TRUE(load_light_scene("area_triangle_point", R"(
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [4 3 2]
  Shape "trianglemesh" "integer indices" [0 1 2  0 2 3]
    "point P" [-1 -1 3  1 -1 3  1 1 3.2  -1 1 3] "normal N" [0 0 -1  0 0.1 -1  0 0 -1  0.1 0 -1]
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [1 1 1] "bool twosided" "true"
  ReverseOrientation
  Shape "trianglemesh" "integer indices" [0 1 2] "point P" [3 0 0  3 1 0  3 0 1]
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [1 1 1]
  Translate 0 -3 0
  Shape "sphere" "float radius" 0.5
AttributeEnd
LightSource "point" "rgb I" [1 1 1] "point from" [0 0 5]
)",
                               box({-4, -4, -4}, {4, 4, 4}), &s));
  ASSERT_EQ(s.lights.count(), 5u);
  Rng rng(9);
  int compared = 0, triangle_lights = 0;
  for (uint32_t light = 0; light < s.lights.count(); ++light) {
    Interaction unused;
    float unused_pdf;
    triangle_lights += s.lights.triangle_point(light, {0.5f, 0.5f}, &unused, &unused_pdf);
  }
  EXPECT_EQ(triangle_lights, 3);  // not the sphere, not the point light
  for (uint32_t light = 0; light < s.lights.count(); ++light)
    for (int i = 0; i < 100; ++i) {
      // One point per sample value, used from many reference points, as the grid uses it.
      const Vec2 u{rng.next_float(), rng.next_float()};
      Interaction it;
      float pdf_area = 0;
      if (!s.lights.triangle_point(light, u, &it, &pdf_area)) continue;
      for (int r = 0; r < 5; ++r) {
        Interaction ref;
        ref.p = {6 * rng.next_float() - 3, 6 * rng.next_float() - 3, 6 * rng.next_float() - 3};
        ref.wo = {1, 0, 0};
        LightSample a, b;
        const Rgb la = s.lights.sample_li(light, ref, u, &a);
        const Rgb lb = s.lights.li_at_triangle_point(light, ref, it, pdf_area, &b);
        ASSERT_TRUE(same_bits(&la, &lb, sizeof la)) << light << " " << i;
        ASSERT_TRUE(same_bits(&a.pdf, &b.pdf, sizeof a.pdf));
        ASSERT_TRUE(same_bits(&a.wi, &b.wi, sizeof a.wi));
        ASSERT_TRUE(same_bits(&a.p_light.p, &b.p_light.p, sizeof a.p_light.p));
        ASSERT_TRUE(same_bits(&a.p_light.n, &b.p_light.n, sizeof a.p_light.n));
        ASSERT_EQ(a.own_shape, b.own_shape);
        // What the grid adds for this sample: the same value, 0 without a sample.
        const float weight = a.pdf > 0 ? la.luminance() / a.pdf : 0.f;
        const float grid = s.lights.triangle_point_weight(light, ref.p, it, pdf_area);
        ASSERT_TRUE(same_bits(&weight, &grid, sizeof grid)) << weight << " " << grid;
        compared += a.pdf > 0;
      }
    }
  EXPECT_GT(compared, 1000);  // both sides of the one-sided lights were reached
}

}  // namespace
}  // namespace rt
