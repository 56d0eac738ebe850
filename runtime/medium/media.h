// runtime/medium/media.h — the archive's participating media, sampled and traversed.
//
// Two kinds, as pbrt-v3 has them: homogeneous (constant coefficients) and
// a density grid (pbrt-v3's GridDensityMedium: trilinear density over
// [p0, p1], zero outside the samples, coefficients times density, the
// extinction taken from the red channel as pbrt-v3 does). Coefficients come
// from the archive already resolved (pbrtc writes presets in); "scale"
// multiplies them here, as pbrt-v3 does after reading them.
//
// Distances: a ray's parameter t may be in units of any |d|; everything
// here works in world distance, so results do not depend on |d|.
//
// sample(): pbrt-v3's Medium::Sample over (0, ray.tmax). It returns the
//   path-throughput factor, and when a scattering event was drawn sets
//   *scattered and *p. Homogeneous media pick the distance from one colour
//   channel's exponential and weight by the channel-averaged pdf, exactly as
//   pbrt-v3; grids use delta tracking.
// tr(): transmittance over (0, ray.tmax): Beer-Lambert for homogeneous media,
//   ratio tracking with pbrt-v3's Russian roulette below 0.1 for grids.
//
// Grids track against a coarse majorant grid (majorant_grid.h) instead of
// pbrt-v3's one global maximum: the same expectation, far fewer density
// lookups in the empty and thin parts of a cloud.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "format/scene_archive.h"
#include "runtime/core/ray.h"
#include "runtime/core/rgb.h"
#include "runtime/core/transform.h"
#include "runtime/medium/majorant_grid.h"
#include "runtime/sampler/sampler.h"

namespace rt {

enum class MediumKind : uint8_t { kHomogeneous, kGrid };

struct Medium {
  MediumKind kind = MediumKind::kHomogeneous;
  Rgb sigma_a, sigma_s, sigma_t;  // scaled; sigma_t = sigma_a + sigma_s
  float g = 0;
  // Grid: density samples in the archive (x fastest), the grid-from-world
  // transform (world to [0,1]^3), and the majorants.
  const float* density = nullptr;
  int nx = 0, ny = 0, nz = 0;
  float grid_sigma_t = 0;  // sigma_t's red channel: pbrt-v3's grid extinction
  Transform grid_from_world;
  MajorantGrid majorants;

  float density_at(Vec3 p_grid) const;  // trilinear, pbrt-v3's sample positions
};

struct MediumStats {
  uint32_t homogeneous = 0, grids = 0;
  uint64_t grid_cells = 0;  // majorant cells over all grids
};

class MediumSet {
 public:
  // Reads every MediumRecord; false with "file:line: error: ..." on values the
  // runtime cannot use (pbrtc refuses them first; this guards other writers).
  [[nodiscard]] bool build(const pbrta::SceneArchive& archive, std::string* error);
  uint32_t size() const { return uint32_t(media_.size()); }
  const Medium& operator[](uint32_t m) const { return media_[m]; }
  const MediumStats& stats() const { return stats_; }

  Rgb sample(uint32_t m, const Ray& ray, Sampler& sampler, bool* scattered, Vec3* p) const;
  Rgb tr(uint32_t m, const Ray& ray, Sampler& sampler) const;

 private:
  std::vector<Medium> media_;
  MediumStats stats_;
};

}  // namespace rt
