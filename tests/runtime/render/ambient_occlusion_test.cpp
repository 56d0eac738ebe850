// pbrt-v3's ambientocclusion integrator on a floor seen from above: an open
// floor returns pi (cosine-weighted visibility times pi, as pbrt-v3 outputs
// it), a floor beside a low wall less, nearest the wall least.
#include <gtest/gtest.h>

#include <cmath>

#include "runtime/film/film.h"
#include "runtime/render/camera.h"
#include "runtime/render/integrator.h"
#include "runtime/render/render_scene.h"
#include "runtime/render/renderer.h"
#include "runtime/runtime_test_support.h"
#include "runtime/sampler/sampler.h"
#include "test_support.h"

namespace rt {
namespace {

constexpr int kRes = 16;

// Mean luminance of each pixel column of the render (x = -1..1 over the film).
std::vector<double> render_columns(const std::string& name, const std::string& integrator,
                                   bool wall) {
  std::string text = R"(
LookAt 0 5 0  0 0 0  0 0 1
Camera "orthographic" "float screenwindow" [-1 1 -1 1]
Film "image" "integer xresolution" 16 "integer yresolution" 16
Sampler "halton" "integer pixelsamples" 4
)" + integrator + R"(
WorldBegin
Material "matte"
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
  "point P" [-10 0 -10  10 0 -10  10 0 10  -10 0 10]
)";
  if (wall)
    text += R"(Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
  "point P" [0 0 -10  0 0 10  0 0.5 10  0 0.5 -10]
)";
  text += "WorldEnd\n";
  std::vector<double> columns;
  pbrta::SceneArchive a;
  if (!testing_support::compile_text(testing_support::scratch_dir(name), text, &a)) return columns;
  Film film;
  Camera camera;
  IntegratorSettings settings;
  RenderScene scene;
  std::string error;
  bool ok = film.build(a, {}, &error) && camera.build(a, film.full_resolution(), &error) &&
            read_integrator(a, &settings, &error) && load_render_scene(a, &scene, &error);
  EXPECT_TRUE(ok) << error;
  if (!ok) return columns;
  std::unique_ptr<Sampler> sampler = make_sampler(a, 0, 0, film.sample_bounds(), &error);
  Integrator it;
  EXPECT_TRUE(it.init(scene, settings, &error)) << error;
  it.preprocess(sampler.get());
  RenderOptions ro;
  ro.quiet = true;
  render(camera, *sampler, it, &film, ro);
  columns.assign(kRes, 0);
  for (int y = 0; y < kRes; ++y)
    for (int x = 0; x < kRes; ++x) columns[size_t(x)] += film.pixel({x, y}).luminance() / kRes;
  return columns;
}

TEST(AmbientOcclusion, OpenFloorGivesPi) {
  // Cosine sampling: every unoccluded ray contributes cos / (cos / pi) = pi
  // exactly (a rare rim sample with pdf 0 adds nothing: 1/16 less at worst).
  std::vector<double> cos = render_columns(
      "ao_open_cos", R"(Integrator "ambientocclusion" "integer nsamples" 16)", false);
  ASSERT_EQ(cos.size(), size_t(kRes));
  for (int x = 0; x < kRes; ++x) EXPECT_NEAR(cos[size_t(x)], kPi, kPi / 256) << x;
  // Uniform sampling: pi on average, with noise.
  std::vector<double> uni = render_columns(
      "ao_open_uniform", R"(Integrator "ambientocclusion" "bool cossample" "false")", false);
  ASSERT_EQ(uni.size(), size_t(kRes));
  double mean = 0;
  for (double c : uni) mean += c / kRes;
  EXPECT_NEAR(mean, kPi, 0.02 * kPi);
}

TEST(AmbientOcclusion, FloorBesideAWallIsDarkerNearIt) {
  std::vector<double> c =
      render_columns("ao_wall", R"(Integrator "ambientocclusion" "integer nsamples" 32)", true);
  ASSERT_EQ(c.size(), size_t(kRes));
  // A wall 0.5 high at x = 0: beside it (1/16 away) it hides nearly half the
  // cosine-weighted hemisphere; 15/16 away much less.
  for (int x : {7, 8}) {
    EXPECT_GT(c[size_t(x)], 0.45 * kPi) << x;
    EXPECT_LT(c[size_t(x)], 0.6 * kPi) << x;
  }
  for (int x : {0, 15}) {
    EXPECT_GT(c[size_t(x)], c[7] + 0.1 * kPi) << x;
    EXPECT_LT(c[size_t(x)], 0.97 * kPi) << x;
  }
}

TEST(AmbientOcclusion, ReadsItsParameters) {
  pbrta::SceneArchive a;
  ASSERT_TRUE(testing_support::compile_text(testing_support::scratch_dir("ao_params"), R"(
Camera "perspective"
Integrator "ambientocclusion" "bool cossample" "false" "integer nsamples" 7
WorldBegin
WorldEnd
)",
                                            &a));
  IntegratorSettings s;
  std::string error;
  ASSERT_TRUE(read_integrator(a, &s, &error)) << error;
  EXPECT_EQ(s.type, IntegratorType::kAmbientOcclusion);
  EXPECT_FALSE(s.cos_sample);
  EXPECT_EQ(s.ao_samples, 7);
}

}  // namespace
}  // namespace rt
