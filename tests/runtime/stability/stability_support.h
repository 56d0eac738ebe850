// tests/runtime/stability/stability_support.h — render generated scene text in-process.
//
// The numerical-stability tests (issue 9) build their scenes as pbrt-v3 text,
// compile them with pbrtc's front end and render them through the same
// pieces pbrtrun uses (film, camera, integrator, Embree scene, sampler), then
// read the film's pixels back. Helpers here summarise an image: finiteness of
// every pixel, mean and its standard error (pixels of an independent sampler
// under a box filter of radius 0.5 are independent estimates).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "runtime/core/rgb.h"
#include "runtime/film/film.h"
#include "runtime/render/camera.h"
#include "runtime/render/integrator.h"
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

// Compiles `text` under a fresh scratch directory named `name` and renders it;
// spp > 0 overrides the scene's sample count. Fails the calling test on any error.
inline Rendered render_text(const std::string& name, const std::string& text, uint64_t seed = 0,
                            int spp = 0) {
  Rendered out;
  pbrta::SceneArchive a;
  if (!testing_support::compile_text(testing_support::scratch_dir(name), text, &a)) return out;
  Film film;
  Camera camera;
  IntegratorSettings settings;
  auto scene = std::make_unique<RenderScene>();
  if (!film.build(a, FilmOptions{}, &out.error) ||
      !camera.build(a, film.full_resolution(), &out.error) ||
      !read_integrator(a, &settings, &out.error) ||
      !load_render_scene(a, scene.get(), &out.error)) {
    ADD_FAILURE() << name << ": " << out.error;
    return out;
  }
  std::unique_ptr<Sampler> sampler = make_sampler(a, spp, seed, film.sample_bounds(), &out.error);
  Integrator integrator;
  if (!sampler || !integrator.init(*scene, settings, &out.error)) {
    ADD_FAILURE() << name << ": " << out.error;
    return out;
  }
  integrator.preprocess(sampler.get());
  RenderOptions ro;
  ro.quiet = true;
  out.stats = render(camera, *sampler, integrator, &film, ro);
  Bounds2i b = film.cropped_pixel_bounds();
  out.width = b.width();
  out.height = b.height();
  for (int y = b.min.y; y < b.max.y; ++y)
    for (int x = b.min.x; x < b.max.x; ++x) out.pixels.push_back(film.pixel({x, y}));
  out.ok = true;
  return out;
}

// Pixels with a NaN or infinite channel.
inline int count_nonfinite(const Rendered& r) {
  int n = 0;
  for (const Rgb& p : r.pixels) n += !p.is_finite();
  return n;
}

// Mean of one channel-average per pixel, and the standard error of that mean.
struct MeanAndError {
  double mean = 0, sigma = 0, sd = 0;
};
inline MeanAndError mean_and_error(const Rendered& r) {
  MeanAndError m;
  const double n = double(r.pixels.size());
  for (const Rgb& p : r.pixels) m.mean += p.average();
  m.mean /= n;
  double var = 0;
  for (const Rgb& p : r.pixels) var += (p.average() - m.mean) * (p.average() - m.mean);
  m.sd = std::sqrt(var / (n - 1));
  m.sigma = m.sd / std::sqrt(n);
  return m;
}

// %.9g: floats survive the round trip through scene text exactly.
inline std::string fmt(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

}  // namespace rt
