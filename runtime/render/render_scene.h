// runtime/render/render_scene.h — everything a ray needs, loaded from one archive.
//
// load_render_scene() builds, in order, the shape table, textures,
// materials, the Embree scene, the lights and the media (the integrator builds its
// light-selection distribution); any part the runtime cannot render yet
// stops the load with "not supported yet: <feature> (file:line)". After
// loading, a RenderScene is read-only and shared by all render threads.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "format/scene_archive.h"
#include "runtime/geometry/scene_geometry.h"
#include "runtime/geometry/shape_table.h"
#include "runtime/light/light_distribution.h"
#include "runtime/light/lights.h"
#include "runtime/material/materials.h"
#include "runtime/medium/media.h"
#include "runtime/texture/textures.h"

namespace rt {

struct RenderScene {
  const pbrta::SceneArchive* archive = nullptr;
  ShapeTable shapes;
  TextureSet textures;
  MaterialSet materials;
  SceneGeometry geometry;
  LightSet lights;
  MediumSet media;                 // empty unless the archive's media bit is set
  uint32_t camera_medium = kNone;  // the medium camera rays start in
  uint64_t effects = 0;            // the archive's effect bits
  // Every shape has a scattering material and none a shadow mask: a ray outside media is
  // stopped by its first hit, so transmittance() asks only whether there is one.
  bool opaque_shapes = false;
};

// Call scene->geometry.set_watertight() first to change that option.
[[nodiscard]] bool load_render_scene(const pbrta::SceneArchive& archive, RenderScene* scene,
                                     std::string* error);

// pbrt-v3's ComputeScatteringFunctions at a hit reached along `ray`: the screen-space
// differentials (zero for a ray without them), then the shape's material's BSDF for `mode`
// (bump mapping updates si's shading frame). False where the surface has no material or the
// interface material: it only bounds media, and rays pass through it.
bool scattering_at(const RenderScene& scene, SurfaceInteraction* si, const RayDifferential& ray,
                   TransportMode mode, bool multiple_lobes, Bsdf* bsdf);

}  // namespace rt
