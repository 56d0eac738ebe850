// runtime/render/visibility.cpp — see visibility.h.
#include "runtime/render/visibility.h"

namespace rt {

Rgb transmittance(const RenderScene& scene, const Interaction& from, const Interaction& to,
                  uint32_t medium, Sampler& sampler, RayCounters* c) {
  return transmittance(scene, from, to, to.p - from.p, medium, sampler, c);
}

Rgb transmittance(const RenderScene& scene, const Interaction& from, const Interaction& to,
                  Vec3 side, uint32_t medium, Sampler& sampler, RayCounters* c) {
  Ray ray = from.spawn_ray_to(to, side);
  // pbrt-v3 finds every hit whole here; only a surface the ray passes through is read.
  if (medium == kNone && scene.opaque_shapes)
    return scene.geometry.occluded(ray) ? Rgb() : Rgb(1.f);
  Rgb tr(1.f);
  for (;;) {
    SurfaceInteraction si;
    SceneGeometry::PendingHit pending;
    const bool hit = scene.geometry.intersect_ids(ray, &si, &pending);
    if (hit && !scene.shapes[si.shape].passes_through) return Rgb();
    if (hit) scene.geometry.complete(pending, ray, &si);
    if (medium != kNone) {
      Ray seg = ray;
      if (hit) seg.tmax = si.t_hit;
      tr *= scene.media.tr(medium, seg, sampler);
    }
    if (!hit || tr.is_black()) return tr;
    ++c->shadow_rays;
    medium = medium_after(scene, si, ray.d, medium);
    ray = si.spawn_ray_to(to);
  }
}

}  // namespace rt
