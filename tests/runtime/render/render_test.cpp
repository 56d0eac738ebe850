// Whole renders of small real scenes: thread-count independence, seeds,
// analytic answers (a furnace), spp and crop overrides, unsupported features.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

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

struct Rendered {
  bool ok = false;
  std::string error;
  std::vector<Rgb> pixels;
  Bounds2i bounds;
  RenderStats stats;
};

Rendered render_text(const std::string& name, const std::string& text, int threads,
                     uint64_t seed = 0, int spp = 0, FilmOptions fo = {}) {
  Rendered out;
  pbrta::SceneArchive a;
  if (!testing_support::compile_text(testing_support::scratch_dir(name), text, &a)) return out;
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
  Film film;
  Camera camera;
  IntegratorSettings settings;
  RenderScene scene;
  if (!film.build(a, fo, &out.error)) return out;
  camera.set_sample_bounds(film.sample_bounds());
  if (!camera.build(a, film.full_resolution(), &out.error) ||
      !read_integrator(a, &settings, &out.error) || !load_render_scene(a, &scene, &out.error))
    return out;
  std::unique_ptr<Sampler> sampler = make_sampler(a, spp, seed, film.sample_bounds(), &out.error);
  if (!sampler) return out;
  Integrator integrator;
  if (!integrator.init(scene, settings, &out.error, &camera, &film)) return out;
  integrator.preprocess(sampler.get());
  RenderOptions ro;
  ro.quiet = true;
  out.stats = render(camera, *sampler, integrator, &film, ro);
  out.bounds = film.cropped_pixel_bounds();
  for (int y = out.bounds.min.y; y < out.bounds.max.y; ++y)
    for (int x = out.bounds.min.x; x < out.bounds.max.x; ++x)
      out.pixels.push_back(film.pixel({x, y}));
  out.ok = true;
  return out;
}

const char* kSpheres = R"(
LookAt 0 0 5  0 0 0  0 1 0
Camera "perspective" "float fov" 40
Film "image" "integer xresolution" 48 "integer yresolution" 32
Sampler "halton" "integer pixelsamples" 8
Integrator "path" "integer maxdepth" 4
WorldBegin
LightSource "infinite" "rgb L" [0.3 0.3 0.35]
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [4 4 4]
  Translate 0 3 0
  Shape "sphere" "float radius" 0.5
AttributeEnd
Material "plastic" "rgb Kd" [0.4 0.2 0.1] "rgb Ks" [0.3 0.3 0.3] "float roughness" 0.05
Shape "sphere" "float radius" 1
Material "matte" "rgb Kd" [0.5 0.5 0.5]
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
  "point P" [-5 -1 -5  5 -1 -5  5 -1 5  -5 -1 5]
WorldEnd
)";

TEST(Render, SameImageForAnyThreadCount) {
  Rendered one = render_text("render_threads1", kSpheres, 1, 7);
  Rendered two = render_text("render_threads2", kSpheres, 2, 7);
  ASSERT_TRUE(one.ok) << one.error;
  ASSERT_TRUE(two.ok) << two.error;
  ASSERT_EQ(one.pixels.size(), two.pixels.size());
  for (size_t i = 0; i < one.pixels.size(); ++i) {
    ASSERT_EQ(one.pixels[i], two.pixels[i]) << "pixel " << i;
  }
  EXPECT_EQ(one.stats.samples, 48u * 32u * 8u);
}

// A camera sample's time is drawn only where something moves, its lens point only for a lens:
// other scenes skip those dimensions (pbrt-v3 draws them and reads nothing).
TEST(Render, CameraSamplesDrawOnlyWhatTheSceneReads) {
  struct Case {
    const char* name;
    const char* camera;
    const char* world;
    bool time, lens;
  };
  const Case cases[] = {
      {"pinhole", R"(Camera "perspective")", "", false, false},
      {"thin_lens", R"(Camera "perspective" "float lensradius" 0.1 "float focaldistance" 3)", "",
       false, true},
      {"ortho_lens", R"(Camera "orthographic" "float lensradius" 0.1)", "", false, true},
      {"environment", R"(Camera "environment")", "", false, false},
      {"moving_camera",
       "ActiveTransform EndTime\nTranslate 0 0 1\nActiveTransform All\nCamera \"perspective\"", "",
       true, false},
      {"moving_shape", R"(Camera "perspective")",
       "ActiveTransform EndTime\nTranslate 0 1 0\nActiveTransform All\n", true, false},
  };
  for (const Case& c : cases) {
    pbrta::SceneArchive a;
    const std::string text = std::string("LookAt 0 0 5  0 0 0  0 1 0\n") + c.camera +
                             "\nWorldBegin\n" + c.world + "Shape \"sphere\"\nWorldEnd\n";
    ASSERT_TRUE(testing_support::compile_text(
        testing_support::scratch_dir(std::string("sample_use_") + c.name), text, &a))
        << c.name;
    Camera camera;
    std::string error;
    ASSERT_TRUE(camera.build(a, {32, 32}, &error)) << c.name << ": " << error;
    const CameraSampleUse use = camera.sample_use(a.header().effects);
    EXPECT_EQ(use.time, c.time) << c.name;
    EXPECT_EQ(use.lens, c.lens) << c.name;
  }
}

