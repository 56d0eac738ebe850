// Scenes far from the origin and at extreme scales render as the unit scene
// does. Each case wraps the whole scene (camera included) in the same
// similarity transform: scale s, a rotation, and an offset chosen so that
// float spacing at the offset is about 1/1000 of the scene's size (offsets
// 1e3..1e7 for scenes of size 0.1..1e3), or a pure scale of 1e-4 or 1e4.
// Radiance is invariant under that transform (lights are distant or
// infinite), so the image must not change beyond noise.
#include <gtest/gtest.h>

#include <cmath>

#include "stability_support.h"

namespace rt {
namespace {

struct Placement {
  const char* name;
  double scale, offset;
};

// offset / scale ~ 8000: the float spacing at the offset is ~1/1000 of the
// scene's ~1-unit-times-scale size.
const Placement kPlacements[] = {
    {"unit", 1, 0},         {"tiny", 1e-4, 0},     {"huge", 1e4, 0},
    {"far1e3", 0.125, 1e3}, {"far1e5", 12.5, 1e5}, {"far1e7", 1250, 1e7},
};

// Camera and world in scene units, mapped to world by T(offset) R S(scale).
// `lights` go under the rigid part only: pbrt-v3's infinite light does not
// normalize directions through its transform, so a scaled one is another
// light (its Sample_Li/Pdf_Li use the unnormalized vectors; this renderer
// matches pbrt-v3 there). `body` is the geometry in scene units.
std::string placed_scene(const Placement& p, const std::string& header, const std::string& lights,
                         const std::string& body) {
  const double ox = p.offset, oy = -0.7 * p.offset, oz = 0.4 * p.offset;
  const char* axis = " 0.2 1 0.3\n";
  // pbrt post-multiplies: CTM = LookAt S^-1 R^-1 T^-1, camera-from-world of the moved scene.
  std::string text = "LookAt 0 3 -2.5  0 0 0.5  0 1 0\n";
  text += "Scale " + fmt(1 / p.scale) + " " + fmt(1 / p.scale) + " " + fmt(1 / p.scale) + "\n";
  text += std::string("Rotate -30") + axis;
  text += "Translate " + fmt(-ox) + " " + fmt(-oy) + " " + fmt(-oz) + "\n";
  text += header;
  text += "WorldBegin\n";
  text += "Translate " + fmt(ox) + " " + fmt(oy) + " " + fmt(oz) + "\n";
  text += std::string("Rotate 30") + axis;
  text += lights;
  text += "Scale " + fmt(p.scale) + " " + fmt(p.scale) + " " + fmt(p.scale) + "\n";
  text += body;
  text += "WorldEnd\n";
  return text;
}

const char* kPlane = R"(
Material "matte" "rgb Kd" [0.5 0.5 0.5]
Shape "trianglemesh" "point P" [-20 0 -20  20 0 -20  20 0 20  -20 0 20]
  "integer indices" [0 1 2  0 2 3]
)";

// A diffuse plane lit by a distant light of radiance-scale L = 3 from
// direction (1, 4, 2): every visible point has radiance Kd/pi * L * cos,
// cos = 4/sqrt(21). The camera sees nothing but the plane. A single
// self-shadowed shadow ray makes a pixel darker (acne).
TEST(FarAndScaled, PlaneUnderDistantLightHasTheAnalyticRadiance) {
  const std::string header = R"(Camera "perspective" "float fov" 45
Film "image" "integer xresolution" 32 "integer yresolution" 24
Sampler "random" "integer pixelsamples" 4
Integrator "directlighting"
)";
  const std::string lights =
      "LightSource \"distant\" \"point from\" [1 4 2] \"point to\" [0 0 0] \"rgb L\" [3 3 3]\n";
  const double expected = 0.5 / kPi * 3 * 4 / std::sqrt(21.0);
  for (const Placement& p : kPlacements) {
    Rendered r =
        render_text(std::string("far_plane_") + p.name, placed_scene(p, header, lights, kPlane), 1);
    ASSERT_TRUE(r.ok) << p.name;
    int off = 0;
    double worst = 0;
    for (const Rgb& px : r.pixels) {
      double e = std::fabs(px.g - expected) / expected;
      worst = std::max(worst, e);
      off += !(e < 1e-3);
    }
    EXPECT_EQ(off, 0) << p.name << ": pixels off the analytic " << expected << " by > 0.1% (worst "
                      << worst << ")";
    EXPECT_EQ(r.stats.nonfinite_samples, 0u) << p.name;
  }
}

