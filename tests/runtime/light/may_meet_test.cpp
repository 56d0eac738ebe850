// LightSet::may_meet lets direct lighting skip tracing a scattering sample that cannot meet the
// light it estimates. The skip is only sound if it never says no to a ray the scene's own
// query finds on that light: these tests trace random rays (from around the light and from
// points on it, as spawned rays leave a surface) through the whole scene and check every ray
// that meets the light, for each shape an area light can have, placed near and far from the
// origin; and that the box does turn most other rays away (else the test proves nothing).
#include <gtest/gtest.h>

#include <string>

#include "light_test_scene.h"
#include "runtime/geometry/scene_geometry.h"

namespace rt {
namespace {

struct Tally {
  int met = 0;          // rays the scene found on the light
  int met_refused = 0;  // of them, rays may_meet said could not meet it
  int missed = 0;       // rays that did not meet the light
  int missed_refused = 0;
};

// n rays from random points in [lo, hi] in random directions, traced through the scene;
// every light of the scene is asked about each.
Tally trace(const std::string& name, const std::string& world, Vec3 lo, Vec3 hi, int n) {
  LightScene s;
  Tally tally;
  if (!load_light_scene(name, world, box(lo, hi), &s)) return tally;
  SceneGeometry geometry;
  if (!build_light_scene_geometry(s, &geometry)) return tally;
  Rng rng(5);
  for (int i = 0; i < n; ++i) {
    const Vec3 p{lo.x + rng.next_float() * (hi.x - lo.x), lo.y + rng.next_float() * (hi.y - lo.y),
                 lo.z + rng.next_float() * (hi.z - lo.z)};
    // Every other ray aimed at the middle third of the box, where the lights are.
    const Vec3 aim{lo.x + (1 + rng.next_float()) * (hi.x - lo.x) / 3,
                   lo.y + (1 + rng.next_float()) * (hi.y - lo.y) / 3,
                   lo.z + (1 + rng.next_float()) * (hi.z - lo.z) / 3};
    const Vec3 d =
        i % 2 ? normalize(aim - p) : uniform_sample_sphere({rng.next_float(), rng.next_float()});
    Ray ray{p, d};
    SurfaceInteraction si;
    const uint32_t hit_light = geometry.intersect(ray, &si) ? s.lights.area_light_at(si) : kNone;
    for (uint32_t light = 0; light < s.lights.count(); ++light) {
      const bool may = s.lights.may_meet(light, ray);
      if (light == hit_light) {
        ++tally.met;
        tally.met_refused += !may;
      } else {
        ++tally.missed;
        tally.missed_refused += !may;
      }
    }
    // A ray leaving the light's surface where this one met it, as a spawned ray does.
    if (hit_light == kNone) continue;
    Ray out = si.spawn_ray(uniform_sample_sphere({rng.next_float(), rng.next_float()}));
    SurfaceInteraction si2;
    if (!geometry.intersect(out, &si2) || s.lights.area_light_at(si2) == kNone) continue;
    ++tally.met;
    tally.met_refused += !s.lights.may_meet(s.lights.area_light_at(si2), out);
  }
  return tally;
}

void expect_sound_and_useful(const Tally& t, int min_met) {
  EXPECT_GE(t.met, min_met);
  EXPECT_EQ(t.met_refused, 0) << "of " << t.met << " rays that met the light";
  EXPECT_GT(t.missed_refused, t.missed / 2) << "of " << t.missed << " rays that did not";
}

TEST(MayMeet, AMeshLightsEveryTriangle) {
  const Tally t = trace("may_meet_mesh", R"(
AreaLightSource "diffuse" "rgb L" [1 1 1] "bool twosided" "true"
Rotate 25 1 1 0
Shape "trianglemesh" "point P" [-1 -1 0  1 -1 0  1 1 0  -1 1 0  0 0 0.8  0 -1.5 -0.4]
  "integer indices" [0 1 4  1 2 4  2 3 4  3 0 4  0 5 1]
)",
                        {-3, -3, -3}, {3, 3, 3}, 20000);
  expect_sound_and_useful(t, 2000);
}

TEST(MayMeet, QuadricLights) {
  const char* const kLights[][2] = {{"may_meet_sphere", R"(
AreaLightSource "diffuse" "rgb L" [1 1 1] "bool twosided" "true"
Translate 0.7 -0.3 0.2
Scale 1 0.5 2
Shape "sphere" "float radius" 0.6 "float zmin" -0.3 "float phimax" 270
)"},
                                    {"may_meet_disk", R"(
AreaLightSource "diffuse" "rgb L" [1 1 1] "bool twosided" "true"
Rotate 60 0 1 1
Translate 0.5 0 0.3
Shape "disk" "float radius" 1.2 "float innerradius" 0.2
)"},
                                    {"may_meet_cylinder", R"(
AreaLightSource "diffuse" "rgb L" [1 1 1] "bool twosided" "true"
Rotate 40 1 0 0
Shape "cylinder" "float radius" 0.5 "float zmin" -0.7 "float zmax" 0.4
)"}};
  for (const auto& [name, world] : kLights) {
    SCOPED_TRACE(name);
    expect_sound_and_useful(trace(name, world, {-3, -3, -3}, {3, 3, 3}, 20000), 1000);
  }
}

TEST(MayMeet, FarFromTheOrigin) {
  // Rounding is largest relative to the shape here: a small light thousands of units out.
  expect_sound_and_useful(trace("may_meet_far", R"(
Translate 4000 -2500 3000
AttributeBegin
AreaLightSource "diffuse" "rgb L" [1 1 1] "bool twosided" "true"
Shape "trianglemesh" "point P" [-1 -1 0  1 -1 0  0 1 0.3] "integer indices" [0 1 2]
AttributeEnd
AreaLightSource "diffuse" "rgb L" [1 1 1] "bool twosided" "true"
Translate 0 0 -1.5
Shape "sphere" "float radius" 0.5
)",
                                {3997, -2503, 2997}, {4003, -2497, 3003}, 20000),
                          1000);
}

TEST(MayMeet, OtherLightsAreAlwaysTraced) {
  LightScene s;
  ASSERT_TRUE(load_light_scene("may_meet_other", R"(
LightSource "point" "point from" [0 0 0]
LightSource "infinite" "rgb L" [1 1 1]
LightSource "distant" "point to" [0 0 -1]
)",
                               box({-1, -1, -1}, {1, 1, 1}), &s));
  Rng rng(3);
  for (uint32_t light = 0; light < s.lights.count(); ++light)
    for (int i = 0; i < 100; ++i)
      EXPECT_TRUE(s.lights.may_meet(
          light, Ray{{5, 5, 5}, uniform_sample_sphere({rng.next_float(), rng.next_float()})}));
}

}  // namespace
}  // namespace rt
