// runtime/render/render_scene.cpp — see render_scene.h.
#include "runtime/render/render_scene.h"

namespace rt {

bool load_render_scene(const pbrta::SceneArchive& a, RenderScene* s, std::string* error) {
  s->archive = &a;
  s->effects = a.header().effects;
  if (!s->shapes.build(a, error)) return false;
  if (!s->textures.build(a, error)) return false;
  if (!s->materials.build(a, s->textures, error)) return false;
  bool alpha = (s->effects & pbrta::kEffectAlpha) != 0;
  if (!s->geometry.build(a, s->shapes, alpha ? &s->textures : nullptr, error)) return false;
  return s->lights.build(a, s->shapes, s->geometry.world_bounds(), error);
}

}  // namespace rt