// A plane, a quadric sphere and a mesh box under a distant and a dim
// infinite light, path traced (indirect light, shadows, contact between
// shapes). Translated/scaled renders are compared with the unit render: the
// image mean within 4 standard errors, and the RMS pixel difference no larger
// than the difference between two seeds of the unit scene (the noise).
TEST(FarAndScaled, ImageMatchesTheUnitSceneWithinNoise) {
  const std::string header = R"(Camera "perspective" "float fov" 45
Film "image" "integer xresolution" 32 "integer yresolution" 24
Sampler "random" "integer pixelsamples" 16
Integrator "path" "integer maxdepth" 3
)";
  const std::string lights = R"(
LightSource "distant" "point from" [1 4 2] "point to" [0 0 0] "rgb L" [3 3 3]
LightSource "infinite" "rgb L" [0.3 0.3 0.3]
)";
  const std::string body = std::string(R"(
AttributeBegin
  Translate 0.6 0.5 0.8
  Material "plastic" "rgb Kd" [0.3 0.4 0.5] "rgb Ks" [0.3 0.3 0.3] "float roughness" 0.05
  Shape "sphere" "float radius" 0.5
AttributeEnd
AttributeBegin
  Translate -0.8 0 0.6
  Rotate 20 0 1 0
  Material "matte" "rgb Kd" [0.7 0.3 0.2]
  Shape "trianglemesh" "point P" [-0.3 0 -0.3  0.3 0 -0.3  0.3 0 0.3  -0.3 0 0.3
                                  -0.3 0.6 -0.3  0.3 0.6 -0.3  0.3 0.6 0.3  -0.3 0.6 0.3]
    "integer indices" [0 2 1 0 3 2  4 5 6 4 6 7  0 1 5 0 5 4  1 2 6 1 6 5  2 3 7 2 7 6  3 0 4 3 4 7]
AttributeEnd
)") + kPlane;
  Rendered ref =
      render_text("far_match_ref1", placed_scene(kPlacements[0], header, lights, body), 1);
  Rendered ref2 =
      render_text("far_match_ref2", placed_scene(kPlacements[0], header, lights, body), 2);
  ASSERT_TRUE(ref.ok && ref2.ok);
  const size_t n = ref.pixels.size();
  double noise_ms = 0;
  for (size_t i = 0; i < n; ++i) {
    double d = ref.pixels[i].average() - ref2.pixels[i].average();
    noise_ms += d * d;
  }
  const double noise_rms = std::sqrt(noise_ms / double(n));
  // Per-pixel sd of one render is noise_rms / sqrt(2); the mean of a
  // difference of two independent renders has sd noise_rms / sqrt(n).
  const double sigma_mean_diff = noise_rms / std::sqrt(double(n));
  ASSERT_GT(noise_rms, 0);
  const double ref_mean = mean_and_error(ref).mean;
  for (size_t k = 1; k < std::size(kPlacements); ++k) {
    const Placement& p = kPlacements[k];
    Rendered r =
        render_text(std::string("far_match_") + p.name, placed_scene(p, header, lights, body), 3);
    ASSERT_TRUE(r.ok) << p.name;
    EXPECT_EQ(count_nonfinite(r), 0) << p.name;
    EXPECT_EQ(r.stats.nonfinite_samples, 0u) << p.name;
    double ms = 0;
    for (size_t i = 0; i < n; ++i) {
      double d = r.pixels[i].average() - ref.pixels[i].average();
      ms += d * d;
    }
    const double rms = std::sqrt(ms / double(n));
    const double mean = mean_and_error(r).mean;
    EXPECT_NEAR(mean, ref_mean, 4 * sigma_mean_diff) << p.name;
    EXPECT_LT(rms, 1.25 * noise_rms) << p.name << " (noise rms " << noise_rms << ")";
  }
}

}  // namespace
}  // namespace rt
