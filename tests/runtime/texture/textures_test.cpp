// Textures from real scene text: values of the combinators, mappings against
// hand-computed coordinates, checkerboard antialiasing, noise textures, and
// the "not supported yet" path.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "runtime/core/rng.h"
#include "runtime/runtime_test_support.h"
#include "runtime/texture/noise.h"
#include "runtime/texture/textures.h"
#include "test_support.h"

namespace rt {
namespace {

const char* kHead = "Camera \"perspective\"\nWorldBegin\n";

// The index of the texture the scene named `name` (float or spectrum).
uint32_t find_texture(const pbrta::SceneArchive& a, std::string_view name, bool rgb) {
  for (uint32_t i = 0; i < a.textures.size; ++i) {
    uint32_t e = a.textures[i].entity;
    bool is_rgb = pbrta::Category(a.entities[e].category) == pbrta::Category::kSpectrumTexture;
    if (a.name_of(e) == name && is_rgb == rgb) return i;
  }
  ADD_FAILURE() << "no texture " << name;
  return 0;
}

SurfaceInteraction at_uv(float u, float v) {
  SurfaceInteraction si;
  si.uv = {u, v};
  return si;
}

SurfaceInteraction at_point(Vec3 p) {
  SurfaceInteraction si;
  si.p = p;
  return si;
}

struct Scene {
  pbrta::SceneArchive archive;
  TextureSet set;
  bool ok = false;
  Scene(const std::string& name, const std::string& body) {
    if (!testing_support::compile_text(testing_support::scratch_dir(name),
                                       std::string(kHead) + body + "WorldEnd\n", &archive))
      return;
    std::string error;
    ok = set.build(archive, &error);
    EXPECT_TRUE(ok) << error;
  }
  float f(std::string_view name, const SurfaceInteraction& si) {
    return set.eval_float(find_texture(archive, name, false), si);
  }
  Rgb c(std::string_view name, const SurfaceInteraction& si) {
    return set.eval_rgb(find_texture(archive, name, true), si);
  }
};

void expect_rgb(Rgb got, Rgb want, float tol = 1e-6f) {
  EXPECT_NEAR(got.r, want.r, tol);
  EXPECT_NEAR(got.g, want.g, tol);
  EXPECT_NEAR(got.b, want.b, tol);
}

TEST(Textures, ConstantScaleMix) {
  Scene s("tex_combinators", R"(
Texture "a" "float" "constant" "float value" 0.25
Texture "b" "float" "scale" "texture tex1" "a" "float tex2" 4
Texture "red" "color" "constant" "rgb value" [1 0 0]
Texture "m" "color" "mix" "texture tex1" "red" "rgb tex2" [0 0 1] "float amount" 0.25
Texture "mt" "color" "mix" "texture tex1" "red" "rgb tex2" [0 0 1] "texture amount" "a"
Texture "sc" "color" "scale" "rgb tex1" [0.5 2 4] "texture tex2" "m"
Texture "fm" "float" "mix" "float tex1" 2 "float tex2" 6
Material "matte" "texture Kd" "m" "float sigma" 10
Shape "sphere"
)");
  ASSERT_TRUE(s.ok);
  SurfaceInteraction si = at_uv(.3f, .7f);
  EXPECT_FLOAT_EQ(s.f("a", si), 0.25f);
  EXPECT_FLOAT_EQ(s.f("b", si), 1.f);
  expect_rgb(s.c("m", si), {0.75f, 0, 0.25f});
  expect_rgb(s.c("mt", si), {0.75f, 0, 0.25f});
  expect_rgb(s.c("sc", si), {0.375f, 0, 1.f});
  EXPECT_FLOAT_EQ(s.f("fm", si), 4.f);  // schema default amount 0.5

  // Material parameters as inputs: the texture index, or the constant.
  ASSERT_GE(s.archive.materials.size, 1u);
  uint32_t mat = s.archive.materials[s.archive.materials.size - 1].entity;
  RgbInput kd = rgb_input(s.archive, mat, "Kd");
  EXPECT_EQ(kd.texture, find_texture(s.archive, "m", true));
  expect_rgb(s.set.eval(kd, si), {0.75f, 0, 0.25f});
  FloatInput sigma = float_input(s.archive, mat, "sigma");
  EXPECT_EQ(sigma.texture, kNone);
  EXPECT_FLOAT_EQ(s.set.eval(sigma, si), 10.f);
  FloatInput bump = float_input(s.archive, mat, "bumpmap");
  EXPECT_EQ(bump.texture, kNone);
  FloatInput missing = float_input(s.archive, mat, "nosuchparam");
  EXPECT_EQ(missing.texture, kNone);
  EXPECT_EQ(missing.value, 0.f);
}

TEST(Textures, UvAndBilerp) {
  Scene s("tex_uv", R"(
Texture "uv" "color" "uv"
Texture "uv2" "color" "uv" "float uscale" 2 "float vscale" 3 "float udelta" 0.25 "float vdelta" 0.5
Texture "bl" "float" "bilerp" "float v00" 1 "float v01" 2 "float v10" 3 "float v11" 4
Texture "cbl" "color" "bilerp" "rgb v00" [1 0 0] "rgb v11" [0 0 1]
)");
  ASSERT_TRUE(s.ok);
  expect_rgb(s.c("uv", at_uv(.3f, .7f)), {.3f, .7f, 0});
  // (2 * .3 + .25, 3 * .7 + .5) = (.85, 2.6): pbrt-v3 keeps the fractional parts.
  expect_rgb(s.c("uv2", at_uv(.3f, .7f)), {.85f, .6f, 0}, 1e-5f);
  // Bilinear in (s, t): v00 at (0,0), v01 at (0,1), v10 at (1,0).
  EXPECT_NEAR(s.f("bl", at_uv(0, 1)), 2, 1e-6);
  EXPECT_NEAR(s.f("bl", at_uv(1, 0)), 3, 1e-6);
  EXPECT_NEAR(s.f("bl", at_uv(.5f, .5f)), 2.5f, 1e-6);
  EXPECT_NEAR(s.f("bl", at_uv(.25f, .5f)), .75f * 1.5f + .25f * 3.5f, 1e-6);
  expect_rgb(s.c("cbl", at_uv(.5f, .5f)), {.5f, .25f, .5f});  // v01, v10 default (1 1 1), (0 0 0)
}

TEST(Textures, CheckerboardPointAndClosedForm) {
  Scene s("tex_checker", R"(
Texture "none" "float" "checkerboard" "string aamode" "none" "float uscale" 4 "float vscale" 4
Texture "cf" "float" "checkerboard" "float uscale" 4 "float vscale" 4
  "float tex1" 1 "float tex2" 0
Texture "cc" "color" "checkerboard" "rgb tex1" [1 0 0] "rgb tex2" [0 0 1]
)");
  ASSERT_TRUE(s.ok);
  // (s, t) = 4 (u, v): check (0,0) is tex1 (default 1), (1,0) tex2 (default 0).
  EXPECT_EQ(s.f("none", at_uv(.1f, .1f)), 1.f);
  EXPECT_EQ(s.f("none", at_uv(.3f, .1f)), 0.f);
  EXPECT_EQ(s.f("none", at_uv(.3f, .3f)), 1.f);
  EXPECT_EQ(s.f("none", at_uv(.3f, .6f)), 0.f);
  // Negative cells: floor(-0.4) = -1, odd, so tex2.
  EXPECT_EQ(s.f("none", at_uv(-.1f, .1f)), 0.f);

  // Closed form, footprint inside one check: the point sample.
  SurfaceInteraction si = at_uv(.1f, .1f);
  si.dudx = si.dvdy = .01f;
  EXPECT_EQ(s.f("cf", si), 1.f);
  // A footprint over many checks averages to the mean of tex1 and tex2.
  si.dudx = si.dvdy = 10;
  EXPECT_FLOAT_EQ(s.f("cf", si), .5f);
  // Half a check wide ([s-ds, s+ds] = [0.75, 1.25] in s, inside one row in t):
  // half the filter is on the tex2 check.
  si = at_uv(1.f / 4, .1f);
  si.dudx = .0625f;  // ds = 4 * 0.0625 = 0.25
  si.dvdy = .001f;
  EXPECT_NEAR(s.f("cf", si), .5f, 1e-5);
  // A quarter inside the neighbour: 0.25 of tex2.
  si = at_uv((1 - .125f) / 4, .1f);
  si.dudx = .0625f;
  si.dvdy = .001f;
  EXPECT_NEAR(s.f("cf", si), .75f, 1e-5);
  // Footprint with no extent in t, in an odd row (t = 1.2): a quarter on the
  // even-sum check (tex1). pbrt-v3 computes 0/0 here; we take the limit.
  si = at_uv((1 - .125f) / 4, .3f);
  si.dudx = .0625f;
  si.dvdy = 0;
  EXPECT_NEAR(s.f("cf", si), .25f, 1e-5);
  expect_rgb(s.c("cc", at_uv(.5f, .2f)), {1, 0, 0});  // uscale 1: all one check in [0,1)^2
}

TEST(Textures, Mappings) {
  Scene s("tex_mappings", R"(
AttributeBegin
  Translate 1 2 3
  Texture "sph" "color" "uv" "string mapping" "spherical"
  Texture "cyl" "color" "uv" "string mapping" "cylindrical"
  Texture "pl" "color" "uv" "string mapping" "planar" "vector3 v1" [1 0 0] "vector3 v2" [0 0 1]
    "float udelta" 0.5 "float vdelta" 0.25
AttributeEnd
)");
  ASSERT_TRUE(s.ok);
  const Vec3 o{1, 2, 3};
  const float r = std::sqrt(.5f);
  // Spherical, about the texture-space origin: s = theta / pi, t = phi / 2pi.
  expect_rgb(s.c("sph", at_point(o + Vec3{1, 0, 0})), {.5f, 0, 0});
  expect_rgb(s.c("sph", at_point(o + Vec3{0, r, r})), {.25f, .25f, 0}, 1e-5f);
  expect_rgb(s.c("sph", at_point(o + Vec3{0, 0, 2})), {0, 0, 0}, 1e-6f);
  // Cylindrical: s = (pi + atan2(y, x)) / 2pi, t = z of the unit direction.
  expect_rgb(s.c("cyl", at_point(o + Vec3{0, 1, 1})), {.75f, r, 0}, 1e-5f);
  expect_rgb(s.c("cyl", at_point(o + Vec3{3, 0, 0})), {.5f, 0, 0}, 1e-6f);
  // Planar ignores the transform (as pbrt-v3): (du + p.v1, dv + p.v2).
  expect_rgb(s.c("pl", at_point({.1f, .2f, .3f})), {.6f, .55f, 0}, 1e-6f);
}

TEST(Textures, MappingDifferentials) {
  Mapping2D uv;
  uv.su = 2;
  uv.sv = 3;
  SurfaceInteraction si = at_uv(.5f, .5f);
  si.dudx = .1f;
  si.dvdx = .2f;
  si.dudy = .3f;
  si.dvdy = .4f;
  Vec2 dx, dy;
  uv.map(si, &dx, &dy);
  EXPECT_FLOAT_EQ(dx.x, .2f);
  EXPECT_FLOAT_EQ(dx.y, .6f);
  EXPECT_FLOAT_EQ(dy.x, .6f);
  EXPECT_FLOAT_EQ(dy.y, 1.2f);

  Mapping2D planar;
  planar.kind = Mapping2DKind::kPlanar;
  planar.vs = {2, 0, 0};
  planar.vt = {0, 1, 1};
  si.dpdx = {1, 2, 3};
  si.dpdy = {0, 0, 1};
  planar.map(si, &dx, &dy);
  EXPECT_FLOAT_EQ(dx.x, 2);
  EXPECT_FLOAT_EQ(dx.y, 5);
  EXPECT_FLOAT_EQ(dy.x, 0);
  EXPECT_FLOAT_EQ(dy.y, 1);

  // Spherical: a small step along +z from the equator lowers theta by step/r.
  Mapping2D sph;
  sph.kind = Mapping2DKind::kSpherical;
  si.p = {2, 0, 0};
  si.dpdx = {0, 0, .01f};
  si.dpdy = {0, .01f, 0};
  Vec2 st = sph.map(si, &dx, &dy);
  EXPECT_NEAR(st.x, .5f, 1e-6);
  EXPECT_NEAR(dx.x, -.005f / kPi, 1e-5);
  EXPECT_NEAR(dy.y, .005f / (2 * kPi), 1e-5);
}

TEST(Textures, SolidTexturesUseTheCtmAsPbrtV3) {
  Scene s("tex_solid", R"(
AttributeBegin
  Scale 2 2 2
  Texture "c3" "float" "checkerboard" "integer dimension" 3
AttributeEnd
Texture "fbm" "float" "fbm"
Texture "wr" "float" "wrinkled"
Texture "windy" "color" "windy"
Texture "marble" "color" "marble"
Texture "dots" "float" "dots" "float uscale" 8 "float vscale" 8
)");
  ASSERT_TRUE(s.ok);
  // pbrt-v3's IdentityMapping3D receives tex2world, so the point is scaled by 2:
  // x = 0.3 -> 0.6 (cell 0, tex1 = 1), x = 0.6 -> 1.2 (cell 1, tex2 = 0).
  EXPECT_EQ(s.f("c3", at_point({.3f, .1f, .1f})), 1.f);
  EXPECT_EQ(s.f("c3", at_point({.6f, .1f, .1f})), 0.f);
  EXPECT_EQ(s.f("c3", at_point({-.1f, .1f, .1f})), 0.f);

  // Deterministic, and within the bound of the octave sum (|noise| <= ~1).
  float lo = 1e9f, hi = -1e9f;
  for (int i = 0; i < 200; ++i) {
    Vec3 p{i * .137f, i * .071f - 3, 1.3f - i * .05f};
    float v = s.f("fbm", at_point(p));
    EXPECT_EQ(v, s.f("fbm", at_point(p)));
    EXPECT_LT(std::fabs(v), 2.f);
    lo = std::min(lo, v);
    hi = std::max(hi, v);
    float w = s.f("wr", at_point(p));
    EXPECT_GE(w, 0.f);
    EXPECT_LT(w, 2.f);
    Rgb m = s.c("marble", at_point(p));
    EXPECT_EQ(m, s.c("marble", at_point(p)));
    EXPECT_TRUE(m.is_finite());
    Rgb wd = s.c("windy", at_point(p));
    EXPECT_EQ(wd.r, wd.g);
    EXPECT_LT(std::fabs(wd.r), 4.f);
  }
  EXPECT_LT(lo, -.1f);  // it varies, both signs
  EXPECT_GT(hi, .1f);

  // Noise vanishes on the integer lattice.
  EXPECT_EQ(noise(3, -2, 7), 0.f);
  EXPECT_EQ(noise(0, 0, 0), 0.f);
  // A footprint wider than the largest feature leaves no octave: FBm is 0 and
  // turbulence is its clamped-octave average, 0.2 counted once for the partial
  // octave and once per octave: 0.2 + 0.2 (1 + .5 + ... + .5^7).
  SurfaceInteraction wide = at_point({.3f, .4f, .5f});
  wide.dpdx = {10, 0, 0};
  EXPECT_EQ(s.f("fbm", wide), 0.f);
  EXPECT_NEAR(s.f("wr", wide), 0.2f + 0.2f * (2 - 1.f / 128), 1e-5);

  // Dots: only inside (1) or outside (0), and both occur.
  int inside = 0, outside = 0;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) {
      float v = s.f("dots", at_uv(i / 40.f, j / 40.f));
      EXPECT_TRUE(v == 0.f || v == 1.f);
      (v == 1.f ? inside : outside)++;
    }
  EXPECT_GT(inside, 20);
  EXPECT_GT(outside, 20);
}

TEST(Textures, MarbleSplineAsPbrtV3) {
  Scene s("tex_marble", R"(
Texture "m" "color" "marble" "float variation" 0
)");
  ASSERT_TRUE(s.ok);
  // With no variation, t = .5 + .5 sin(p.y). sin = -1: t = 0, the first control point x 1.5.
  expect_rgb(s.c("m", at_point({.3f, -kPi / 2, .7f})), {.87f, .87f, .9f}, 1e-5f);
  // t = .5: pbrt-v3's min(1, segment) picks segment 1 and evaluates its cubic
  // Bezier at 2 (outside [0, 1]): -c1 + 6 c2 - 12 c3 + 8 c4, times 1.5.
  expect_rgb(s.c("m", at_point({.3f, 0, .7f})), {2.55f, 2.43f, 2.46f}, 1e-4f);
}

TEST(Textures, NoiseIsContinuousAndBounded) {
  float prev = noise(0.01f, .37f, .61f);
  float lo = 1, hi = -1;
  for (int i = 1; i < 2000; ++i) {
    float x = .01f + i * .005f;
    float v = noise(x, .37f, .61f);
    EXPECT_LT(std::fabs(v - prev), .05f);
    prev = v;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  EXPECT_GE(lo, -1.1f);
  EXPECT_LE(hi, 1.1f);
  EXPECT_LT(lo, -.2f);
  EXPECT_GT(hi, .2f);
  // Period 256 on the lattice (the permutation wraps).
  EXPECT_NEAR(noise(.3f, .4f, .5f), noise(256.3f, .4f, .5f), 1e-4);
}

// fbm and turbulence against their definition (pbrt-v3's octave loops, noise() by noise()),
// over footprints from every octave allowed down to none and max_octaves 1 to 9: skipping
// the partial octave's noise when its weight is 0 must change no bit.
TEST(Textures, FbmAndTurbulenceAreTheirOctaveSums) {
  Rng rng(22);
  auto smooth = [](float v) {
    const float t = clamp((v - .3f) / (.7f - .3f), 0.f, 1.f);
    return t * t * (-2 * t + 3);
  };
  int skipped = 0;
  for (int k = 0; k < 3000; ++k) {
    const Vec3 p{40 * rng.next_float() - 20, 40 * rng.next_float() - 20,
                 40 * rng.next_float() - 20};
    const float len = std::pow(10.f, -4 + 4 * rng.next_float());
    const Vec3 dpdx{len, 0, 0}, dpdy{0, len * rng.next_float(), 0};
    const float omega = .3f + .5f * rng.next_float();
    const int max_octaves = 1 + k % 9;
    const float len2 = std::max(length_squared(dpdx), length_squared(dpdy));
    const float n = clamp(-1 - .5f * (std::log(len2) * 1.442695040888963387004650940071f), 0.f,
                          float(max_octaves));
    const int n_int = int(std::floor(n));
    float f = 0, t = 0, lambda = 1, o = 1;
    for (int i = 0; i < n_int; ++i) {
      f += o * noise(lambda * p);
      t += o * std::fabs(noise(lambda * p));
      lambda *= 1.99f;
      o *= omega;
    }
    const float w = smooth(n - n_int);
    skipped += w == 0;
    f += o * w * noise(lambda * p);
    t += o * lerp(w, 0.2f, std::fabs(noise(lambda * p)));
    for (int i = n_int; i < max_octaves; ++i) {
      t += o * 0.2f;
      o *= omega;
    }
    ASSERT_EQ(fbm(p, dpdx, dpdy, omega, max_octaves), f) << "k " << k;
    ASSERT_EQ(turbulence(p, dpdx, dpdy, omega, max_octaves), t) << "k " << k;
  }
  EXPECT_GT(skipped, 300);   // the case the skip is for is well covered
  EXPECT_LT(skipped, 2700);  // and so is a partial octave that counts
}

TEST(Textures, UnsupportedGivesMessage) {
  std::string dir = testing_support::scratch_dir("tex_ptex");
  testing_support::write_file(dir + "/t.ptx", "not a ptex file");
  pbrta::SceneArchive a;
  ASSERT_TRUE(testing_support::compile_text(dir, std::string(kHead) + R"(
Texture "p" "color" "ptex" "string filename" "t.ptx"
WorldEnd
)",
                                            &a));
  TextureSet set;
  std::string error;
  EXPECT_FALSE(set.build(a, &error));
  EXPECT_EQ(error, "not supported yet: ptex texture (scene.pbrt:4)");
}

}  // namespace
}  // namespace rt