TEST(Render, SeedChangesTheNoiseNotTheImage) {
  Rendered a = render_text("render_seed1", kSpheres, 2, 1);
  Rendered b = render_text("render_seed2", kSpheres, 2, 2);
  ASSERT_TRUE(a.ok && b.ok) << a.error << b.error;
  int differ = 0;
  double sum_a = 0, sum_b = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    differ += a.pixels[i] != b.pixels[i];
    sum_a += a.pixels[i].average();
    sum_b += b.pixels[i].average();
  }
  EXPECT_GT(differ, int(a.pixels.size() / 4));
  EXPECT_NEAR(sum_a / sum_b, 1.0, 0.05);
}

// A white furnace: a diffuse sphere of albedo 0.5 under a uniform environment
// of radiance 1 reflects exactly 0.5 everywhere (it is convex: no
// interreflection), and the background is 1.
TEST(Render, FurnaceSphereReflectsItsAlbedo) {
  for (const char* integrator : {"path", "directlighting"}) {
    std::string text = std::string(R"(
LookAt 0 0 5  0 0 0  0 1 0
Camera "perspective" "float fov" 20
Film "image" "integer xresolution" 32 "integer yresolution" 32
Sampler "sobol" "integer pixelsamples" 64
Integrator ")") + integrator +
                       R"("
WorldBegin
LightSource "infinite" "rgb L" [1 1 1]
Material "matte" "rgb Kd" [0.5 0.5 0.5]
Shape "sphere" "float radius" 1
WorldEnd
)";
    Rendered r = render_text(std::string("render_furnace_") + integrator, text, 2);
    ASSERT_TRUE(r.ok) << r.error;
    // Pixel (16,16) looks at the sphere's centre; (1,1) at the background.
    Rgb centre = r.pixels[16 * 32 + 16], corner = r.pixels[1 * 32 + 1];
    EXPECT_NEAR(centre.g, 0.5, 0.03) << integrator;
    EXPECT_NEAR(corner.g, 1.0, 1e-4) << integrator;
  }
}

// A floor exactly on y = 0 has a zero error bound along its normal, so
// shadow rays start exactly on it; they must not hit it again. Every floor
// pixel sees the light: its value is Kd/pi * I cos / r^2 > 0.
TEST(Render, FloorOnAnAxisPlaneIsNotSelfShadowed) {
  Rendered r = render_text("render_floor", R"(
LookAt 0 1.2 -4.5   0 0.6 0   0 1 0
Camera "perspective" "float fov" 42
Film "image" "integer xresolution" 32 "integer yresolution" 24
Sampler "halton" "integer pixelsamples" 4
Integrator "directlighting"
WorldBegin
LightSource "point" "point from" [0 2 0] "rgb I" [5 5 5]
Material "matte" "rgb Kd" [0.5 0.5 0.5]
Shape "trianglemesh" "point P" [-4 0 -4   4 0 -4   4 0 4   -4 0 4]
  "integer indices" [0 1 2  0 2 3]
WorldEnd
)",
                           2);
  ASSERT_TRUE(r.ok) << r.error;
  for (int y = 14; y < 24; ++y)
    for (int x = 0; x < 32; ++x) EXPECT_GT(r.pixels[y * 32 + x].g, 0.f) << x << "," << y;
}

TEST(Render, CropWindowRendersOnlyItsPixels) {
  FilmOptions fo;
  fo.has_crop = true;
  fo.crop[0] = 0.25f;
  fo.crop[1] = 0.75f;
  fo.crop[2] = 0;
  fo.crop[3] = 0.5f;
  Rendered crop = render_text("render_crop", kSpheres, 2, 3, 0, fo);
  Rendered full = render_text("render_full", kSpheres, 2, 3);
  ASSERT_TRUE(crop.ok && full.ok) << crop.error << full.error;
  EXPECT_EQ(crop.bounds.width(), 24);
  EXPECT_EQ(crop.bounds.height(), 16);
  EXPECT_EQ(crop.pixels.size(), 24u * 16u);
  EXPECT_LT(crop.stats.samples, full.stats.samples / 2);
}

TEST(Render, SppOverrideSetsTheSampleCount) {
  Rendered r = render_text("render_spp", kSpheres, 2, 0, 2);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.stats.samples, 48u * 32u * 2u);
}

// Every integrator pbrt-v3 has is read, with its own defaults (pbrtc refuses unknown names).
TEST(Render, EveryPbrtIntegratorIsRead) {
  for (const char* name : {"whitted", "directlighting", "path", "volpath", "bdpt", "mlt", "sppm",
                           "ambientocclusion"}) {
    pbrta::SceneArchive a;
    ASSERT_TRUE(testing_support::compile_text(
        testing_support::scratch_dir(std::string("render_integrator_") + name),
        std::string("Camera \"perspective\"\nIntegrator \"") + name +
            "\"\nWorldBegin\nShape \"sphere\"\nWorldEnd\n",
        &a));
    IntegratorSettings s;
    std::string error;
    EXPECT_TRUE(read_integrator(a, &s, &error)) << name << ": " << error;
  }
}

}  // namespace
}  // namespace rt
