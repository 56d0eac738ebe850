// runtime/light/light_distribution.h — which light to sample at a point:
// pbrt-v3's lightsamplestrategy "uniform", "power" and "spatial".
//
// uniform: every light equally likely. power: in proportion to the
// luminance of LightSet::power. spatial: pbrt-v3's SpatialLightDistribution:
// a grid over the world bounds, 64 voxels along its longest axis; each
// voxel's distribution is the luminance of 128 sample_li estimates per light
// at low-discrepancy points inside the voxel (radical inverse in bases 2..11),
// with every light kept at least 0.001 of the average contribution. A light on a triangle
// gets the same point for a sample value in every voxel: with up to 64 lights those points
// are sampled once, and a voxel's sample only adds its luminance over pdf (at low spp the
// voxels were a quarter of a path-traced room's instructions).
//
// A voxel's distribution is a pure function of the voxel, so it is computed
// the first time lookup() meets the voxel (as pbrt-v3 does: an eager grid of
// 64^3 voxels times every light would cost minutes) and published with one
// atomic compare-and-swap; a thread that loses the race discards its copy,
// which is identical. Results never depend on thread scheduling.
//
// sample() is the renderer's hot path: with at most kFlatLights lights it
// reads a copy of each voxel's distribution kept inline in one flat table
// (one cache line or less per voxel, so one memory access per lookup
// instead of three pointer hops); its choice and pmf equal
// lookup(p).sample_discrete(u, pmf) bit for bit.
//
// lookup() and sample() are thread-safe. With no lights the distribution has count() 0.
// The LightSet must outlive this object.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "runtime/core/sampling.h"
#include "runtime/light/lights.h"

namespace rt {

class LightDistribution {
 public:
  [[nodiscard]] bool build(const LightSet& lights, const Bounds3& world_bounds,
                           std::string_view strategy, std::string* error);
  const Distribution1D& lookup(Vec3 p) const;
  // Where in the grid a point's distribution is: found once per hit and used twice (three
  // divisions each time were 3% of a path-traced room).
  struct Site {
    size_t voxel = 0;
  };
  Site site(Vec3 p) const { return {spatial_ ? voxel_index(p) : 0}; }
  // A light for a point at p (at site) with probability *pmf, chosen by u.
  int sample(Vec3 p, float u, float* pmf) const { return sample(site(p), u, pmf); }
  int sample(Site site, float u, float* pmf) const;
  // The probability sample(site, ...) picks `light` with (its *pmf when it does).
  float pmf(Site site, int light) const;
  // Starts loading the record sample(site, ...) will read: a spatial grid is megabytes, so its
  // record is a cache miss that the work between a hit and its light sample can hide.
  void prefetch(Site site) const;

  // The spatial grid's resolution ({1, 1, 1} for the other strategies).
  std::array<int, 3> voxels() const { return nvoxels_; }

 private:
  struct VoxelCache;
  struct FlatTable;
  size_t voxel_index(Vec3 p) const;
  const Distribution1D& voxel_distribution(size_t index) const;

  const LightSet* lights_ = nullptr;
  Bounds3 bounds_;
  bool spatial_ = false;
  std::array<int, 3> nvoxels_{{1, 1, 1}};
  std::array<float, 3> voxels_per_unit_{{0, 0, 0}};
  Distribution1D single_;  // uniform / power
  std::shared_ptr<VoxelCache> cache_;
  std::shared_ptr<FlatTable> flat_;  // null when there are too many lights
  // The points the grid's 128 sample values pick on each light on a triangle, the same in
  // every voxel (LightSet::triangle_point), made once at build; empty past kPointLights lights.
  struct GridPoint {
    Interaction it;
    float pdf_area = 0;
    bool on_triangle = false;
  };
  std::vector<GridPoint> grid_points_;  // [sample * count + light]
};

}  // namespace rt
