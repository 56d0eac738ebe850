// runtime/geometry/scene_geometry.h — the archive's shapes in Embree, hits as pbrt-v3 interactions.
//
// build() puts every shape into Embree 3: still world meshes sit in the
// top-level scene, on the archive's own (16-byte padded) arrays when their
// transform is the identity, else on a copy of their positions through it (as
// pbrt-v3 transforms meshes at load); each object definition is one child
// scene, instanced once per ObjectInstance (a mesh with its own transform
// inside an object is copied through that transform: Embree here has a single
// instance level); quadrics are user geometries
// calling runtime/geometry/quadric_intersect.h, curves are user geometries of
// their pieces (curve_hit.h). Alpha and shadowalpha are
// Embree filters that drop hits where the value is exactly 0.
//
// A scene of a few still world shapes is not queried through Embree at all, and a scene's
// few still world quadrics may be tested beside Embree's tree rather than from its
// callbacks: prim_list.h, set_max_listed().
//
// intersect() rebuilds the closest hit in world space exactly as pbrt-v3's
// Triangle::Intersect would (triangle_hit.h), so materials, lights and ray
// spawning see pbrt-v3's numbers; the hit on Embree's triangle is measured
// again there, since Embree's t and barycentrics depend on the kernels it
// picks for the CPU. occluded() answers any hit. Both take
// hits in (0, ray.tmax), are const and thread-safe, and allocate nothing.
// A quadric with an animated transform is intersected where it is at each
// ray's time, inside motion bounds; a moving mesh sits in its own scene under
// an Embree instance with quaternion motion blur, or, where Embree's
// decomposition cannot hold pbrt-v3's interpolation, matrices at enough time
// steps (keyframes with shear); a moving mesh inside an object is placed once
// per instance with the instance's transform or motion composed on (one exact
// motion under a still or only translating similarity, else sampled); hits are
// rebuilt at the ray's time; a moving object instance likewise. Unsupported
// input (moving things with different TransformTimes, which pbrtc never writes)
// fails build() with "not supported yet: <what> (file:line)".
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>

#include "format/scene_archive.h"
#include "runtime/core/interaction.h"
#include "runtime/geometry/shape_table.h"

namespace rt {

class TextureSet;

struct GeometryStats {
  double build_seconds = 0;
  uint64_t embree_bytes = 0;  // Embree's own allocations after the build
  uint32_t triangles = 0, quadrics = 0, curves = 0, instances = 0, copied_meshes = 0;
  uint32_t sampled_motions = 0;  // moving meshes and instances given time steps
  uint32_t listed = 0;  // primitives tested one by one beside (or instead of) Embree's tree
  uint32_t placed_instances = 0;  // object instances copied into the world (set_max_placed)
};

class SceneGeometry {
 public:
  // set_max_listed's default; the most triangles a scene may have for all of its shapes to
  // be listed, and the most quadrics listed beside Embree's tree in a scene with more.
  static constexpr size_t kDefaultMaxListed = 32, kMaxListedTriangles = 16,
                          kMaxListedBesideTree = 4;
  // set_max_placed's default: at most this many triangles (a quadric counts one) are copied
  // into the world for placed instances. What pbrt-v3 shares, copies pay for in memory: ten
  // instances of a 3200-triangle grid placed took 1.9 MiB in Embree and a peak RSS of 11.8 MiB
  // against pbrt-v3's 10.3; at this budget (ten instances of 392 triangles: 0.2 MiB in
  // Embree) the peak RSS stayed at pbrt-v3's, 9.5 MiB.
  static constexpr size_t kDefaultMaxPlaced = 4096;

  SceneGeometry();
  ~SceneGeometry();
  SceneGeometry(const SceneGeometry&) = delete;
  SceneGeometry& operator=(const SceneGeometry&) = delete;

