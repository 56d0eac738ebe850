// Whole renders of the fourier material with the real measured table the
// shared corpus carries (pbrt-v3-scenes' roughgold_alpha_0.2.bsdf): compiled
// by pbrtc into the archive and rendered through pbrtrun's pieces
// (render_text). In the white furnace (furnace_scene) a
// convex gold sphere must be finite everywhere, must not create energy (mean
// over its pixels <= 1 + 4 sigma), and must look like gold (red > blue).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "runtime/render_text.h"

namespace rt {
namespace {

std::string gold_table() {
  return testing_support::shared_dir() +
         "/scenes/hm-materials-partial/pbrt-v3-scenes/dragon/bsdfs/roughgold_alpha_0.2.bsdf";
}

TEST(FourierRender, GoldSphereInAFurnaceIsFiniteAndCreatesNoEnergy) {
  const Rendered r =
      render_text("fourier_furnace",
                  furnace_scene("Material \"fourier\" \"string bsdffile\" \"" + gold_table() + "\"",
                                R"(Shape "sphere" "float radius" 1)"),
                  3);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.stats.nonfinite_samples, 0u);
  ASSERT_EQ(r.width, 32);
  // The sphere covers the pixels within ~0.8 of the image's half-width of
  // the centre (fov 30 at distance 5: the radius-1 sphere spans 0.75 of it).
  double sum[3] = {0, 0, 0}, sum2 = 0;
  int n = 0, background = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      const Rgb& p = r.at(x, y);
      for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(p[c]) && p[c] >= 0);
      const double dx = (x + 0.5) / 16 - 1, dy = (y + 0.5) / 16 - 1;
      const double rr = std::sqrt(dx * dx + dy * dy);
      if (rr < 0.6) {
        for (int c = 0; c < 3; ++c) sum[c] += p[c];
        const double l = (p[0] + p[1] + p[2]) / 3;
        sum2 += l * l;
        ++n;
      } else if (rr > 0.95) {
        background += std::fabs(p[0] - 1) < 1e-4f && std::fabs(p[2] - 1) < 1e-4f;
      }
    }
  ASSERT_GT(n, 100);
  EXPECT_GT(background, 0);  // the corners see the environment, exactly 1
  const double mean = (sum[0] + sum[1] + sum[2]) / (3.0 * n);
  const double sigma = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
  std::printf("[ fourier furnace ] mean %.4f (r %.4f g %.4f b %.4f) sigma %.4f over %d pixels\n",
              mean, sum[0] / n, sum[1] / n, sum[2] / n, sigma, n);
  EXPECT_LE(mean, 1 + 4 * sigma);
  EXPECT_GT(mean, 0.3);             // gold reflects most light
  EXPECT_GT(sum[0], 1.2 * sum[2]);  // and reflects red more than blue
}

TEST(FourierRender, RendersTheTableThroughAMixAndWithBump) {
  const std::string text = R"(
LookAt 0 0 5  0 0 0  0 1 0
Camera "perspective" "float fov" 30
Film "image" "integer xresolution" 16 "integer yresolution" 16
Sampler "random" "integer pixelsamples" 8
Integrator "directlighting"
WorldBegin
LightSource "distant" "point from" [0 0 5] "point to" [0 0 0] "rgb L" [3 3 3]
Texture "bumps" "float" "wrinkled" "float scale" 0.01
MakeNamedMaterial "gold" "string type" "fourier" "string bsdffile" ")" +
                           gold_table() + R"(" "texture bumpmap" "bumps"
MakeNamedMaterial "white" "string type" "matte"
MakeNamedMaterial "both" "string type" "mix" "string namedmaterial1" "gold"
  "string namedmaterial2" "white" "rgb amount" [0.5 0.5 0.5]
NamedMaterial "both"
Shape "sphere" "float radius" 1
WorldEnd
)";
  const Rendered r = render_text("fourier_mix", text);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.stats.nonfinite_samples, 0u);
  // The sphere's centre faces the light: lit, and warmer than the white half alone.
  const Rgb& c = r.at(8, 8);
  EXPECT_GT(c[0], 0.1f);
  EXPECT_GT(c[0], c[2]);
}

}  // namespace
}  // namespace rt
