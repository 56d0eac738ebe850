// runtime/render/renderer.h — the tile-parallel render loop.
//
// The sample bounds are cut into 16x16-pixel tiles rendered in parallel with
// oneTBB; each tile has its own sampler clone and film tile, and the tiles
// are merged into the film in tile order once all are done, so the image is
// bit-identical whatever the thread count (samplers depend only on pixel,
// sample index and seed). Non-finite radiance never reaches the film: such
// samples are counted and added as black, as pbrt-v3 does. Progress with an
// ETA goes to stderr unless quiet.
#pragma once

#include <cstdint>

#include "runtime/film/film.h"
#include "runtime/render/camera.h"
#include "runtime/render/integrator.h"
#include "runtime/sampler/sampler.h"

namespace rt {

struct RenderOptions {
  bool quiet = false;
  // > 0: camera differentials scaled as for this many samples per pixel
  // (pbrt-v3 uses the sampler's count; see RenderJobOptions::differential_spp).
  int differential_spp = 0;
};

struct RenderStats {
  double seconds = 0;
  double first_tile_seconds = 0;  // time to the first finished tile (first pixels)
  uint64_t samples = 0, camera_rays = 0, rays = 0, shadow_rays = 0;
  uint64_t nonfinite_samples = 0;
  // bdpt and mlt: strategies joined, and those that carried no radiance (pbrt-v3's "zero
  // radiance paths"); mlt: mutations proposed and accepted; sppm: iterations and photons.
  uint64_t paths = 0, zero_radiance_paths = 0;
  uint64_t mutations = 0, accepted = 0;
  uint64_t iterations = 0, photons = 0;
};

RenderStats render(const Camera& camera, const Sampler& sampler, const Integrator& integrator,
                   Film* film, const RenderOptions& options);

}  // namespace rt