  // archive and shapes (and textures, when given) must outlive this object:
  // Embree reads the archive's arrays in place. textures evaluates alpha and
  // shadowalpha textures; it may be null when no shape has one.
  [[nodiscard]] bool build(const pbrta::SceneArchive& archive, const ShapeTable& shapes,
                           const TextureSet* textures, std::string* error);
  // Before build(): also give every unmasked mesh the watertight vertex
  // patches of watertight.h. Embree's ROBUST test lets a few rays aimed
  // exactly at shared vertices through (runtime_stability_tests measures
  // how many); the patches close those cracks at the cost of a box per
  // vertex in the BVH, so they are opt-in (pbrtrun --watertight).
  void set_watertight(bool on) { watertight_ = on; }
  // Before build(): shapes tested one by one behind their boxes (prim_list.h) rather than put
  // in Embree, unless watertight: a scene of at most n primitives, kMaxListedTriangles of them
  // triangles at most, all of them still world shapes (placed instances' copies count as
  // world shapes; no other instances, no curves; quadrics without masks, meshes' masks tested
  // as Embree's filters test them), is listed whole and Embree is never asked; otherwise its
  // still world quadrics without masks (placed ones too), when there are at most
  // kMaxListedBesideTree and Embree would have no other user geometry (curves, moving or
  // Embree-instanced quadrics), are listed and tested beside Embree's tree. 0: nothing
  // listed. Hits are pbrt-v3's triangle test's (a listed triangle's interaction is built on
  // that test's t and barycentrics, not measured again) and the same quadric test; tests
  // compare.
  void set_max_listed(size_t n) { max_listed_ = n; }
  // Before build(): still instances of objects made only of still triangle meshes and still
  // quadrics are copied into the world rather than put under Embree instances: a mesh's
  // vertices through the instance's transform (as a world mesh's go through its own), a
  // quadric tested through the instance's transform times its own. While the copies come to at
  // most n (triangles, and one per quadric) in all; objects are taken whole (every instance of
  // one, or none), in the archive's order. One tree instead of two levels (or, for a few
  // shapes, a list: set_max_listed): no ray transformed into each instance on the way down.
  // Triangle hits are those of the instanced geometry (same vertices, same arithmetic), quadric
  // hits up to the product transform's rounding (tests compare); all still report their
  // instance. 0: every instance under Embree's.
  void set_max_placed(size_t n) { max_placed_ = n; }
  // Before build(): Embree's device configuration (rtcNewDevice's string), e.g.
  // "max_isa=sse4.2" to use the kernels a CPU without AVX would. Hits do not depend on
  // it (intersect() measures Embree's triangle again itself); tests check that.
  void set_embree_config(std::string config) { embree_config_ = std::move(config); }

  // Closest hit in (0, ray.tmax): fills p, p_error, n, wo, time, uv, dpdu,
  // dpdv, dndu, dndv, the shading frame, shape, prim, instance, face_index;
  // not the differentials (SurfaceInteraction::compute_differentials).
  // skip_shape: a world sphere or disk the ray cannot meet (a ray leaving an area light's own
  // shape: LightSet::shape_left_behind); its test is skipped.
  bool intersect(const Ray& ray, SurfaceInteraction* si, uint32_t skip_shape = kNone) const;
  // The same hit in two steps, for a caller that may need only what was hit: intersect_ids()
  // fills si's shape, prim and instance (a quadric's or curve's whole interaction too: it is
  // made while Embree traverses) and keeps the rest of the hit in *pending; complete() then
  // fills si as intersect() would have (nothing to do for quadrics and curves).
  struct PendingHit {
    const void* geom = nullptr;  // a triangle mesh's geometry record, or null (si is whole)
    const void* inst = nullptr;
    uint32_t prim = 0;
    float u = 0, v = 0, t = 0;
  };
  bool intersect_ids(const Ray& ray, SurfaceInteraction* si, PendingHit* pending,
                     uint32_t skip_shape = kNone) const;
  void complete(const PendingHit& pending, const Ray& ray, SurfaceInteraction* si) const;
  // Any hit in (0, ray.tmax). skip_shape: a world sphere or disk that the
  // caller knows cannot block this ray (an area light's own shape, for a
  // shadow ray to a point sampled on it; LightSample::own_shape): its test
  // is skipped. A line meets a sphere at most twice and a plane once, so the
  // segment to a point on the visible side never meets it before t = 1.
  bool occluded(const Ray& ray, uint32_t skip_shape = kNone) const;

  // pbrt-v3's world bound: mesh vertices, quadric boxes through their
  // transforms, instances' object boxes through the instance transforms.
  Bounds3 world_bounds() const { return world_bounds_; }
  bool watertight() const { return watertight_; }
  const GeometryStats& stats() const { return stats_; }

  // Internal to the Embree callbacks (scene_geometry.cpp).
  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
  Bounds3 world_bounds_;
  bool watertight_ = false;
  size_t max_listed_ = kDefaultMaxListed;
  size_t max_placed_ = kDefaultMaxPlaced;
  std::string embree_config_;
  GeometryStats stats_;
};

}  // namespace rt
