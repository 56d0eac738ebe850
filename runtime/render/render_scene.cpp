// runtime/render/render_scene.cpp — see render_scene.h.
#include "runtime/render/render_scene.h"

#include <chrono>

namespace rt {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

bool load_render_scene(const pbrta::SceneArchive& a, RenderScene* s, std::string* warnings,
                       std::string* error) {
  s->archive = &a;
  s->effects = a.header().effects;
  (void)warnings;
  auto t0 = std::chrono::steady_clock::now();
  if (!s->shapes.build(a, error)) return false;
  if (!s->textures.build(a, error)) return false;
  s->times.textures = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  if (!s->materials.build(a, s->textures, error)) return false;
  s->times.materials = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  bool alpha = (s->effects & pbrta::kEffectAlpha) != 0;
  if (!s->geometry.build(a, s->shapes, alpha ? &s->textures : nullptr, error)) return false;
  s->times.geometry = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  if (!s->lights.build(a, s->shapes, s->geometry.world_bounds(), error)) return false;
  s->times.lights = seconds_since(t0);
  return true;
}

}  // namespace rt
