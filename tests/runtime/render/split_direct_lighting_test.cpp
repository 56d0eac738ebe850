// The path integrator's direct lighting, split as pbrt-v4's (the light sample at the vertex,
// the path's own next scattering sample weighted where it meets a light), has pbrt-v3's
// expectation: at maxdepth 1 a path render is direct lighting, which the directlighting
// integrator ("one" strategy) computes with pbrt-v3's EstimateDirect (its own scattering ray,
// counted only for the light it chose). Several area lights of different sizes (so the choice
// of light matters to the weights), glossy and diffuse surfaces, an infinite light.
#include <gtest/gtest.h>

#include <string>

#include "runtime/render_text.h"

namespace rt {
namespace {

std::string scene(const char* integrator) {
  return std::string(R"(
LookAt 0 2 6  0 0 0  0 1 0
Camera "perspective" "float fov" 45
Film "image" "integer xresolution" 48 "integer yresolution" 32
Sampler "halton" "integer pixelsamples" 256
)") + integrator +
         R"(
WorldBegin
LightSource "infinite" "rgb L" [0.05 0.05 0.06]
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [400 400 400]
  Translate -2 2.5 -1
  Shape "sphere" "float radius" 0.05
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [25 25 25]
  Translate 0 2.5 -1
  Shape "sphere" "float radius" 0.2
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [4 2 1]
  Translate 2 2.5 -1
  Shape "sphere" "float radius" 0.5
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [1 2 4]
  Shape "trianglemesh" "integer indices" [0 1 2]
    "point P" [-3 3 -3  3 3 -3  0 1 -3]
AttributeEnd
Material "plastic" "rgb Kd" [0.1 0.1 0.1] "rgb Ks" [0.8 0.8 0.8] "float roughness" 0.01
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
  "point P" [-4 0 -2  4 0 -2  4 0 1  -4 0 1]
Material "matte" "rgb Kd" [0.5 0.5 0.5]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
  "point P" [-6 -0.5 -6  6 -0.5 -6  6 -0.5 4  -6 -0.5 4]
WorldEnd
)";
}

TEST(SplitDirectLighting, PathAtDepthOneIsPbrtV3sDirectLighting) {
  Rendered path =
      render_text("split_direct_path", scene("Integrator \"path\" \"integer maxdepth\" 1"));
  Rendered direct = render_text(
      "split_direct_direct",
      scene("Integrator \"directlighting\" \"integer maxdepth\" 1 \"string strategy\" \"one\""));
  ASSERT_TRUE(path.ok && direct.ok);
  // The whole image, then bands of eight rows: lights and their glossy reflections (top and
  // middle), the diffuse floor (bottom).
  for (int band = 0; band < 5; ++band) {
    const int y0 = band == 4 ? 0 : band * 8, y1 = band == 4 ? 32 : y0 + 8;
    const double a = mean_luminance(direct, 0, 48, y0, y1);
    const double b = mean_luminance(path, 0, 48, y0, y1);
    EXPECT_NEAR(b / a, 1, 0.01) << "rows " << y0 << "-" << y1 << ": directlighting " << a
                                << ", path " << b;
  }
  EXPECT_EQ(path.stats.nonfinite_samples, 0u);
}

}  // namespace
}  // namespace rt
