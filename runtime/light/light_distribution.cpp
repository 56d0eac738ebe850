// runtime/light/light_distribution.cpp — see light_distribution.h.
#include "runtime/light/light_distribution.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <new>
#include <vector>

#include <sys/mman.h>

#include "format/huge_pages.h"

namespace rt {

namespace {

constexpr int kMaxVoxels = 64;
constexpr int kVoxelSamples = 128;
// Lights whose grid points are kept: 128 points each, 60 bytes a point (480 KiB at most).
constexpr int kPointLights = 64;
// Flat records: a state word, each light's pmf and the n - 1 cdf entries between the first
// (0) and the last (1), padded to a power of two of at most 16 words (64 bytes, one cache
// line): with two lights 16 bytes. The grid is megabytes, and a record is a cache miss at
// nearly every bounce; the smaller it is, the more of the visited ones stay cached. A voxel
// whose cdf does not run from exactly 0 to 1 (a non-finite contribution) is marked kFlatSlow
// and sampled from its distribution.
constexpr int kFlatLights = 6;
constexpr uint32_t kFlatEmpty = 0, kFlatWriting = 1, kFlatReady = 2, kFlatSlow = 3;

int flat_stride(int n) {
  int words = 2 * n, stride = 1;
  while (stride < words) stride *= 2;
  return stride;
}

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

// Every voxel samples the same 128 points of the unit cube (bases 2, 3, 5) with the same light
// samples (bases 7, 11), scaled to its box: computed once, not per voxel (they were a quarter
// of a voxel's cost).
struct VoxelSample {
  float p[3];
  Vec2 u;
};
const VoxelSample* voxel_samples() {
  static const std::vector<VoxelSample> table = [] {
    std::vector<VoxelSample> t(kVoxelSamples);
    for (int i = 0; i < kVoxelSamples; ++i)
      t[size_t(i)] = {{radical_inverse(2, uint64_t(i)), radical_inverse(3, uint64_t(i)),
                       radical_inverse(5, uint64_t(i))},
                      {radical_inverse(7, uint64_t(i)), radical_inverse(11, uint64_t(i))}};
    return t;
  }();
  return table.data();
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

// Mapped fresh, so only the pages of voxels a render visits take memory (veach-mis at full
// resolution: 9.7 MiB less than a zero-filled vector), and a large table in huge pages: a
// lookup lands on a random voxel of megabytes, and in 4 KiB pages its address translation
// missed as often as its data (the Cornell box's 8 MiB table: 3% of the render). A small
// table stays in 4 KiB pages, which the TLB covers, instead of paying for whole huge pages
// (own/motion-instances' peak RSS: 15.5 MiB so, 17.2 MiB in huge pages).
struct LightDistribution::FlatTable {
  static constexpr uint64_t kHugeFrom = uint64_t{4} << 20;
  FlatTable(size_t voxels, int lights) : n(lights), stride(size_t(flat_stride(lights))) {
    // Zeroed by the kernel (every record kFlatEmpty) and page-aligned, so no record straddles
    // two cache lines.
    const uint64_t bytes = voxels * stride * sizeof(uint32_t);
    void* p = nullptr;
    if (bytes >= kHugeFrom) {
      p = pbrta::map_huge(bytes, &mapped);
    } else {
      mapped = (bytes + 4095) / 4096 * 4096;
      p = mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE,
               -1, 0);
      if (p == MAP_FAILED) p = nullptr;
    }
    if (!p) throw std::bad_alloc();
    base = static_cast<uint32_t*>(p);
  }
  ~FlatTable() { munmap(base, mapped); }
  // A voxel's record: its state word, then the lights' pmfs (record(v)[1 + light]), then the
  // cdf entries.
  uint32_t* record(size_t voxel) const { return base + voxel * stride; }
  FlatTable(const FlatTable&) = delete;
  FlatTable& operator=(const FlatTable&) = delete;
  int n;
  size_t stride;
  uint64_t mapped = 0;
  uint32_t* base;
};

bool LightDistribution::build(const LightSet& lights, const Bounds3& world_bounds,
                              std::string_view strategy, std::string* error) {
  lights_ = &lights;
  bounds_ = world_bounds;
  spatial_ = false;
  nvoxels_ = {1, 1, 1};
  cache_.reset();
  flat_.reset();
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
  for (int i = 0; i < 3; ++i) voxels_per_unit_[i] = diag[i] > 0 ? nvoxels_[i] / diag[i] : 0;
  const size_t voxels = size_t(nvoxels_[0]) * nvoxels_[1] * nvoxels_[2];
  cache_ = std::make_shared<VoxelCache>(voxels);
  if (n <= uint32_t(kFlatLights)) flat_ = std::make_shared<FlatTable>(voxels, int(n));
  grid_points_.clear();
  if (n <= uint32_t(kPointLights)) {
    grid_points_.resize(size_t(kVoxelSamples) * n);
    const VoxelSample* samples = voxel_samples();
    for (int i = 0; i < kVoxelSamples; ++i)
      for (uint32_t j = 0; j < n; ++j) {
        GridPoint& g = grid_points_[size_t(i) * n + j];
        g.on_triangle = lights.triangle_point(j, samples[i].u, &g.it, &g.pdf_area);
      }
  }
  return true;
}

size_t LightDistribution::voxel_index(Vec3 p) const {
  // Two sites a hit (a prefetch, then the point): multiplying by voxels_per_unit_ rather than
  // dividing by the extent (pbrt-v3's Bounds3::Offset) moves a point by rounding only, and
  // a voxel's distribution is a choice of sampling density, never of value.
  int v[3];
  for (int i = 0; i < 3; ++i)
    v[i] = clamp(int((p[i] - bounds_.lo[i]) * voxels_per_unit_[i]), 0, nvoxels_[i] - 1);
  return (size_t(v[2]) * nvoxels_[1] + v[1]) * nvoxels_[0] + v[0];
}

const Distribution1D& LightDistribution::lookup(Vec3 p) const {
  if (!spatial_) return single_;
  return voxel_distribution(voxel_index(p));
}

int LightDistribution::sample(Site site, float u, float* pmf) const {
  if (!spatial_) return single_.sample_discrete(u, pmf);
  const size_t index = site.voxel;
  if (!flat_) return voxel_distribution(index).sample_discrete(u, pmf);
  uint32_t* rec = flat_->record(index);
  const int n = flat_->n;
  if (__atomic_load_n(rec, __ATOMIC_ACQUIRE) == kFlatReady) {
    float f[2 * kFlatLights];  // pmf[n], then cdf[1..n-1]
    std::memcpy(f, rec + 1, sizeof(float) * size_t(2 * n - 1));
    // Distribution1D's choice: the count of cdf entries <= u (std::upper_bound's), less one,
    // clamped to a light; the first entry is 0 and the last 1.
    int count = int(!(u < 0.f)) + int(!(u < 1.f));
    for (int i = 1; i < n; ++i) count += int(!(u < f[n + i - 1]));
    const int chosen = clamp(count - 1, 0, n - 1);
    if (pmf) *pmf = f[chosen];
    return chosen;
  }
  const Distribution1D& d = voxel_distribution(index);
  // The first thread here copies the distribution into the flat record; the
  // others (rarely: only while it writes) use the distribution itself.
  uint32_t expected = kFlatEmpty;
  if (__atomic_compare_exchange_n(rec, &expected, kFlatWriting, false, __ATOMIC_ACQUIRE,
                                  __ATOMIC_RELAXED)) {
    const float* cdf = d.cdf_data();
    if (cdf[0] == 0 && cdf[n] == 1) {
      for (int i = 0; i < n; ++i) {
        const float p = d.discrete_pdf(i);
        std::memcpy(rec + 1 + i, &p, sizeof(float));
      }
      std::memcpy(rec + 1 + n, cdf + 1, sizeof(float) * size_t(n - 1));
      __atomic_store_n(rec, kFlatReady, __ATOMIC_RELEASE);
    } else {
      __atomic_store_n(rec, kFlatSlow, __ATOMIC_RELEASE);
    }
  }
  return d.sample_discrete(u, pmf);
}

float LightDistribution::pmf(Site site, int light) const {
  if (!spatial_) return single_.discrete_pdf(light);
  if (flat_) {
    const uint32_t* rec = flat_->record(site.voxel);
    if (__atomic_load_n(rec, __ATOMIC_ACQUIRE) == kFlatReady) {
      float p;
      std::memcpy(&p, rec + 1 + light, sizeof(float));
      return p;
    }
  }
  return voxel_distribution(site.voxel).discrete_pdf(light);
}

void LightDistribution::prefetch(Site site) const {
  if (flat_) __builtin_prefetch(flat_->record(site.voxel));
}

const Distribution1D& LightDistribution::voxel_distribution(size_t index) const {
  std::atomic<const Distribution1D*>& slot = cache_->slots[index];
  if (const Distribution1D* d = slot.load(std::memory_order_acquire)) return *d;

  // The voxel's box, as pbrt-v3 computes it from the grid fractions.
  int v[3] = {int(index % size_t(nvoxels_[0])),
              int(index / size_t(nvoxels_[0]) % size_t(nvoxels_[1])),
              int(index / (size_t(nvoxels_[0]) * size_t(nvoxels_[1])))};
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
  const VoxelSample* samples = voxel_samples();
  for (int i = 0; i < kVoxelSamples; ++i) {
    const VoxelSample& vs = samples[i];
    Interaction ref;  // a point in free space: no normal, time 0
    ref.p = {lerp(vs.p[0], lo.x, hi.x), lerp(vs.p[1], lo.y, hi.y), lerp(vs.p[2], lo.z, hi.z)};
    ref.wo = {1, 0, 0};
    const GridPoint* points = grid_points_.empty() ? nullptr : &grid_points_[size_t(i) * n];
    for (uint32_t j = 0; j < n; ++j) {
      if (points && points[j].on_triangle) {
        contrib[j] += lights_->triangle_point_weight(j, ref.p, points[j].it, points[j].pdf_area);
        continue;
      }
      Rgb li = lights_->sample_li(j, ref, vs.u, &s);
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
