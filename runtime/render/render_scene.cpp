// runtime/render/render_scene.cpp — see render_scene.h.
#include "runtime/render/render_scene.h"

namespace rt {

bool load_render_scene(const pbrta::SceneArchive& a, RenderScene* s, std::string* error) {
  s->archive = &a;
  s->effects = a.header().effects;
  if (!s->shapes.build(a, error)) return false;
  if (!s->textures.build(a, error)) return false;
  if (!s->materials.build(a, s->textures, error)) return false;
  // A surface without a material, or with the interface one, scatters nothing: rays pass
  // through it.
  s->opaque_shapes = true;
  for (uint32_t i = 0; i < s->shapes.size(); ++i) {
    const uint32_t m = s->shapes[i].material;
    s->shapes.set_passes_through(i, m == kNone || s->materials.is_interface(m));
    if (s->shapes[i].passes_through || s->shapes[i].has_shadow_mask()) s->opaque_shapes = false;
  }
  bool alpha = (s->effects & pbrta::kEffectAlpha) != 0;
  if (!s->geometry.build(a, s->shapes, alpha ? &s->textures : nullptr, error)) return false;
  if (!s->lights.build(a, s->shapes, s->geometry.world_bounds(), error)) return false;
  if (!(s->effects & pbrta::kEffectMedia)) return true;
  s->camera_medium = a.scene().camera_medium;
  return s->media.build(a, error);
}

bool scattering_at(const RenderScene& scene, SurfaceInteraction* si, const RayDifferential& ray,
                   TransportMode mode, bool multiple_lobes, Bsdf* bsdf) {
  // A medium's boundary is only passed through: nothing reads its differentials.
  const ShapeInfo& shape = scene.shapes[si->shape];
  if (shape.passes_through) return false;
  si->compute_differentials(ray);
  return scene.materials.compute_bsdf(shape.material, si, mode, multiple_lobes, bsdf);
}

}  // namespace rt
