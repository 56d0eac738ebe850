// pbrt-v3's bdpt against the path tracer on scenes both render without bias: the same
// image within noise (every strategy, MIS-weighted, sums to the same estimate); light
// tracing's splats land where the camera sees the light; unsupported input is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "box_scene.h"
#include "runtime/render/bdpt.h"
#include "runtime/render_text.h"

namespace rt {
namespace {

// The box with a point light and glossy surfaces (no delta chains that only one of the
// integrators could sample).
std::string box(const char* integrator, const std::string& params = " \"integer maxdepth\" [5]") {
  return box_scene(std::string("Integrator \"") + integrator + "\"" + params, true, true);
}

TEST(Bdpt, AgreesWithThePathTracer) {
  Rendered path = render_text("bdpt_box_path", box("path"));
  Rendered bdpt = render_text("bdpt_box_bdpt", box("bdpt"));
  ASSERT_TRUE(path.ok && bdpt.ok);
  // The whole image and each quadrant (walls, floor, ceiling light, sphere).
  for (int q = 0; q < 5; ++q) {
    int x0 = q == 4 ? 0 : (q % 2) * 12, y0 = q == 4 ? 0 : (q / 2) * 12;
    int x1 = q == 4 ? 24 : x0 + 12, y1 = q == 4 ? 24 : y0 + 12;
    double a = mean_luminance(path, x0, x1, y0, y1), b = mean_luminance(bdpt, x0, x1, y0, y1);
    EXPECT_NEAR(b / a, 1, 0.03) << "region " << q << ": path " << a << ", bdpt " << b;
  }
  EXPECT_EQ(bdpt.stats.nonfinite_samples, 0u);
}

// A point light over a diffuse floor: much of the image comes from light tracing (t = 1)
// splats, which sum over all samples of all pixels; scaled by 1 / spp, the image is the same
// at 16 and 64 samples per pixel.
TEST(Bdpt, SplatsAreScaledPerSample) {
  const std::string scene = R"(
LookAt 0 3 -3  0 0 0  0 1 0
Camera "perspective" "float fov" [40]
Film "image" "integer xresolution" [16] "integer yresolution" [16]
Sampler "02sequence" "integer pixelsamples" [16]
Integrator "bdpt" "integer maxdepth" [4]
WorldBegin
LightSource "point" "point from" [0 3 0] "rgb I" [5 5 5]
Material "matte" "rgb Kd" [0.5 0.5 0.5]
Shape "trianglemesh" "point P" [-5 0 -5  5 0 -5  5 0 5  -5 0 5] "integer indices" [0 2 1 0 3 2]
WorldEnd
)";
  Rendered a = render_text("bdpt_splat_16", scene, 0, 16);
  Rendered b = render_text("bdpt_splat_64", scene, 0, 64);
  ASSERT_TRUE(a.ok && b.ok);
  double la = mean_luminance(a, 0, 16, 0, 16), lb = mean_luminance(b, 0, 16, 0, 16);
  EXPECT_GT(la, 0.05);
  EXPECT_NEAR(lb / la, 1, 0.05);
}

// visualizeweights: each strategy's MIS-weighted contributions in an image of its own; with
// the box filter they add up to the render itself, pixel by pixel.
TEST(Bdpt, WeightedStrategyImagesAddUpToTheRender) {
  const std::string text =
      box("bdpt", " \"integer maxdepth\" [3] \"bool visualizeweights\" \"true\"");
  std::unique_ptr<KeptRender> k = render_kept("bdpt_weights", text, 0, 16);
  ASSERT_TRUE(k->result.ok);
  ASSERT_TRUE(k->settings.bdpt_visualize_weights);
  const Integrator& integrator = k->integrator;
  const Film& film = k->film;
  int images = 0;
  for (int depth = 0; depth <= 3; ++depth)
    for (int s = 0; s <= depth + 2; ++s)
      images += integrator.bdpt()->strategy_film(s, depth + 2 - s) != nullptr;
  EXPECT_EQ(images, 1 + 3 + 4 + 5);  // depths 0 to 3: t >= 1, and never s = t = 1
  double total = 0;
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 24; ++x) {
      Rgb sum;
      for (int depth = 0; depth <= 3; ++depth)
        for (int s = 0; s <= depth + 2; ++s)
          if (const Film* f = integrator.bdpt()->strategy_film(s, depth + 2 - s))
            sum += f->pixel({x, y});
      Rgb whole = film.pixel({x, y});
      total += whole.luminance();
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum[c], whole[c], 1e-4f + 1e-4f * whole[c]);
    }
  EXPECT_GT(total, 0);
}

TEST(Bdpt, RefusesWhatItCannotRender) {
  pbrta::SceneArchive a;
  ASSERT_TRUE(testing_support::compile_text(testing_support::scratch_dir("bdpt_ortho"), R"(
Camera "orthographic"
Integrator "bdpt"
WorldBegin
Shape "sphere"
WorldEnd
)",
                                            &a));
  Film film;
  Camera camera;
  IntegratorSettings settings;
  RenderScene scene;
  std::string error;
  ASSERT_TRUE(film.build(a, FilmOptions{}, &error)) << error;
  ASSERT_TRUE(camera.build(a, film.full_resolution(), &error)) << error;
  ASSERT_TRUE(read_integrator(a, &settings, &error)) << error;
  ASSERT_TRUE(load_render_scene(a, &scene, &error)) << error;
  Integrator integrator;
  EXPECT_FALSE(integrator.init(scene, settings, &error, &camera, &film));
  EXPECT_NE(error.find("bdpt needs a perspective camera"), std::string::npos) << error;
  EXPECT_FALSE(integrator.init(scene, settings, &error));
  EXPECT_NE(error.find("bdpt needs the camera and the film"), std::string::npos) << error;
}

}  // namespace
}  // namespace rt
