// tests/runtime/render_text.h — render generated scene text in-process.
//
// render_text() compiles pbrt-v3 text with pbrtc's front end and renders it
// through the same pieces pbrtrun uses (film, camera, integrator, Embree
// scene, sampler), then reads the film's pixels back: for tests that assert
// on whole images (tests/runtime/stability, the material furnace renders).
// furnace_scene() is the materials' white furnace: one object lit only by a
// constant infinite light of radiance 1, path traced. mean_luminance() averages a rectangle of
// a render's pixels.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "runtime/core/rgb.h"
#include "runtime/film/film.h"
#include "runtime/render/camera.h"
#include "runtime/render/integrator.h"
#include "runtime/render/render_job.h"
#include "runtime/render/render_scene.h"
#include "runtime/render/renderer.h"
#include "runtime/runtime_test_support.h"
#include "runtime/sampler/sampler.h"
#include "test_support.h"

namespace rt {

struct Rendered {
  bool ok = false;
  std::string error;
  int width = 0, height = 0;
  std::vector<Rgb> pixels;  // row-major over the cropped film
  RenderStats stats;
  const Rgb& at(int x, int y) const { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
};

// Everything a render used, kept for inspection (bdpt's strategy images); not movable: the
// integrator points into the scene, camera and film.
struct KeptRender {
  Rendered result;
  pbrta::SceneArchive archive;
  Film film;
  Camera camera;
  IntegratorSettings settings;
  RenderScene scene;
  Integrator integrator;
};

// Compiles `text` under a fresh scratch directory named `name` and renders it;
// spp > 0 overrides the scene's sample count. Fails the calling test on any error.
inline std::unique_ptr<KeptRender> render_kept(const std::string& name, const std::string& text,
                                               uint64_t seed = 0, int spp = 0) {
  auto k = std::make_unique<KeptRender>();
  Rendered& out = k->result;
  if (!testing_support::compile_text(testing_support::scratch_dir(name), text, &k->archive))
    return k;
  const pbrta::SceneArchive& a = k->archive;
  bool film_ok = k->film.build(a, FilmOptions{}, &out.error);
  if (film_ok) k->camera.set_sample_bounds(k->film.sample_bounds());
  if (!film_ok || !k->camera.build(a, k->film.full_resolution(), &out.error) ||
      !read_integrator(a, &k->settings, &out.error) ||
      !load_render_scene(a, &k->scene, &out.error)) {
    ADD_FAILURE() << name << ": " << out.error;
    return k;
  }
  std::unique_ptr<Sampler> sampler =
      make_sampler(a, spp, seed, k->film.sample_bounds(), &out.error);
  if (!sampler || !k->integrator.init(k->scene, k->settings, &out.error, &k->camera, &k->film)) {
    ADD_FAILURE() << name << ": " << out.error;
    return k;
  }
  k->integrator.preprocess(sampler.get());
  RenderOptions ro;
  ro.quiet = true;
  long long rendered_spp = 0;
  if (!render_integrator(k->scene, k->camera, *sampler, k->integrator, &k->film, spp, seed, false,
                         ro, &out.stats, &rendered_spp, &out.error)) {
    ADD_FAILURE() << name << ": " << out.error;
    return k;
  }
  Bounds2i b = k->film.cropped_pixel_bounds();
  out.width = b.width();
  out.height = b.height();
  for (int y = b.min.y; y < b.max.y; ++y)
    for (int x = b.min.x; x < b.max.x; ++x) out.pixels.push_back(k->film.pixel({x, y}));
  out.ok = true;
  return k;
}

inline Rendered render_text(const std::string& name, const std::string& text, uint64_t seed = 0,
                            int spp = 0) {
  return render_kept(name, text, seed, spp)->result;
}

// `material_line` on `shape_line` (radius 1 at the origin fills most of the
// 32x32 image) under a constant infinite light of radiance 1; sobol, 64 spp,
// path integrator with maxdepth 10.
// The mean luminance of pixels [x0, x1) x [y0, y1) of a render.
inline double mean_luminance(const Rendered& r, int x0, int x1, int y0, int y1) {
  double sum = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) sum += r.at(x, y).luminance();
  return sum / ((x1 - x0) * (y1 - y0));
}

inline std::string furnace_scene(const std::string& material_line, const std::string& shape_line) {
  return R"(
LookAt 0 0 5  0 0 0  0 1 0
Camera "perspective" "float fov" 30
Film "image" "integer xresolution" 32 "integer yresolution" 32
Sampler "sobol" "integer pixelsamples" 64
Integrator "path" "integer maxdepth" 10
WorldBegin
LightSource "infinite" "rgb L" [1 1 1]
)" + material_line +
         "\n" + shape_line + R"(
WorldEnd
)";
}

}  // namespace rt
