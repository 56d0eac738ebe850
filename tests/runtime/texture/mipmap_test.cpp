// MIP-map lookups over images pbrtc decoded from a PFM written here: texel
// orientation (texture t counts the file's rows bottom-up), wrap modes,
// bilinear, trilinear and EWA filtering, and imagemap textures using them.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <string>

#include "runtime/runtime_test_support.h"
#include "runtime/texture/mipmap.h"
#include "runtime/texture/textures.h"
#include "test_support.h"

namespace rt {
namespace {

constexpr int kSize = 4;

// The RGB of texel (s, t): t is the row counted from the bottom, which is
// both PFM's row order and pbrt-v3's texture t.
Rgb file_texel(int s, int t) {
  return {float(s + kSize * t), float(10 * (s + 1)), float(t)};
}

Rgb level0_mean() {
  Rgb sum;
  for (int t = 0; t < kSize; ++t)
    for (int s = 0; s < kSize; ++s) sum += file_texel(s, t);
  return sum / float(kSize * kSize);
}

// A little-endian float RGB PFM: "PF", size, negative scale, rows bottom to top.
void write_pfm(const std::string& path) {
  std::ofstream f(path, std::ios::binary);
  f << "PF\n" << kSize << " " << kSize << "\n-1\n";
  for (int t = 0; t < kSize; ++t)
    for (int s = 0; s < kSize; ++s) {
      Rgb c = file_texel(s, t);
      float v[3] = {c.r, c.g, c.b};
      f.write(reinterpret_cast<const char*>(v), sizeof v);
    }
}

struct ImageScene {
  pbrta::SceneArchive archive;
  TextureSet set;
  bool ok = false;
  ImageScene(const std::string& name, const std::string& textures) {
    std::string dir = testing_support::scratch_dir(name);
    write_pfm(dir + "/grid.pfm");
    if (!testing_support::compile_text(
            dir, "Camera \"perspective\"\nWorldBegin\n" + textures + "WorldEnd\n", &archive))
      return;
    std::string error;
    ok = set.build(archive, &error);
    EXPECT_TRUE(ok) << error;
  }
  // The MIP map of the i-th texture.
  const MipMap& mip(uint32_t i) const { return set.mipmap(set.node(i).mipmap); }
};

void expect_rgb(Rgb got, Rgb want, float tol = 1e-5f) {
  EXPECT_NEAR(got.r, want.r, tol);
  EXPECT_NEAR(got.g, want.g, tol);
  EXPECT_NEAR(got.b, want.b, tol);
}

Vec2 centre(int s, int t, int res = kSize) {
  return {(s + .5f) / res, (t + .5f) / res};
}

SurfaceInteraction at_uv(Vec2 uv, float dudx = 0, float dvdy = 0) {
  SurfaceInteraction si;
  si.uv = uv;
  si.dudx = dudx;
  si.dvdy = dvdy;
  return si;
}

TEST(MipMap, OrientationAndTexelCentres) {
  ImageScene sc("mip_orient", R"(
Texture "g" "color" "imagemap" "string filename" "grid.pfm"
Texture "gf" "float" "imagemap" "string filename" "grid.pfm"
)");
  ASSERT_TRUE(sc.ok);
  const MipMap& m = sc.mip(0);
  EXPECT_EQ(m.width(), kSize);
  EXPECT_EQ(m.height(), kSize);
  EXPECT_EQ(m.levels(), 3);
  EXPECT_EQ(m.channels(), 3);
  for (int t = 0; t < kSize; ++t)
    for (int s = 0; s < kSize; ++s) {
      EXPECT_EQ(m.texel(0, s, t), file_texel(s, t)) << s << "," << t;
      // Zero footprint: EWA falls back to bilinear, exact at texel centres.
      SurfaceInteraction si = at_uv(centre(s, t));
      EXPECT_EQ(sc.set.eval_rgb(0, si), file_texel(s, t)) << s << "," << t;
      EXPECT_NEAR(sc.set.eval_float(1, si), file_texel(s, t).luminance(), 1e-4);
    }
  // The stored rows are top to bottom: row 0 of level 0 holds the file's top row (t = 3).
  const pbrta::ImageRecord& im = sc.archive.images[sc.archive.textures[0].image];
  const float* row0 =
      reinterpret_cast<const float*>(sc.archive.reader().section_data(im.section) + im.offset);
  EXPECT_EQ(row0[0], file_texel(0, kSize - 1).r);
  // A light map reads the same image unflipped: (s, t) is stored row t.
  MipMap unflipped;
  std::string error;
  ASSERT_TRUE(unflipped.init(sc.archive, sc.archive.textures[0].image, false, &error)) << error;
  EXPECT_EQ(unflipped.texel(0, 1, 0), file_texel(1, kSize - 1));

  // Halfway between two texel centres: their average.
  Vec2 mid{(1 + 1.f) / kSize, (2 + .5f) / kSize};
  expect_rgb(m.bilerp(0, mid), (file_texel(1, 2) + file_texel(2, 2)) * .5f);
}

TEST(MipMap, WrapModes) {
  ImageScene sc("mip_wrap", R"(
Texture "r" "color" "imagemap" "string filename" "grid.pfm" "string wrap" "repeat"
Texture "b" "color" "imagemap" "string filename" "grid.pfm" "string wrap" "black"
Texture "c" "color" "imagemap" "string filename" "grid.pfm" "string wrap" "clamp"
)");
  ASSERT_TRUE(sc.ok);
  const MipMap &rep = sc.mip(0), &blk = sc.mip(1), &clp = sc.mip(2);
  EXPECT_EQ(rep.wrap(), ImageWrap::kRepeat);
  EXPECT_EQ(blk.wrap(), ImageWrap::kBlack);
  EXPECT_EQ(clp.wrap(), ImageWrap::kClamp);
  EXPECT_EQ(rep.texel(0, -1, 0), file_texel(3, 0));
  EXPECT_EQ(rep.texel(0, 5, -2), file_texel(1, 2));
  EXPECT_EQ(blk.texel(0, -1, 0), Rgb(0.f));
  EXPECT_EQ(blk.texel(0, 2, 4), Rgb(0.f));
  EXPECT_EQ(clp.texel(0, -1, 0), file_texel(0, 0));
  EXPECT_EQ(clp.texel(0, 7, 9), file_texel(3, 3));
  // Lookups outside [0, 1]: one period over (repeat), nothing (black), the edge (clamp).
  Vec2 out{1 + centre(0, 1).x, centre(0, 1).y};
  EXPECT_EQ(sc.set.eval_rgb(0, at_uv(out)), file_texel(0, 1));
  EXPECT_EQ(sc.set.eval_rgb(1, at_uv(out)), Rgb(0.f));
  EXPECT_EQ(sc.set.eval_rgb(2, at_uv(out)), file_texel(3, 1));
  // At the edge between the last texel and the black beyond: half of it.
  Vec2 edge{1.f, centre(0, 1).y};
  expect_rgb(blk.bilerp(0, edge), file_texel(3, 1) * .5f);
}

TEST(MipMap, TrilinearPicksLevelByWidth) {
  ImageScene sc("mip_tri", R"(
Texture "t" "color" "imagemap" "string filename" "grid.pfm" "bool trilinear" "true"
)");
  ASSERT_TRUE(sc.ok);
  const MipMap& m = sc.mip(0);
  // Level 1 texel (0, 0) is the box average of level 0 texels (0..1, 0..1).
  Rgb box = (file_texel(0, 0) + file_texel(1, 0) + file_texel(0, 1) + file_texel(1, 1)) * .25f;
  expect_rgb(m.texel(1, 0, 0), box);
  // Width 0.5 = level 1's texel spacing: exactly level 1, bilinear there.
  expect_rgb(m.lookup_trilinear(centre(0, 0, 2), .5f), box);
  // Width 0.25: level 0.
  expect_rgb(m.lookup_trilinear(centre(2, 1), .25f), file_texel(2, 1));
  // Halfway (in log2) between levels 0 and 1.
  Vec2 st = centre(0, 0, 2);
  expect_rgb(m.lookup_trilinear(st, std::sqrt(.125f)), (m.bilerp(0, st) + m.bilerp(1, st)) * .5f,
             1e-4f);
  // Width >= 1: the single coarsest texel, the image mean.
  expect_rgb(m.lookup_trilinear(st, 3), level0_mean());
  // The texture: width = 2 max |dst| with dst from du/dx, dv/dy (uv mapping):
  // du/dx = 0.25 -> width 0.5 -> level 1.
  expect_rgb(sc.set.eval_rgb(0, at_uv(centre(0, 0, 2), .25f, .01f)), box);
  expect_rgb(sc.set.eval_rgb(0, at_uv(centre(0, 0, 2), 0, 0)), m.bilerp(0, centre(0, 0, 2)));
}

TEST(MipMap, EwaLimits) {
  ImageScene sc("mip_ewa", R"(
Texture "e" "color" "imagemap" "string filename" "grid.pfm"
Texture "ef" "float" "imagemap" "string filename" "grid.pfm" "float maxanisotropy" 2
)");
  ASSERT_TRUE(sc.ok);
  const MipMap& m = sc.mip(0);
  Vec2 st{.3f, .6f};
  // No footprint, or a degenerate (line) ellipse: bilinear.
  EXPECT_EQ(m.lookup_ewa(st, {0, 0}, {0, 0}, 8), m.bilerp(0, st));
  EXPECT_EQ(m.lookup_ewa(st, {.2f, 0}, {0, 0}, 8), m.bilerp(0, st));
  // A footprint covering the image: the coarsest level, the mean.
  expect_rgb(m.lookup_ewa(st, {1, 0}, {0, 1}, 8), level0_mean(), 1e-4f);
  expect_rgb(m.lookup_ewa(st, {5, 1}, {-1, 5}, 8), level0_mean(), 1e-4f);
  // A small round footprint at a texel centre stays near that texel and is
  // a convex combination (the weights are positive): within the image's range.
  Rgb small = m.lookup_ewa(centre(1, 2), {.01f, 0}, {0, .01f}, 8);
  EXPECT_NEAR(small.r, file_texel(1, 2).r, 1.5f);
  EXPECT_GE(small.r, 0.f);
  EXPECT_LE(small.r, 15.f);
  // Widening the ellipse moves the result towards the mean.
  float prev = 1e9f;
  for (float w : {.02f, .1f, .3f, 1.f}) {
    Rgb v = m.lookup_ewa(centre(0, 0), {w, 0}, {0, w}, 8);
    float d = std::fabs(v.r - level0_mean().r);
    EXPECT_LE(d, prev + 1e-4f) << w;
    prev = d;
  }
  EXPECT_LT(prev, 1e-3f);
  // The texture passes du/dx, dv/dy through: the float version agrees with
  // the float MIP map's own EWA (maxanisotropy 2 clamps this 10:1 ellipse).
  const MipMap& mf = sc.mip(1);
  EXPECT_EQ(mf.channels(), 1);
  SurfaceInteraction si = at_uv(st, .1f, .01f);
  EXPECT_EQ(sc.set.eval_float(1, si), mf.lookup_ewa_float(st, {.1f, 0}, {0, .01f}, 2));
  EXPECT_NE(sc.set.eval_float(1, si), mf.lookup_ewa_float(st, {.1f, 0}, {0, .01f}, 8));
}

}  // namespace
}  // namespace rt

namespace rt {
namespace {

// pbrtc writes f32 texels only; f16 levels are widened through this.
TEST(MipMap, HalfToFloat) {
  EXPECT_EQ(half_to_float(0x3C00), 1.f);
  EXPECT_EQ(half_to_float(0xC000), -2.f);
  EXPECT_EQ(half_to_float(0x7BFF), 65504.f);
  EXPECT_EQ(half_to_float(0x0400), std::ldexp(1.f, -14));
  EXPECT_EQ(half_to_float(0x0001), std::ldexp(1.f, -24));  // smallest subnormal
  EXPECT_EQ(half_to_float(0x0200), std::ldexp(1.f, -15));
  EXPECT_EQ(half_to_float(0x3555), 0.333251953125f);
  EXPECT_EQ(half_to_float(0x8000), -0.f);
  EXPECT_TRUE(std::signbit(half_to_float(0x8000)));
  EXPECT_EQ(half_to_float(0x7C00), kInfinity);
  EXPECT_TRUE(std::isnan(half_to_float(0x7E00)));
}

}  // namespace
}  // namespace rt
