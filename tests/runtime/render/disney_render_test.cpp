// Whole renders of a Disney-material object in a white furnace (a constant
// infinite light of radiance 1, path integrator): every pixel finite, and a
// convex object that creates no energy cannot look brighter than the
// environment, so the mean over the object's pixels stays <= 1 (+ 4 sigma
// of the estimate) while still scattering a good part of the light.
//
// The thin setup is a disk, not a sphere: in pbrt-v3's model a thin surface
// seen from its back has the specular lobe's Fresnel of the inside of a
// dielectric (total internal reflection; the Schlick part is 1 for a
// negative cosine) on top of the diffuse transmission, so a closed thin
// sphere traps and multiplies light (its furnace converges to about 1.7,
// as pbrt-v3's own formulas give); a disk is seen from the front only.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "runtime/render_text.h"

namespace rt {
namespace {

constexpr int kSize = 32;

TEST(DisneyRender, FurnaceSphereIsFiniteAndCreatesNoEnergy) {
  struct Setup {
    const char* name;
    const char* material;
    const char* shape = R"(Shape "sphere" "float radius" 1)";
  } setups[] = {
      {"disney_furnace_metal",
       R"(Material "disney" "rgb color" [1 1 1] "float metallic" 1 "float roughness" 0.3)"},
      {"disney_furnace_glass",
       R"(Material "disney" "rgb color" [1 1 1] "float spectrans" 1 "float roughness" 0.2)"},
      {"disney_furnace_thin",
       R"(Material "disney" "rgb color" [0.8 0.8 0.8] "bool thin" "true" "float flatness" 0.5
          "float difftrans" 1 "float roughness" 0.3)",
       R"(Shape "disk" "float radius" 1)"},
      {"disney_furnace_coat",
       R"(Material "disney" "rgb color" [0.5 0.5 0.5] "float clearcoat" 1 "float sheen" 1
          "float roughness" 0.5)"},
  };
  // The sphere's image is a disc of radius 16 tan(asin(1/5)) / tan(15 deg),
  // about 12.2 pixels (the disk's 11.9): pixels within 11 of the centre all
  // see the object, the sphere's grazing rim included.
  for (const Setup& s : setups) {
    const Rendered r = render_text(s.name, furnace_scene(s.material, s.shape), 5);
    ASSERT_TRUE(r.ok) << s.name << ": " << r.error;
    const std::vector<Rgb>& pixels = r.pixels;
    ASSERT_EQ(pixels.size(), size_t(kSize * kSize));
    double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
    int n = 0;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        Rgb p = pixels[y * kSize + x];
        for (int k = 0; k < 3; ++k) {
          ASSERT_TRUE(std::isfinite(p[k])) << s.name << " pixel " << x << "," << y;
          ASSERT_GE(p[k], 0) << s.name << " pixel " << x << "," << y;
        }
        float dx = x + 0.5f - kSize / 2, dy = y + 0.5f - kSize / 2;
        if (dx * dx + dy * dy > 11 * 11) continue;
        ++n;
        for (int k = 0; k < 3; ++k) {
          sum[k] += p[k];
          sum2[k] += double(p[k]) * p[k];
        }
      }
    // The background is the environment itself.
    EXPECT_NEAR(pixels[0].g, 1, 1e-4) << s.name;
    for (int k = 0; k < 3; ++k) {
      double mean = sum[k] / n;
      double sigma = std::sqrt(std::max(0.0, sum2[k] / n - mean * mean) / n);
      EXPECT_LE(mean, 1 + 4 * sigma) << s.name << " channel " << k;
      EXPECT_GT(mean, 0.3) << s.name << " channel " << k;
    }
  }
}

}  // namespace
}  // namespace rt
