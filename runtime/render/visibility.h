// runtime/render/visibility.h — what lies between points of a RenderScene: pbrt-v3's
// VisibilityTester::Tr, shared by the path and bidirectional integrators.
//
// Surfaces with the interface material ("none", or no material) only bound media: rays pass
// through them and change medium there (pbrt-v3's GetMedium: the far side's when the shape's
// two media differ). transmittance() is 0 at the first real surface and otherwise the product
// of the crossed media's transmittance (1 without media); it counts rays in *counters.
#pragma once

#include <cstdint>

#include "runtime/core/interaction.h"
#include "runtime/core/rgb.h"
#include "runtime/render/render_scene.h"
#include "runtime/sampler/sampler.h"

namespace rt {

struct RayCounters {
  uint64_t camera_rays = 0, rays = 0, shadow_rays = 0;
  // bdpt and mlt: strategies (s, t) joined, and how many of them carried no radiance.
  uint64_t paths = 0, zero_radiance_paths = 0;
};

// The medium a ray leaving hit si along w is in: the far side's if the shape bounds two
// media, else `medium`.
inline uint32_t medium_after(const RenderScene& scene, const SurfaceInteraction& si, Vec3 w,
                             uint32_t medium) {
  const ShapeInfo& s = scene.shapes[si.shape];
  if (!s.medium_transition()) return medium;
  return dot(w, si.n) > 0 ? s.outside_medium : s.inside_medium;
}

Rgb transmittance(const RenderScene& scene, const Interaction& from, const Interaction& to,
                  uint32_t medium, Sampler& sampler, RayCounters* counters);
// The same, the ray leaving `from` by the side direction `side` names (a light sample's wi:
// Interaction::spawn_ray_to says why).
Rgb transmittance(const RenderScene& scene, const Interaction& from, const Interaction& to,
                  Vec3 side, uint32_t medium, Sampler& sampler, RayCounters* counters);

}  // namespace rt
