// runtime/geometry/prim_list.cpp — see prim_list.h.
#include "runtime/geometry/prim_list.h"

#include <xmmintrin.h>

#include <algorithm>

namespace rt {

void PrimList::add_box(const Bounds3& b) {
  const size_t k = entries_.size() % 4;
  if (k == 0) groups_.push_back({});
  Group& g = groups_.back();
  for (int i = 0; i < 3; ++i) {
    g.lo[i][k] = next_float_down(b.lo[i]);
    g.hi[i][k] = next_float_up(b.hi[i]);
  }
}

void PrimList::add_triangle(Vec3 p0, Vec3 p1, Vec3 p2, uint32_t tag, uint32_t prim, bool masked) {
  Bounds3 b;
  b.extend(p0);
  b.extend(p1);
  b.extend(p2);
  const int k = int(entries_.size() % 4);
  add_box(b);
  groups_.back().tri.set(k, p0, p1, p2);
  groups_.back().triangles |= 1 << k;
  entries_.push_back({tag, prim, -1, masked});
}

void PrimList::add_quadric(const ShapeInfo& s, const PreparedQuadric& q, const Bounds3& world_box,
                           uint32_t tag, uint32_t shape) {
  add_box(world_box);
  entries_.push_back({tag, 0, int32_t(quadrics_.size()), false});
  quadrics_.push_back({&s, &q, shape});
}

// The slab test on four boxes at once. The far distances are widened by their rounding (pbrt
// book 3rd ed. 3.9.2), so no box the ray meets is missed. A slab distance that is NaN (0
// times an infinite 1 / d: the origin on a face the ray runs along) bounds nothing:
// cmpunord marks it, and max / min return their second operand, the running bound, for it.
int PrimList::group_mask(size_t g, const float o[3], const float inv[3], float tmax) const {
  const Group& b = groups_[g];
  __m128 t0 = _mm_setzero_ps(), t1 = _mm_set1_ps(tmax);
  const __m128 widen = _mm_set1_ps(1 + 2 * gamma_bound(3));
  for (int i = 0; i < 3; ++i) {
    const __m128 oi = _mm_set1_ps(o[i]), ii = _mm_set1_ps(inv[i]);
    const __m128 ta = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(b.lo[i]), oi), ii);
    const __m128 tb = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(b.hi[i]), oi), ii);
    const __m128 nan = _mm_cmpunord_ps(ta, tb);
    const __m128 near = _mm_or_ps(_mm_min_ps(ta, tb), nan);
    const __m128 far = _mm_or_ps(_mm_mul_ps(_mm_max_ps(ta, tb), widen), nan);
    t0 = _mm_max_ps(near, t0);
    t1 = _mm_min_ps(far, t1);
  }
  return _mm_movemask_ps(_mm_cmple_ps(t0, t1));
}

bool PrimList::test(const Entry& e, const GroupHits& gh, int k, const Ray& ray, float best,
                    float* t, Hit* hit, SurfaceInteraction* si) const {
  if (e.quadric < 0) {
    *t = gh.t[k];
    // any() asks with no hit record: a shadow query, where shadowalpha masks too.
    if (!(gh.hits >> k & 1) || !(*t < best) ||
        dropped(e, *t, gh.b1[k], gh.b2[k], ray, hit == nullptr))
      return false;
    if (hit) *hit = {e.tag, e.prim, *t, gh.b1[k], gh.b2[k]};
    return true;
  }
  const QuadricRef& q = quadrics_[size_t(e.quadric)];
  Ray r = ray;
  r.tmax = best;
  SurfaceInteraction qsi;  // a candidate's: a rejected test may have written part of it
  if (!intersect_quadric(*q.s, q.q->shape, q.q->world_to_object, r, t, si ? &qsi : nullptr) ||
      !(*t < best))
    return false;
  if (hit) *hit = {e.tag, 0, *t, 0, 0};
  if (si) *si = qsi;
  return true;
}

template <class Visit>
bool PrimList::each_met(const Ray& ray, const float* tmax, Visit visit) const {
  const float o[3] = {ray.o.x, ray.o.y, ray.o.z};
  const float inv[3] = {1 / ray.d.x, 1 / ray.d.y, 1 / ray.d.z};
  WatertightRay wr;
  bool have_wr = false;
  for (size_t g = 0; g < groups_.size(); ++g) {
    int mask = group_mask(g, o, inv, *tmax);
    if (!mask) continue;
    GroupHits gh;
    gh.hits = 0;
    if (const int tri = mask & groups_[g].triangles) {
      if (!have_wr) wr = watertight_ray(ray.o, ray.d);
      have_wr = true;
      gh.hits = watertight_triangles4(wr, groups_[g].tri, tri, *tmax, gh.t, gh.b1, gh.b2);
    }
    const int lanes = int(std::min<size_t>(4, entries_.size() - 4 * g));
    for (int k = 0; k < lanes; ++k, mask >>= 1)
      if ((mask & 1) && visit(entries_[4 * g + size_t(k)], gh, k)) return true;
  }
  return false;
}

bool PrimList::closest(const Ray& ray, Hit* hit, SurfaceInteraction* si,
                       uint32_t skip_shape) const {
  float best = ray.tmax;
  bool found = false;
  each_met(ray, &best, [&](const Entry& e, const GroupHits& gh, int k) {
    float t;
    if (!skips(e, skip_shape) && test(e, gh, k, ray, best, &t, hit, si)) {
      best = t;
      found = true;
    }
    return false;
  });
  return found;
}

bool PrimList::any(const Ray& ray, uint32_t skip_shape) const {
  return each_met(ray, &ray.tmax, [&](const Entry& e, const GroupHits& gh, int k) {
    float t;
    return !skips(e, skip_shape) && test(e, gh, k, ray, ray.tmax, &t, nullptr, nullptr);
  });
}

}  // namespace rt
