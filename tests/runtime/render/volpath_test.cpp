// volpath beside path (issue 35): pbrt-v3's volpath is its path integrator wherever no medium
// is, so on a scene without media the two give the same pixels (here: the same kernel); path on
// a scene with media ignores them (pbrt-v3 warns and renders the surfaces), so its image is the
// image of the scene without them. A camera inside a medium sees the medium's attenuation.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "runtime/render_text.h"

namespace rt {
namespace {

std::string scene(const std::string& integrator, const std::string& medium_lines) {
  return R"(
LookAt 0 0.5 4  0 0 0  0 1 0
Camera "perspective" "float fov" 40
Film "image" "integer xresolution" 24 "integer yresolution" 24
Sampler "halton" "integer pixelsamples" 16
Integrator ")" +
         integrator + R"(" "integer maxdepth" 5
WorldBegin
LightSource "point" "point from" [2 3 2] "rgb I" [10 10 10]
LightSource "infinite" "rgb L" [0.2 0.3 0.4]
)" + medium_lines +
         R"(
AttributeBegin
Material "matte" "rgb Kd" [0.7 0.5 0.3]
Shape "trianglemesh" "point3 P" [-3 -1 -3  3 -1 -3  3 -1 3  -3 -1 3] "integer indices" [0 1 2 0 2 3]
AttributeEnd
AttributeBegin
Material "glass"
Shape "sphere" "float radius" 0.7
AttributeEnd
WorldEnd
)";
}

constexpr const char* kFog =
    "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [0.2 0.2 0.2] "
    "\"rgb sigma_s\" [0.5 0.5 0.5]\nAttributeBegin\nMediumInterface \"fog\" \"\"\nMaterial \"\"\n"
    "Shape \"sphere\" \"float radius\" 1.2\nAttributeEnd\n";

TEST(VolPath, IsPathWhereThereAreNoMedia) {
  Rendered path = render_text("volpath_no_media_path", scene("path", ""));
  Rendered vol = render_text("volpath_no_media_volpath", scene("volpath", ""));
  ASSERT_TRUE(path.ok && vol.ok);
  ASSERT_EQ(path.pixels.size(), vol.pixels.size());
  for (size_t i = 0; i < path.pixels.size(); ++i) ASSERT_EQ(path.pixels[i], vol.pixels[i]) << i;
}

// The fog's boundary without the fog: an interface sphere bounding no medium.
constexpr const char* kNoFog =
    "AttributeBegin\nMaterial \"\"\nShape \"sphere\" \"float radius\" 1.2\nAttributeEnd\n";

TEST(VolPath, PathIgnoresMediaAsPbrtV3Does) {
  Rendered plain = render_text("path_without_fog", scene("path", kNoFog));
  Rendered fog = render_text("path_with_fog", scene("path", kFog));
  ASSERT_TRUE(plain.ok && fog.ok);
  for (size_t i = 0; i < plain.pixels.size(); ++i) ASSERT_EQ(plain.pixels[i], fog.pixels[i]) << i;
  // volpath does see the fog: the image changes.
  Rendered vol = render_text("volpath_with_fog", scene("volpath", kFog));
  ASSERT_TRUE(vol.ok);
  double diff = 0;
  for (size_t i = 0; i < plain.pixels.size(); ++i)
    diff += std::abs(vol.pixels[i].g - plain.pixels[i].g);
  EXPECT_GT(diff / double(plain.pixels.size()), 0.01);
}

// The camera sits in a purely absorbing medium (CameraMedium from the outside medium at Camera):
// every camera ray to the sky is attenuated by exp(-sigma_a * distance to the enclosing sphere),
// in expectation (volpath samples a distance in the medium, as pbrt-v3 does, and a ray that
// stops where nothing scatters carries nothing).
TEST(VolPath, CameraInsideAMedium) {
  const std::string text = R"(
MakeNamedMedium "ink" "string type" "homogeneous" "rgb sigma_a" [0.1 0.2 0.4] "rgb sigma_s" [0 0 0]
MediumInterface "" "ink"
LookAt 0 0 0  0 0 1  0 1 0
Camera "perspective" "float fov" 10
Film "image" "integer xresolution" 8 "integer yresolution" 8
Sampler "random" "integer pixelsamples" 256
Integrator "volpath"
WorldBegin
LightSource "infinite" "rgb L" [1 1 1]
AttributeBegin
MediumInterface "ink" ""
Material ""
Shape "sphere" "float radius" 3
AttributeEnd
WorldEnd
)";
  Rendered r = render_text("volpath_camera_medium", text);
  ASSERT_TRUE(r.ok);
  // Rays travel 3 units to the sphere from its centre, whatever their direction.
  const double expected[3] = {std::exp(-0.3), std::exp(-0.6), std::exp(-1.2)};
  for (int c = 0; c < 3; ++c) {
    double sum = 0, sum2 = 0;
    for (const Rgb& p : r.pixels) {
      sum += p[c];
      sum2 += double(p[c]) * p[c];
    }
    const double n = double(r.pixels.size()), mean = sum / n;
    const double sigma = std::sqrt((sum2 / n - mean * mean) / (n - 1));
    EXPECT_GT(sigma, 0);
    EXPECT_NEAR(mean, expected[c], 4 * sigma) << "channel " << c;
  }
}

}  // namespace
}  // namespace rt
