// Media in a white furnace (issue 35): a sphere of medium behind an index-matched interface
// (Material "") under a constant infinite light of radiance 1, rendered with volpath. Without
// absorption no light is lost or made, so the image mean is 1 within 4 standard errors, for
// several g, for a homogeneous medium and for a non-constant density grid; with absorption it
// is below 1. Very dense (scale 1e4), very thin (1e-4) and far-away (1e5 units) media render
// finite images with the expected values, and do not hang.
#include <gtest/gtest.h>

#include <string>

#include "stability_support.h"

namespace rt {
namespace {

// A medium `params` (after the type) filling a sphere of radius `size` at `offset` along x
// (the grid's bounds scale with it), seen from 5 radii away.
std::string medium_scene(const std::string& params, int maxdepth = 1000, double offset = 0,
                         double size = 1) {
  const std::string at = fmt(offset);
  return R"(
LookAt )" +
         at + " 0 " + fmt(5 * size) + "  " + at + R"( 0 0  0 1 0
Camera "perspective" "float fov" 30
Film "image" "integer xresolution" 32 "integer yresolution" 32
PixelFilter "box" "float xwidth" 0.5 "float ywidth" 0.5
Sampler "random" "integer pixelsamples" 64
Integrator "volpath" "integer maxdepth" )" +
         std::to_string(maxdepth) + R"(
WorldBegin
LightSource "infinite" "rgb L" [1 1 1]
AttributeBegin
Translate )" +
         at + R"( 0 0
Scale )" +
         fmt(size) + " " + fmt(size) + " " + fmt(size) + R"(
MakeNamedMedium "m" )" +
         params + R"(
MediumInterface "m" ""
Material ""
Shape "sphere"
AttributeEnd
WorldEnd
)";
}

// An 8^3 grid of densities in [0, 1] from a fixed pattern, over the sphere's bounds.
std::string grid_params(const std::string& coefficients) {
  std::string d;
  for (int i = 0; i < 512; ++i) d += " " + fmt(((i * 37) % 101) / 100.0);
  return "\"string type\" \"heterogeneous\" \"integer nx\" 8 \"integer ny\" 8 \"integer nz\" 8 "
         "\"point3 p0\" [-1 -1 -1] \"point3 p1\" [1 1 1] \"float density\" [" +
         d + "] " + coefficients;
}

void expect_furnace_one(const std::string& name, const std::string& params) {
  Rendered r = render_text(name, medium_scene(params));
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(count_nonfinite(r), 0) << name;
  MeanAndError m = mean_and_error(r);
  EXPECT_NEAR(m.mean, 1.0, 4 * m.sigma + 1e-6) << name << ": sigma " << m.sigma;
}

TEST(MediaFurnace, HomogeneousWithoutAbsorptionConservesEnergy) {
  for (const char* g : {"-0.6", "0", "0.8"})
    expect_furnace_one(std::string("media_furnace_g") + g,
                       std::string("\"string type\" \"homogeneous\" \"rgb sigma_a\" [0 0 0] "
                                   "\"rgb sigma_s\" [1 2 0.5] \"float g\" ") +
                           g);
}

TEST(MediaFurnace, DensityGridWithoutAbsorptionConservesEnergy) {
  expect_furnace_one(
      "media_furnace_grid",
      grid_params("\"rgb sigma_a\" [0 0 0] \"rgb sigma_s\" [3 3 3] \"float g\" 0.3"));
}

TEST(MediaFurnace, AbsorptionLosesEnergy) {
  for (const std::string& params :
       {std::string("\"string type\" \"homogeneous\" \"rgb sigma_a\" [0.5 0.5 0.5] "
                    "\"rgb sigma_s\" [1 1 1]"),
        grid_params("\"rgb sigma_a\" [1 1 1] \"rgb sigma_s\" [2 2 2]")}) {
    Rendered r = render_text("media_furnace_absorbing", medium_scene(params));
    ASSERT_TRUE(r.ok);
    MeanAndError m = mean_and_error(r);
    EXPECT_LT(m.mean + 4 * m.sigma, 1.0) << params.substr(0, 40);
    // The corners see the sky past the sphere: exactly 1.
    EXPECT_FLOAT_EQ(r.at(0, 0).g, 1.f);
  }
}

