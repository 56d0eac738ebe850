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
  if (!s->lights.build(a, s->shapes, s->geometry.world_bounds(), error)) return false;
  s->opaque_shapes = true;
  for (uint32_t i = 0; i < s->shapes.size(); ++i)
    if (!has_material(*s, i) || s->shapes[i].has_shadow_mask()) s->opaque_shapes = false;
  if (!(s->effects & pbrta::kEffectMedia)) return true;
  s->camera_medium = a.scene().camera_medium;
  return s->media.build(a, error);
}

bool scattering_at(const RenderScene& scene, SurfaceInteraction* si, const RayDifferential& ray,
                   TransportMode mode, bool multiple_lobes, Bsdf* bsdf) {
  si->compute_differentials(ray);
  const uint32_t m = scene.shapes[si->shape].material;
  return m != kNone && scene.materials.compute_bsdf(m, si, mode, multiple_lobes, bsdf);
}

}  // namespace rt
