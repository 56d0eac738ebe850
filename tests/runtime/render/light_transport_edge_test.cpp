// The bidirectional integrators on degenerate configurations (a light shut in a closed box,
// a camera inside glass, a zero-area light) finish with finite images and count what they
// drop; and light tracing alone (bdpt's s = 2, t = 1 strategy, unweighted) against the
// analytic radiance of a diffuse plane under a point light.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "runtime/render/bdpt.h"
#include "runtime/render_text.h"

namespace rt {
namespace {

std::string with_integrator(const std::string& world, const char* integrator) {
  return std::string(R"(
LookAt 0 1 -3  0 1 0  0 1 0
Camera "perspective" "float fov" [50]
Film "image" "integer xresolution" [16] "integer yresolution" [16]
Sampler "02sequence" "integer pixelsamples" [8]
Integrator ")") +
         integrator + "\" \"integer maxdepth\" [4]" +
         (std::string(integrator) == "mlt"
              ? " \"integer bootstrapsamples\" [2000] \"integer chains\" [16]"
          : std::string(integrator) == "sppm" ? " \"float radius\" [0.2]"
                                              : "") +
         "\nWorldBegin\n" + world + "\nWorldEnd\n";
}

const char* kIntegrators[] = {"path", "bdpt", "mlt", "sppm"};

void expect_finite(const char* name, const std::string& world) {
  for (const char* integrator : kIntegrators) {
    SCOPED_TRACE(std::string(name) + " with " + integrator);
    Rendered r = render_text(std::string("edge_") + name + "_" + integrator,
                             with_integrator(world, integrator));
    ASSERT_TRUE(r.ok);
    for (const Rgb& p : r.pixels) ASSERT_TRUE(p.is_finite());
  }
}

TEST(LightTransportEdges, LightShutInAClosedBox) {
  expect_finite("closed_box", R"(
LightSource "point" "point from" [0 1 5] "rgb I" [10 10 10]
Material "matte"
AttributeBegin
  Translate 0 1 5
  ReverseOrientation
  Shape "sphere" "float radius" [0.5]
AttributeEnd
Shape "trianglemesh" "point P" [-5 0 -5  5 0 -5  5 0 10  -5 0 10] "integer indices" [0 2 1 0 3 2]
)");
}

TEST(LightTransportEdges, CameraInsideGlass) {
  expect_finite("camera_in_glass", R"(
LightSource "point" "point from" [0 3 0] "rgb I" [10 10 10]
AttributeBegin
  Material "glass"
  Translate 0 1 -3
  Shape "sphere" "float radius" [1]
AttributeEnd
Material "matte"
Shape "trianglemesh" "point P" [-5 0 -5  5 0 -5  5 0 10  -5 0 10] "integer indices" [0 2 1 0 3 2]
)");
}

TEST(LightTransportEdges, ZeroAreaLight) {
  expect_finite("zero_area_light", R"(
LightSource "point" "point from" [0 3 0] "rgb I" [10 10 10]
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [5 5 5]
  Shape "trianglemesh" "point P" [0 2 0  1 2 0  2 2 0] "integer indices" [0 1 2]
  Shape "sphere" "float radius" [0]
AttributeEnd
Material "matte"
Shape "trianglemesh" "point P" [-5 0 -5  5 0 -5  5 0 10  -5 0 10] "integer indices" [0 2 1 0 3 2]
)");
}

// Light tracing alone: a point light of intensity I at height h over a diffuse plane of
// reflectance R, seen from above. The plane's radiance at horizontal distance d from the
// light's foot is R / pi * I cos(theta) / r^2 with cos(theta) = h / r, r^2 = h^2 + d^2.
TEST(LightTransportEdges, LightTracingMatchesTheAnalyticPlane) {
  const std::string text = R"(
LookAt 0 4 0  0 0 0  0 0 1
Camera "perspective" "float fov" [40]
Film "image" "integer xresolution" [16] "integer yresolution" [16]
Sampler "02sequence" "integer pixelsamples" [1024]
Integrator "bdpt" "integer maxdepth" [1] "bool visualizestrategies" "true"
WorldBegin
LightSource "point" "point from" [0 1 0] "rgb I" [3 3 3]
Material "matte" "rgb Kd" [0.5 0.5 0.5]
Shape "trianglemesh" "point P" [-9 0 -9  9 0 -9  9 0 9  -9 0 9] "integer indices" [0 2 1 0 3 2]
WorldEnd
)";
  std::unique_ptr<KeptRender> k = render_kept("edge_lighttracing", text);
  ASSERT_TRUE(k->result.ok);
  const Integrator& integrator = k->integrator;
  const Film* tracing = integrator.bdpt()->strategy_film(2, 1);
  ASSERT_NE(tracing, nullptr);
  // Each pixel's centre ray meets the plane at (x, 0, z); tan(20 deg) * 4 spans half the image.
  const float half = 4 * std::tan(radians(20.f));
  // 4x4-pixel blocks: each pixel's own light-tracing noise is a few percent.
  double worst = 0;
  for (int by = 0; by < 16; by += 4)
    for (int bx = 0; bx < 16; bx += 4) {
      double expected = 0, got = 0;
      for (int py = by; py < by + 4; ++py)
        for (int px = bx; px < bx + 4; ++px) {
          // The analytic radiance averaged over the pixel (4x4 sub-points).
          for (int sy = 0; sy < 4; ++sy)
            for (int sx = 0; sx < 4; ++sx) {
              float u = (px + (sx + 0.5f) / 4) / 16, v = (py + (sy + 0.5f) / 4) / 16;
              float x = (1 - 2 * u) * half, z = (1 - 2 * v) * half;
              float r2 = 1 + x * x + z * z;
              expected += 0.5 / kPi * 3 * (1 / std::sqrt(r2)) / r2 / 16;
            }
          got += tracing->pixel({px, py}).g;
        }
      worst = std::max(worst, std::fabs(got / expected - 1));
    }
  EXPECT_LT(worst, 0.05) << "light tracing's worst block, relative to the analytic radiance";
}

}  // namespace
}  // namespace rt
