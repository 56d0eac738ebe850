// Extreme radiance: tiny lights of radiance 1e6 give the analytic
// irradiance and finite float32 pixels, and the film's maxsampleluminance
// clamp behaves as pbrt-v3's: a sample whose luminance exceeds the maximum
// is scaled (all channels alike) so its luminance equals it.
#include <gtest/gtest.h>

#include <cfloat>
#include <cstdio>

#include "stability_support.h"

namespace rt {
namespace {

// Looking straight down at a matte plane under a sphere light of radius r
// and radiance Le at height 1: the point below sees the sphere fill a cone
// of sin^2 = r^2, so its radiance is Kd/pi * pi Le r^2 = Kd Le r^2.
std::string tiny_light_scene(double radius, double le, const char* integrator) {
  return std::string(R"(
LookAt 0 0.5 0  0 0 0  0 0 1
Camera "perspective" "float fov" 4
Film "image" "integer xresolution" 8 "integer yresolution" 8
Sampler "random" "integer pixelsamples" 64
)") + integrator +
         R"(
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [)" +
         fmt(le) + " " + fmt(le) + " " + fmt(le) + R"(]
  Translate 0 1 0
  Shape "sphere" "float radius" )" +
         fmt(radius) + R"(
AttributeEnd
Material "matte" "rgb Kd" [0.5 0.5 0.5]
Shape "trianglemesh" "point P" [-5 0 -5  5 0 -5  5 0 5  -5 0 5] "integer indices" [0 1 2 0 2 3]
WorldEnd
)";
}

TEST(ExtremeRadiance, TinyBrightSphereLightGivesTheAnalyticIrradiance) {
  struct Case {
    double radius, le, tolerance;
  };
  // At r = 1e-3 the cone's 1 - cos(theta_max) = 5e-7 is computed in float,
  // as pbrt-v3 computes it (1 - sin^2 then sqrt): ~5% error in the pdf,
  // +7.3% measured here. pbrt-v3 has the same bias; pbrt-v4 switched to a
  // Taylor expansion for small cones. Kept as pbrt-v3 for convergence.
  const Case cases[] = {{1e-2, 1e4, 0.01}, {1e-3, 1e6, 0.10}};
  for (const char* integrator : {"Integrator \"directlighting\"", "Integrator \"path\""}) {
    for (const Case& c : cases) {
      Rendered r =
          render_text("extreme_tiny_light", tiny_light_scene(c.radius, c.le, integrator), 3);
      ASSERT_TRUE(r.ok);
      EXPECT_EQ(count_nonfinite(r), 0);
      EXPECT_EQ(r.stats.nonfinite_samples, 0u);
      const double expected = 0.5 * c.le * c.radius * c.radius;
      MeanAndError e = mean_and_error(r);
      std::printf("[ extreme ] %s r=%g Le=%g: mean %.5f (analytic %.5f, %+.2f%%)\n", integrator,
                  c.radius, c.le, e.mean, expected, 100 * (e.mean / expected - 1));
      EXPECT_NEAR(e.mean, expected, c.tolerance * expected + 4 * e.sigma)
          << integrator << " r=" << c.radius;
    }
  }
}

// The camera looks at a big sphere light of radiance (4e6, 2e6, 1e6)
// (and a grey one of 1e30) over a floor. Unclamped, covered
// pixels are exactly Le; clamped at 10, they are Le * 10 / luminance(Le),
// and no pixel anywhere exceeds luminance 10.
std::string bright_view_scene(Rgb le, const char* film_extra) {
  return std::string(R"(
LookAt 0 0 4  0 0 0  0 1 0
Camera "perspective" "float fov" 30
Film "image" "integer xresolution" 16 "integer yresolution" 16 )") +
         film_extra + R"(
Sampler "random" "integer pixelsamples" 16
Integrator "path" "integer maxdepth" 5
WorldBegin
AttributeBegin
  Material "matte" "rgb Kd" [0 0 0]
  AreaLightSource "diffuse" "rgb L" [)" +
         fmt(le.r) + " " + fmt(le.g) + " " + fmt(le.b) + R"(]
  Shape "sphere" "float radius" 1
AttributeEnd
Material "matte" "rgb Kd" [0.5 0.5 0.5]
Shape "trianglemesh" "point P" [-5 -1.2 -5  5 -1.2 -5  5 -1.2 5  -5 -1.2 5] "integer indices" [0 1 2 0 2 3]
WorldEnd
)";
}

TEST(ExtremeRadiance, MaxSampleLuminanceScalesSamplesAsPbrtV3) {
  for (Rgb le : {Rgb(4e6f, 2e6f, 1e6f), Rgb(1e30f)}) {
    const double lum = le.luminance();
    Rendered free = render_text("extreme_unclamped", bright_view_scene(le, ""), 4);
    Rendered clamped =
        render_text("extreme_clamped", bright_view_scene(le, "\"float maxsampleluminance\" 10"), 4);
    ASSERT_TRUE(free.ok && clamped.ok);
    EXPECT_EQ(count_nonfinite(free), 0);
    EXPECT_EQ(count_nonfinite(clamped), 0);
    EXPECT_EQ(free.stats.nonfinite_samples, 0u);
    EXPECT_EQ(clamped.stats.nonfinite_samples, 0u);
    // Pixel (8, 8) is well inside the sphere's disk (radius ~ 7.5 pixels); the
    // light's own material is black, so it shows exactly its emission.
    const Rgb c = free.at(8, 8), k = clamped.at(8, 8);
    EXPECT_NEAR(c.r, le.r, 1e-6 * le.r);
    EXPECT_NEAR(c.b, le.b, 1e-6 * le.b);
    const double s = 10 / lum;
    EXPECT_NEAR(k.r, le.r * s, 1e-5 * le.r * s);
    EXPECT_NEAR(k.g, le.g * s, 1e-5 * le.g * s);
    EXPECT_NEAR(k.b, le.b * s, 1e-5 * le.b * s);
    float brightest = 0;
    for (const Rgb& p : clamped.pixels) brightest = std::max(brightest, p.luminance());
    EXPECT_LE(brightest, 10 * (1 + 1e-5));
    EXPECT_GT(brightest, 9.99);
    // The floor, lit by the light, is clamped too but stays lit.
    EXPECT_GT(clamped.at(0, 15).luminance(), 0);
    EXPECT_LT(free.at(0, 15).luminance(), FLT_MAX);
  }
}

}  // namespace
}  // namespace rt
