// runtime/render/sppm_grid.h — which of a set of spheres contain a point: the
// visible-point grid of pbrt-v3's SPPM (book 3rd ed., 16.2.4).
//
// build() lays a uniform grid over the bounds of all present spheres (a radius
// <= 0 marks a sphere absent), with cells about as wide as the largest radius
// along the longest axis (pbrt-v3's resolution rule), and files every sphere
// under each cell its bounding box overlaps. Cells are not stored: a cell's
// index is hashed into one of `hash_size` buckets, as pbrt-v3 does, so memory
// follows the sphere count, not the scene's extent. The buckets are one
// compact array (counts, prefix sums, then a fill) rebuilt per call rather than
// pbrt-v3's lock-free lists; a sphere is filed once per bucket even when two of
// its cells hash to the same one (pbrt-v3's lists would hold it twice and
// count a photon there twice).
//
// for_each_containing(p, f) calls f(i) for each sphere i with |p - center|^2 <=
// radius^2, in no particular order; points outside the grid's bounds meet none.
// build() runs in parallel (oneTBB) and is not thread-safe; queries are, until
// the next build(). The spheres passed to build() must stay alive and unchanged
// while the grid is queried.
#pragma once

#include <cstdint>
#include <vector>

#include "runtime/core/vec.h"

namespace rt {

struct GridSphere {
  Vec3 center;
  float radius = -1;  // <= 0: absent
};

class SphereGrid {
 public:
  void build(const std::vector<GridSphere>& spheres, uint32_t hash_size);

  template <class F>
  void for_each_containing(Vec3 p, F&& f) const {
    int cell[3];
    if (empty_ || !to_cell(p, cell)) return;
    const uint32_t h = bucket(cell);
    for (uint32_t k = start_[h]; k < start_[h + 1]; ++k) {
      const uint32_t i = entries_[k];
      const GridSphere& s = (*spheres_)[i];
      if (distance_squared(s.center, p) <= s.radius * s.radius) f(i);
    }
  }

  // The grid's resolution per axis (0s before the first build with a present sphere).
  const int* resolution() const { return res_; }

 private:
  // The cell holding p, clamped into the grid; false when p lies outside it.
  bool to_cell(Vec3 p, int cell[3]) const;
  uint32_t bucket(const int cell[3]) const;
  // The distinct buckets of the cells sphere s's bounding box overlaps (usually
  // at most 27: cells are at least as wide as the largest radius).
  void buckets_of(const GridSphere& s, std::vector<uint32_t>* out) const;

  const std::vector<GridSphere>* spheres_ = nullptr;
  bool empty_ = true;
  Bounds3 bounds_;
  int res_[3] = {0, 0, 0};
  uint32_t hash_size_ = 1;
  std::vector<uint32_t> start_;    // hash_size_ + 1 offsets into entries_
  std::vector<uint32_t> entries_;  // sphere indices, bucket by bucket
};

}  // namespace rt
