// runtime/geometry/prim_list.h — a scene of a few world primitives, traversed by testing each.
//
// Most reference scenes are a handful of triangles and quadrics (a Cornell box, a floor under
// a sphere, the bdpt test rooms). There a ray spends more in Embree's per-query machinery
// (its ray and context records, the robust traversal of a one-node tree, a filter callback
// per triangle hit) than in the primitives. PrimList holds such a scene's triangles (world
// vertices, as pbrt-v3 transforms meshes at load) and still quadrics, each behind its box,
// and answers a query by testing every box the ray meets: triangles with pbrt-v3's own
// watertight test (watertight.h), which also rejects a hit within its error bound of the
// origin as pbrt-v3's does, quadrics with intersect_quadric. SceneGeometry uses it for scenes
// that qualify (scene_geometry.h) and Embree for every other.
//
// A triangle hit gives the caller its tag and triangle and the barycentrics of the hit; a
// quadric hit its tag and, for a closest-hit query, its whole interaction. A masked triangle's
// hit is first put to the caller's mask test (set_mask_test), which may drop it, as an Embree
// filter would. Hits are taken in (0, ray.tmax), the interval open at tmax. Const queries are
// thread-safe.
#pragma once

#include <cstdint>
#include <vector>

#include "runtime/core/interaction.h"
#include "runtime/core/ray.h"
#include "runtime/geometry/quadric_intersect.h"
#include "runtime/geometry/shape_table.h"
#include "runtime/geometry/watertight4.h"

namespace rt {

class PrimList {
 public:
  // Triangle `prim` of a mesh whose world vertices are p0, p1, p2; tag names the mesh. masked:
  // its hits go through the mask test.
  void add_triangle(Vec3 p0, Vec3 p1, Vec3 p2, uint32_t tag, uint32_t prim, bool masked = false);
  // Whether a masked triangle's hit (tag, prim, at t with barycentrics b1, b2 of the ray) is
  // dropped; shadow: for any(). ctx is handed back.
  using MaskTest = bool (*)(const void* ctx, uint32_t tag, uint32_t prim, float t, float b1,
                            float b2, const Ray& ray, bool shadow);
  void set_mask_test(MaskTest test, const void* ctx) {
    mask_test_ = test;
    mask_ctx_ = ctx;
  }
  // A still quadric; s and q must outlive the list. shape is its ShapeTable index (occluded's
  // skip_shape), or kNone for one never skipped.
  void add_quadric(const ShapeInfo& s, const PreparedQuadric& q, const Bounds3& world_box,
                   uint32_t tag, uint32_t shape);
  size_t size() const { return entries_.size(); }

  struct Hit {
    uint32_t tag = 0, prim = 0;
    float t = 0, b1 = 0, b2 = 0;  // triangles: barycentrics of p1 and p2
  };
  // The closest hit, skipping the quadric of ShapeTable index skip_shape; a quadric's
  // interaction goes to *si (untouched for a triangle's).
  bool closest(const Ray& ray, Hit* hit, SurfaceInteraction* si, uint32_t skip_shape = kNone) const;
  // Any hit, skipping the quadric of ShapeTable index skip_shape.
  bool any(const Ray& ray, uint32_t skip_shape) const;

 private:
  struct Entry {
    uint32_t tag, prim;
    int32_t quadric;  // index into quadrics_, or -1 for a triangle (its group's lane)
    bool masked;
  };
  struct QuadricRef {
    const ShapeInfo* s;
    const PreparedQuadric* q;
    uint32_t shape;
  };
  // Entries four at a time: their boxes, padded outwards by an ulp (lo x, y, z then hi x, y, z
  // of entries 4 g .. 4 g + 3; a partial last group's missing lanes are never read), and the
  // vertices of those that are triangles (bit k of `triangles`: entry 4 g + k), tested
  // together (watertight4.h).
  struct alignas(16) Group {
    float lo[3][4], hi[3][4];
    TriangleLanes tri;
    int triangles;
  };
  // The triangle lanes' answers for one group (bit k of `hits`: lane k's triangle is hit).
  struct GroupHits {
    int hits;
    float t[4], b1[4], b2[4];
  };
  void add_box(const Bounds3& b);
  // Which of group g's boxes the ray meets within [0, tmax] (bit k: entry 4 g + k).
  int group_mask(size_t g, const float o[3], const float inv[3], float tmax) const;
  // visit(entry, group hits, lane) for each entry whose box the ray meets within [0, *tmax]
  // (read for every group: closest() shrinks it as it goes), until visit returns true; whether
  // one did. A triangle's lane of the group hits was tested with the *tmax of its group.
  template <class Visit>
  bool each_met(const Ray& ray, const float* tmax, Visit visit) const;
  // Entry e's hit in (0, best): its t, and (closest) its hit record and interaction. A
  // triangle's test is lane k of gh.
  bool test(const Entry& e, const GroupHits& gh, int k, const Ray& ray, float best, float* t,
            Hit* hit, SurfaceInteraction* si) const;
  bool skips(const Entry& e, uint32_t skip_shape) const {
    return e.quadric >= 0 && skip_shape != kNone &&
           quadrics_[size_t(e.quadric)].shape == skip_shape;
  }
  bool dropped(const Entry& e, float t, float b1, float b2, const Ray& ray, bool shadow) const {
    return e.masked && mask_test_(mask_ctx_, e.tag, e.prim, t, b1, b2, ray, shadow);
  }

  std::vector<Group> groups_;
  std::vector<Entry> entries_;
  std::vector<QuadricRef> quadrics_;
  MaskTest mask_test_ = nullptr;
  const void* mask_ctx_ = nullptr;
};

}  // namespace rt
