// tests/runtime/light/light_test_scene.h — a LightSet built from real scene text.
//
// Compiles "Camera; WorldBegin; <world>; WorldEnd" with pbrtc's front end,
// builds the shape table and the lights (with the given world bounds), and
// offers the Monte Carlo helpers the light tests share.
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "runtime/core/rng.h"
#include "runtime/geometry/scene_geometry.h"
#include "runtime/geometry/shape_table.h"
#include "runtime/light/lights.h"
#include "runtime/runtime_test_support.h"
#include "test_support.h"

namespace rt {

struct LightScene {
  pbrta::SceneArchive archive;
  ShapeTable shapes;
  LightSet lights;
  std::string dir;
};

inline std::string light_scene_text(const std::string& world) {
  return "Camera \"perspective\"\nWorldBegin\n" + world + "\nWorldEnd\n";
}

// Fails the test (and returns false) when the scene does not compile or the
// lights do not build.
inline bool load_light_scene(const std::string& name, const std::string& world,
                             const Bounds3& bounds, LightScene* s) {
  if (s->dir.empty()) s->dir = testing_support::scratch_dir(name);
  if (!testing_support::compile_text(s->dir, light_scene_text(world), &s->archive)) return false;
  std::string error;
  if (!s->shapes.build(s->archive, &error)) {
    ADD_FAILURE() << "shapes: " << error;
    return false;
  }
  if (!s->lights.build(s->archive, s->shapes, bounds, &error)) {
    ADD_FAILURE() << "lights: " << error;
    return false;
  }
  return true;
}

// The scene's geometry, for tests that trace rays; fails the test (and returns false) when it
// does not build.
inline bool build_light_scene_geometry(const LightScene& s, SceneGeometry* geometry) {
  std::string error;
  if (geometry->build(s.archive, s.shapes, nullptr, &error)) return true;
  ADD_FAILURE() << "geometry: " << error;
  return false;
}

inline Bounds3 box(Vec3 lo, Vec3 hi) {
  Bounds3 b;
  b.extend(lo);
  b.extend(hi);
  return b;
}

inline Interaction surface_point(Vec3 p, Vec3 n) {
  Interaction it;
  it.p = p;
  it.n = normalize(n);
  return it;
}

// Irradiance at ref (normal ref.n) from one light, estimated with its own
// sample_li over n samples: mean of Li |cos| / pdf over the upper hemisphere.
// Counts samples whose pdf_li (at the sampled point) disagrees with sample_li's
// pdf, except within a degree of `pole` when given (an environment map's
// poles, where acos cannot give sin(theta) to 1e-3, in pbrt-v3 as here).
inline Rgb estimate_irradiance(const LightSet& lights, uint32_t light, const Interaction& ref,
                               int n, uint64_t seed, int* pdf_mismatches = nullptr,
                               Vec3 pole = Vec3{}) {
  Rng rng(seed);
  Rgb sum;
  for (int i = 0; i < n; ++i) {
    Vec2 u{rng.next_float(), rng.next_float()};
    LightSample s;
    Rgb li = lights.sample_li(light, ref, u, &s);
    if (s.pdf == 0) continue;
    if (pdf_mismatches && !s.delta && std::fabs(dot(s.wi, pole)) <= 0.9998f) {
      float pdf = lights.pdf_li(light, ref, s.wi, &s.p_light);
      if (!(std::fabs(pdf - s.pdf) <= 1e-3f * s.pdf)) ++*pdf_mismatches;
    }
    float c = dot(ref.n, s.wi);
    if (c > 0) sum += li * (c / s.pdf);
  }
  return sum / float(n);
}

// A little-endian RGB PFM (rows bottom to top, as the format stores them).
inline void write_pfm(const std::string& path, int w, int h, const float* rgb_top_down) {
  FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  std::fprintf(f, "PF\n%d %d\n-1.0\n", w, h);
  for (int y = h - 1; y >= 0; --y)
    std::fwrite(rgb_top_down + size_t(y) * w * 3, 4, size_t(w) * 3, f);
  std::fclose(f);
}

}  // namespace rt