// Scale 1e4: the sphere is opaque (absorbing) or a dense white scatterer (bounded by maxdepth);
// either way finite, and quick.
TEST(MediaExtremes, VeryDenseMedia) {
  Rendered opaque = render_text(
      "media_dense_absorbing",
      medium_scene("\"string type\" \"homogeneous\" \"rgb sigma_a\" [1 1 1] \"rgb sigma_s\" "
                   "[0 0 0] \"float scale\" 1e4"));
  ASSERT_TRUE(opaque.ok);
  EXPECT_EQ(count_nonfinite(opaque), 0);
  EXPECT_EQ(opaque.at(16, 16), Rgb(0.f));
  EXPECT_FLOAT_EQ(opaque.at(0, 0).r, 1.f);
  Rendered grid =
      render_text("media_dense_grid",
                  medium_scene(grid_params("\"rgb sigma_a\" [0.1 0.1 0.1] \"rgb sigma_s\" [1 1 1] "
                                           "\"float scale\" 1e4"),
                               50));
  ASSERT_TRUE(grid.ok);
  EXPECT_EQ(count_nonfinite(grid), 0);
  MeanAndError m = mean_and_error(grid);
  EXPECT_GT(m.mean, 0.0);
  EXPECT_LT(m.mean, 1.0);
}

TEST(MediaExtremes, VeryThinMediaAreAlmostClear) {
  for (const std::string& params :
       {std::string("\"string type\" \"homogeneous\" \"rgb sigma_a\" [1 1 1] "
                    "\"rgb sigma_s\" [1 1 1] \"float scale\" 1e-4"),
        grid_params("\"rgb sigma_a\" [1 1 1] \"rgb sigma_s\" [1 1 1] \"float scale\" 1e-4")}) {
    Rendered r = render_text("media_thin", medium_scene(params));
    ASSERT_TRUE(r.ok);
    EXPECT_EQ(count_nonfinite(r), 0);
    // At most 2e-4 of optical depth lost through the sphere (absorption 1e-4 per unit, 2 units
    // at most); a rare scattered sample weighs its albedo, 1/2, so single pixels stay near 1.
    for (const Rgb& p : r.pixels) {
      EXPECT_GT(p.g, 0.95f);
      EXPECT_LT(p.g, 1.05f);
    }
    MeanAndError m = mean_and_error(r);
    EXPECT_NEAR(m.mean, 1.0, 4 * m.sigma + 2e-4);
  }
}

// 1e5 units out a float step is 1/128: a unit sphere there is drawn to within 1%, so the far
// sphere is 100 units across (the medium 100 times thinner), as large against its position as
// a unit sphere 1000 units out.
TEST(MediaExtremes, FarFromTheOriginStillConservesEnergy) {
  for (const std::string& params :
       {std::string("\"string type\" \"homogeneous\" \"rgb sigma_a\" [0 0 0] \"rgb sigma_s\" "
                    "[0.01 0.01 0.01]"),
        grid_params("\"rgb sigma_a\" [0 0 0] \"rgb sigma_s\" [0.03 0.03 0.03]")}) {
    Rendered r = render_text("media_far", medium_scene(params, 1000, 1e5, 100));
    ASSERT_TRUE(r.ok);
    EXPECT_EQ(count_nonfinite(r), 0);
    MeanAndError m = mean_and_error(r);
    EXPECT_NEAR(m.mean, 1.0, 4 * m.sigma + 1e-6) << params.substr(0, 40);
  }
}

}  // namespace
}  // namespace rt
