// runtime/light/light_distribution.cpp — see light_distribution.h.
#include "runtime/light/light_distribution.h"

#include <atomic>
#include <cmath>
#include <vector>

namespace rt {

namespace {

constexpr int kMaxVoxels = 64;
constexpr int kVoxelSamples = 128;

// The radical inverse of i in a prime base (van der Corput), as pbrt-v3
// computes it: the reversed digits scaled by base^-digits, below 1.
float radical_inverse(int base, uint64_t i) {
  const float inv_base = 1.f / float(base);
  uint64_t reversed = 0;
  float inv_base_n = 1;
  while (i) {
    uint64_t next = i / uint64_t(base);
    reversed = reversed * uint64_t(base) + (i - next * uint64_t(base));
    inv_base_n *= inv_base;
    i = next;
  }
  return std::min(float(reversed) * inv_base_n, kOneMinusEpsilon);
}

}  // namespace

struct LightDistribution::VoxelCache {
  explicit VoxelCache(size_t n) : slots(new std::atomic<const Distribution1D*>[n]), size(n) {
    for (size_t i = 0; i < n; ++i) slots[i].store(nullptr, std::memory_order_relaxed);
  }
  ~VoxelCache() {
    for (size_t i = 0; i < size; ++i) delete slots[i].load(std::memory_order_relaxed);
  }
  std::unique_ptr<std::atomic<const Distribution1D*>[]> slots;
  size_t size;
};

bool LightDistribution::build(const LightSet& lights, const Bounds3& world_bounds,
                              std::string_view strategy, std::string* error) {
  lights_ = &lights;
  bounds_ = world_bounds;
  spatial_ = false;
  nvoxels_ = {1, 1, 1};
  cache_.reset();
  uint32_t n = lights.count();
  if (strategy == "uniform" || (strategy == "spatial" && n <= 1)) {
    // One light needs no grid: every voxel would give it probability 1.
    std::vector<float> ones(n, 1.f);
    single_ = Distribution1D(ones.data(), int(n));
    return true;
  }
  if (strategy == "power") {
    std::vector<float> power(n);
    for (uint32_t i = 0; i < n; ++i) power[i] = lights.power(i).luminance();
    single_ = Distribution1D(power.data(), int(n));
    return true;
  }
  if (strategy != "spatial") {
    *error = "unknown lightsamplestrategy \"" + std::string(strategy) +
             "\" (pbrt-v3 has uniform, power and spatial)";
    return false;
  }
  spatial_ = true;
  Vec3 diag = world_bounds.empty() ? Vec3{} : world_bounds.diagonal();
  float bmax = diag[max_dimension(diag)];
  for (int i = 0; i < 3; ++i)
    nvoxels_[i] = bmax > 0 ? std::max(1, int(std::round(diag[i] / bmax * kMaxVoxels))) : 1;
  cache_ = std::make_shared<VoxelCache>(size_t(nvoxels_[0]) * nvoxels_[1] * nvoxels_[2]);
  return true;
}

const Distribution1D& LightDistribution::lookup(Vec3 p) const {
  if (!spatial_) return single_;
  Vec3 o = bounds_.offset(p);
  int v[3];
  for (int i = 0; i < 3; ++i) v[i] = clamp(int(o[i] * nvoxels_[i]), 0, nvoxels_[i] - 1);
  return voxel_distribution(v[0], v[1], v[2]);
}

const Distribution1D& LightDistribution::voxel_distribution(int x, int y, int z) const {
  std::atomic<const Distribution1D*>& slot =
      cache_->slots[(size_t(z) * nvoxels_[1] + y) * nvoxels_[0] + x];
  if (const Distribution1D* d = slot.load(std::memory_order_acquire)) return *d;

  // The voxel's box, as pbrt-v3 computes it from the grid fractions.
  int v[3] = {x, y, z};
  Vec3 lo, hi;
  for (int i = 0; i < 3; ++i) {
    float t0 = float(v[i]) / float(nvoxels_[i]), t1 = float(v[i] + 1) / float(nvoxels_[i]);
    float a = lerp(t0, bounds_.lo[i], bounds_.hi[i]), b = lerp(t1, bounds_.lo[i], bounds_.hi[i]);
    lo[i] = std::min(a, b);
    hi[i] = std::max(a, b);
  }
  uint32_t n = lights_->count();
  std::vector<float> contrib(n, 0.f);
  LightSample s;
  for (int i = 0; i < kVoxelSamples; ++i) {
    Interaction ref;  // a point in free space: no normal, time 0
    ref.p = {lerp(radical_inverse(2, i), lo.x, hi.x), lerp(radical_inverse(3, i), lo.y, hi.y),
             lerp(radical_inverse(5, i), lo.z, hi.z)};
    ref.wo = {1, 0, 0};
    Vec2 u{radical_inverse(7, i), radical_inverse(11, i)};
    for (uint32_t j = 0; j < n; ++j) {
      Rgb li = lights_->sample_li(j, ref, u, &s);
      if (s.pdf > 0) contrib[j] += li.luminance() / s.pdf;
    }
  }
  // Every light keeps some probability: the samples may all have missed a
  // light that matters somewhere in the voxel.
  float sum = 0;
  for (float c : contrib) sum += c;
  float avg = sum / (float(kVoxelSamples) * float(n));
  float floor_value = avg > 0 ? .001f * avg : 1;
  for (float& c : contrib) c = std::max(c, floor_value);

  auto* fresh = new Distribution1D(contrib.data(), int(n));
  const Distribution1D* expected = nullptr;
  if (slot.compare_exchange_strong(expected, fresh, std::memory_order_acq_rel,
                                   std::memory_order_acquire))
    return *fresh;
  delete fresh;  // another thread published the same distribution first
  return *expected;
}

}  // namespace rt
