// pbrtc --texture-precision as the renderer sees it: hm-textures' ewa-filtering compiled with
// f32, f16 and unorm8 texels, its imagemap "rendered" as a 96 x 96 image of EWA and trilinear
// lookups whose footprints sweep every MIP level. Both filters are convex combinations of
// texels, so every pixel of the f16 image lies within the f32 one's relative half-ulp (2^-11)
// and every unorm8 pixel within half a step (0.5 / 255) of it; and the quantised images are
// not the f32 one (the option really rounds).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "compiler/archive_builder.h"
#include "compiler/parser.h"
#include "compiler/scene_builder.h"
#include "runtime/texture/textures.h"
#include "test_support.h"

namespace rt {
namespace {

constexpr int kRes = 96;

struct Compiled {
  pbrta::SceneArchive archive;
  TextureSet set;
};

// Compiles the shared scene with the given texel format and builds its textures.
bool compile(const std::string& rel, pbrta::PixelFormat format, Compiled* c) {
  const std::string path = testing_support::shared_dir() + "/scenes/" + rel;
  pbrtc::SourceFiles files;
  pbrtc::Diagnostics diag(&files, nullptr);
  pbrtc::SceneDesc scene;
  if (!pbrtc::build_scene(path, &files, &diag, &scene)) {
    ADD_FAILURE() << "cannot compile " << path;
    return false;
  }
  pbrtc::ArchiveOptions opt;
  opt.texture_format = format;
  const std::string out =
      testing_support::scratch_dir("texprec_runtime_" + std::to_string(int(format))) +
      "/scene.pbrta";
  std::string error;
  if (!pbrtc::write_archive(scene, files, pbrtc::directory_of(path), out, opt, nullptr, &error) ||
      !c->archive.load(out, 1, &error) || !c->set.build(c->archive, &error)) {
    ADD_FAILURE() << error;
    return false;
  }
  return true;
}

// The imagemap at every pixel: uv across [0, 1]^2 (the scene's uscale 15 repeats it), with a
// footprint growing 2^(10 y / kRes) from a hundredth of a texel (level 0) to the whole image
// (the top level), anisotropic in half the columns.
std::vector<Rgb> render(const TextureSet& set, uint32_t texture) {
  std::vector<Rgb> img;
  for (int y = 0; y < kRes; ++y)
    for (int x = 0; x < kRes; ++x) {
      SurfaceInteraction si;
      si.uv = {(x + .5f) / kRes, (y + .37f) / kRes};
      const float d = 1e-6f * std::exp2(16.f * y / kRes);
      si.dudx = d;
      si.dvdy = x % 2 ? 4 * d : d;
      si.dvdx = x % 3 ? 0.f : d / 2;
      img.push_back(set.eval_rgb(texture, si));
    }
  return img;
}

TEST(TexturePrecision, QuantisedTexelsRenderWithinTheirBound) {
  // The same lines.png: EWA filtering in one scene, trilinear in the other.
  for (const char* name : {"ewa-filtering", "trilinear-filtering"}) {
    SCOPED_TRACE(name);
    const std::string scene =
        std::string("hm-textures/pbrt-v3-rs/scenes/textures/") + name + ".pbrt";
    Compiled f32, f16, u8;
    ASSERT_TRUE(compile(scene, pbrta::PixelFormat::kFloat32, &f32));
    ASSERT_TRUE(compile(scene, pbrta::PixelFormat::kHalf16, &f16));
    ASSERT_TRUE(compile(scene, pbrta::PixelFormat::kUnorm8, &u8));
    ASSERT_EQ(f16.archive.images[0].format, uint32_t(pbrta::PixelFormat::kHalf16));
    ASSERT_EQ(u8.archive.images[0].format, uint32_t(pbrta::PixelFormat::kUnorm8));
    ASSERT_EQ(f32.set.size(), 1u);
    ASSERT_EQ(f32.set.node(0).kind, TextureKind::kImage);
    EXPECT_EQ(f32.set.node(0).trilinear, name[0] == 't');
    const std::vector<Rgb> a = render(f32.set, 0), h = render(f16.set, 0), q = render(u8.set, 0);
    int differ_h = 0, differ_q = 0;
    double worst_q = 0;
    for (size_t i = 0; i < a.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const float ref = a[i][k];
        ASSERT_TRUE(std::isfinite(ref));
        // Float arithmetic in the filter adds a few ulps to the bound.
        ASSERT_LE(std::fabs(h[i][k] - ref), ref * (1.f / 2048) + 1e-6f) << "pixel " << i;
        ASSERT_LE(std::fabs(q[i][k] - ref), 0.5f / 255 + 1e-6f) << "pixel " << i;
        differ_h += h[i][k] != ref;
        differ_q += q[i][k] != ref;
        worst_q = std::max(worst_q, double(std::fabs(q[i][k] - ref)));
      }
    // The texels (two palette colours after the sRGB curve, and their box-filtered mixes) are
    // neither halves nor steps of 1/255: neither archive renders the f32 image.
    std::printf("%s: %d of %zu channel values differ with f16, %d with unorm8 (worst %.3g)\n", name,
                differ_h, 3 * a.size(), differ_q, worst_q);
    EXPECT_GT(differ_q, int(a.size()) / 2);
    EXPECT_GT(differ_h, 0);
    EXPECT_GT(worst_q, 0.1 / 255);
  }
}

}  // namespace
}  // namespace rt
