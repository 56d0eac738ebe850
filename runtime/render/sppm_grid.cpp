// runtime/render/sppm_grid.cpp — see sppm_grid.h.
#include "runtime/render/sppm_grid.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <memory>

namespace rt {

void SphereGrid::build(const std::vector<GridSphere>& spheres, uint32_t hash_size) {
  spheres_ = &spheres;
  hash_size_ = std::max(hash_size, 1u);
  bounds_ = Bounds3{};
  float max_radius = 0;
  for (const GridSphere& s : spheres) {
    if (s.radius <= 0) continue;
    const Vec3 r{s.radius, s.radius, s.radius};
    bounds_.extend(s.center - r);
    bounds_.extend(s.center + r);
    max_radius = std::max(max_radius, s.radius);
  }
  start_.assign(size_t(hash_size_) + 1, 0);
  entries_.clear();
  empty_ = max_radius <= 0;
  if (empty_) return;

  // Cells about as wide as the largest sphere along the longest axis, so a
  // sphere overlaps few of them; the cap only keeps the conversion defined.
  const Vec3 diag = bounds_.diagonal();
  const float max_diag = std::max(diag.x, std::max(diag.y, diag.z));
  const int base = int(std::min(max_diag / max_radius, float(1 << 30)));
  for (int i = 0; i < 3; ++i) res_[i] = std::max(int(float(base) * diag[i] / max_diag), 1);

  // Count per bucket, turn the counts into offsets, then fill; the order inside
  // a bucket depends on scheduling, which only reorders the caller's sums.
  const size_t n = spheres.size();
  std::unique_ptr<std::atomic<uint32_t>[]> counts(new std::atomic<uint32_t>[hash_size_]());
  auto for_each_bucket = [&](auto&& visit) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024),
                      [&](const tbb::blocked_range<size_t>& r) {
                        std::vector<uint32_t> buckets;
                        for (size_t i = r.begin(); i != r.end(); ++i) {
                          if (spheres[i].radius <= 0) continue;
                          buckets_of(spheres[i], &buckets);
                          for (uint32_t h : buckets) visit(uint32_t(i), h);
                        }
                      });
  };
  for_each_bucket([&](uint32_t, uint32_t h) { counts[h].fetch_add(1, std::memory_order_relaxed); });
  for (uint32_t h = 0; h < hash_size_; ++h) {
    start_[h + 1] = start_[h] + counts[h].load(std::memory_order_relaxed);
    counts[h].store(start_[h], std::memory_order_relaxed);
  }
  entries_.resize(start_[hash_size_]);
  for_each_bucket([&](uint32_t i, uint32_t h) {
    entries_[counts[h].fetch_add(1, std::memory_order_relaxed)] = i;
  });
}

bool SphereGrid::to_cell(Vec3 p, int cell[3]) const {
  const Vec3 o = bounds_.offset(p);
  bool inside = true;
  for (int i = 0; i < 3; ++i) {
    // Clamped as a float first: a far-away p must not overflow the conversion.
    const float f = float(res_[i]) * o[i];
    inside &= f >= 0 && f < float(res_[i]);
    cell[i] = f >= 0 ? int(std::min(f, float(res_[i] - 1))) : 0;
  }
  return inside;
}

uint32_t SphereGrid::bucket(const int cell[3]) const {
  // pbrt-v3's spatial hash (three large primes, xor), in unsigned arithmetic.
  const uint32_t h = (uint32_t(cell[0]) * 73856093u) ^ (uint32_t(cell[1]) * 19349663u) ^
                     (uint32_t(cell[2]) * 83492791u);
  return h % hash_size_;
}

void SphereGrid::buckets_of(const GridSphere& s, std::vector<uint32_t>* out) const {
  const Vec3 r{s.radius, s.radius, s.radius};
  int lo[3], hi[3];
  to_cell(s.center - r, lo);
  to_cell(s.center + r, hi);
  out->clear();
  int c[3];
  for (c[2] = lo[2]; c[2] <= hi[2]; ++c[2])
    for (c[1] = lo[1]; c[1] <= hi[1]; ++c[1])
      for (c[0] = lo[0]; c[0] <= hi[0]; ++c[0]) {
        const uint32_t h = bucket(c);
        if (std::find(out->begin(), out->end(), h) == out->end()) out->push_back(h);
      }
}

}  // namespace rt
