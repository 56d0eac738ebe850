// runtime/geometry/scene_geometry.cpp — see scene_geometry.h.
#include "runtime/geometry/scene_geometry.h"

#include <embree3/rtcore.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <deque>
#include <mutex>
#include <vector>

#include "runtime/core/clock.h"
#include "runtime/geometry/curve_hit.h"
#include "runtime/geometry/prim_list.h"
#include "runtime/geometry/quadric_intersect.h"
#include "runtime/geometry/triangle_hit.h"
#include "runtime/geometry/watertight.h"
#include "runtime/texture/textures.h"

namespace rt {

namespace {

// Embree user data of every triangle, quadric and curve geometry.
struct GeomData {
  const SceneGeometry::Impl* impl = nullptr;
  uint32_t shape = kNone;
  bool quadric = false;
  bool curve = false;                // the curve's pieces; prepared.world_to_object is the shape's
  const float* positions = nullptr;  // triangles: the vertex buffer Embree reads
  bool copied = false;               // positions are a copy through the shape's transform
  uint32_t placed = kNone;   // an instance copied into the world: its index in Impl::instances,
                             // whose transform the positions (a quadric's prepared transform)
                             // went through too
  Bounds3 box;               // quadrics: the box Embree is given, in the space of the scene
                             // holding it (the world, or its object's space)
  PreparedQuadric prepared;  // quadrics; inside instances only .shape applies
  std::vector<TriangleFrame> frames;  // a listed mesh's, per triangle (triangle_hit.h)
};

// A top-level Embree instance: an object instance, or a moving mesh in its own scene.
struct InstanceData {
  Transform to_world;
  uint32_t child = kNone;             // index into Impl::children
  uint32_t archive_instance = kNone;  // kNone for a moving world mesh
  bool mirrors = false;               // an object instance whose transform mirrors
  // A moving mesh: its object-space scene moved by this over time (to_world is where at()
  // puts it at the start), an instance as pbrt-v3's TransformedPrimitive is.
  const AnimatedTransform* motion = nullptr;
  // A moving mesh inside an object definition, flattened into the top level once per instance
  // of its object (Embree here nests one instance level): the instance's transform, or its
  // motion, is composed onto the mesh's motion, as pbrt-v3's two TransformedPrimitives do.
  // Only set with motion.
  bool composed = false;
  Transform outer;
  const AnimatedTransform* outer_motion = nullptr;
  // A motion sampled in time steps (motion_steps): how far Embree's geometry may lie from the
  // exact one hits are rebuilt on, added to their error bounds so spawned rays clear both.
  float step_error = 0;

  // Buffer space to world at a ray's time.
  Transform at(float time) const {
    const Transform inner = motion ? motion->at(time) : to_world;
    if (!composed) return inner;
    return (outer_motion ? outer_motion->at(time) : outer) * inner;
  }
};

// The context every query hands Embree; its callbacks get it back and cast.
struct QueryContext {
  RTCIntersectContext rtc;         // must stay first
  const Ray* ray;                  // the world-space ray
  SurfaceInteraction* quadric_si;  // intersect(): the accepted quadric or curve hit, or null
  float near_t;                    // triangle hits at t <= near_t are re-tested (near_filter)
  uint32_t skip_shape;             // a world quadric that cannot block or stop this ray
};

bool is_quadric(ShapeKind k) {
  return k != ShapeKind::kTriangles && k != ShapeKind::kCurve;
}

// A world shape PrimList may hold: still, and a quadric without masks (a mesh's masks are
// PrimList's mask test).
bool listable(const ShapeInfo& s) {
  return s.object == kNone && !s.motion &&
         (s.kind == ShapeKind::kTriangles || (!s.has_alpha_mask() && !s.has_shadow_mask()));
}

bool empty_mesh(const ShapeInfo& s) {
  return s.mesh.num_triangles == 0 || s.mesh.num_vertices == 0;
}

// An archive transform that differs at the shutter's start and end.
bool moves(const pbrta::TransformRecord& t) {
  return std::memcmp(t.start, t.end, sizeof t.start) != 0;
}

}  // namespace

struct SceneGeometry::Impl {
  RTCDevice device = nullptr;
  RTCScene top = nullptr;
  const pbrta::SceneArchive* archive = nullptr;
  const ShapeTable* shapes = nullptr;
  const TextureSet* textures = nullptr;

  struct Child {
    RTCScene scene = nullptr;
    std::vector<const GeomData*> geoms;  // by geomID within the child
    Bounds3 bounds;                      // in the child's own space
  };
  std::vector<Child> children;
  std::vector<const GeomData*> top_geoms;  // by top-level geomID; null for instances
  std::vector<uint32_t> top_instance;      // by top-level geomID: index into instances, or kNone
  std::vector<InstanceData> instances;
  std::deque<GeomData> geoms;                      // stable addresses for Embree's user pointers
  std::deque<std::vector<float>> copies;           // transformed vertex copies (padded for Embree)
  std::deque<VertexPatches> patches;               // watertight vertex fallback (watertight.h)
  std::deque<AnimatedTransform> instance_motions;  // moving object instances
  bool watertight = false;                         // SceneGeometry::set_watertight
  // By object: how many instances of it are copied into the world (choose_placed), 0 for an
  // object left to Embree's instances.
  std::vector<uint32_t> placed_copies;
  // Shapes queried by testing each (prim_list.h) rather than through Embree: every shape of a
  // scene of a few (kAll), or the still world quadrics of one with few (kQuadrics: no user
  // geometry callbacks in Embree's traversal). A listed hit's tag indexes listed_geoms.
  enum class Listing { kNone, kQuadrics, kAll };
  Listing listing = Listing::kNone;
  PrimList listed;
  std::vector<const GeomData*> listed_geoms;
  // Moving meshes' shared keyframe times (pbrt-v3's TransformTimes): a ray's time maps to
  // Embree's [0, 1] through them.
  bool has_moving_meshes = false;
  float motion_t0 = 0, motion_t1 = 1;
  float embree_time(float time) const {
    if (!has_moving_meshes || !(motion_t1 > motion_t0)) return 0;
    return std::clamp((time - motion_t0) / (motion_t1 - motion_t0), 0.f, 1.f);
  }

  std::mutex error_mutex;
  std::string embree_error;
  std::atomic<int64_t> embree_bytes{0};

  ~Impl() {
    if (top) rtcReleaseScene(top);
    for (Child& c : children)
      if (c.scene) rtcReleaseScene(c.scene);
    if (device) rtcReleaseDevice(device);
  }

  const InstanceData* instance_of(unsigned inst_geom_id) const {
    return inst_geom_id == RTC_INVALID_GEOMETRY_ID ? nullptr
                                                   : &instances[top_instance[inst_geom_id]];
  }
  const GeomData* geom_of(const InstanceData* inst, unsigned geom_id) const {
    return inst ? children[inst->child].geoms[geom_id] : top_geoms[geom_id];
  }

  // The instance a hit on g belongs to: the one g was placed for, else the Embree instance
  // the query went through (null for the world).
  const InstanceData* instance_for(const GeomData& g, const InstanceData* embree_inst) const {
    return g.placed != kNone ? &instances[g.placed] : embree_inst;
  }

  // The interaction at triangle prim, hit at *t_hit with barycentrics (u, v): Embree's, which
  // triangle_interaction measures again (they depend on the CPU) and updates *t_hit, or, in a
  // scene listed whole, PrimList's own, which it keeps.
  void fill_triangle(const GeomData& g, const InstanceData* inst, uint32_t prim, float u, float v,
                     const Ray& ray, float* t_hit, SurfaceInteraction* si) const {
    inst = instance_for(g, inst);
    TriangleSpace space;
    space.positions = g.positions;
    space.buffer_has_shape_transform = g.copied;
    space.positions_in_world = g.placed != kNone;
    space.instance = inst != nullptr;
    space.instance_mirrors = inst && inst->mirrors;
    // A listed scene's hits are all PrimList's.
    space.measured = listing == Listing::kAll;
    space.frames = g.frames.empty() ? nullptr : g.frames.data();
    // A moving instance's transform is made per hit. (Not a std::optional<Transform>: GCC
    // zeroes its 136 bytes on every call, moving or not.)
    if (inst && inst->motion) {
      const Transform moving = inst->at(ray.time);
      space.to_world = &moving;
      triangle_interaction((*shapes)[g.shape], space, prim, u, v, ray, t_hit, si);
    } else {
      space.to_world = inst ? &inst->to_world : nullptr;
      triangle_interaction((*shapes)[g.shape], space, prim, u, v, ray, t_hit, si);
    }
    if (inst && inst->step_error > 0)
      si->p_error += Vec3{inst->step_error, inst->step_error, inst->step_error};
  }

  // What intersect_ids() reports for hit geometry g: a quadric's or curve's interaction is
  // already in *si; a triangle's is left to complete() in *pending.
  void record_hit(const GeomData* g, const InstanceData* inst, uint32_t prim, float u, float v,
                  float t, SurfaceInteraction* si, SceneGeometry::PendingHit* pending) const {
    inst = instance_for(*g, inst);
    if (g->quadric || g->curve) {
      si->prim = g->curve ? prim : 0;
      si->face_index = 0;
      si->dpdx = si->dpdy = Vec3{};
      si->dudx = si->dvdx = si->dudy = si->dvdy = 0;
      pending->geom = nullptr;
    } else {
      si->prim = prim;
      *pending = {g, inst, prim, u, v, t};
    }
    si->shape = g->shape;
    si->instance = inst ? inst->archive_instance : kNone;
    si->t_hit = t;
  }

  // pbrt-v3's alpha masks: a texture, or the constant 0 (any other constant
  // makes no mask). A hit is dropped only where the value is exactly 0.
  bool masked(float value, uint32_t texture, const SurfaceInteraction& si) const {
    return texture != kNone ? textures->eval_float(texture, si) == 0 : value == 0;
  }
  // Whether the masks of triangle prim of mesh g drop its hit (at t_hit, barycentrics u, v of
  // the world ray) as pbrt-v3 would, the hit rebuilt for them; shadow: for an any-hit query,
  // where shadowalpha applies too.
  bool mask_drops(const GeomData& g, const InstanceData* inst, uint32_t prim, float u, float v,
                  const Ray& ray, float t_hit, bool shadow) const {
    const ShapeInfo& s = (*shapes)[g.shape];
    SurfaceInteraction si;
    fill_triangle(g, inst, prim, u, v, ray, &t_hit, &si);
    bool drop = s.has_alpha_mask() && masked(s.alpha, s.alpha_texture, si);
    if (shadow && !drop && s.has_shadow_mask())
      drop = masked(s.shadow_alpha, s.shadow_alpha_texture, si);
    return drop;
  }
};

namespace {

using Impl = SceneGeometry::Impl;

// ---- Embree callbacks (always called with N == 1: only rtcIntersect1 / rtcOccluded1) ----

void on_embree_error(void* user, RTCError code, const char* str) {
  auto* impl = static_cast<Impl*>(user);
  std::lock_guard<std::mutex> lock(impl->error_mutex);
  const std::string what = "Embree error " + std::to_string(int(code)) + ": " + (str ? str : "");
  if (impl->embree_error.find(what) != std::string::npos) return;  // one call per geometry
  if (!impl->embree_error.empty()) impl->embree_error += "; ";
  impl->embree_error += what;
}

bool on_embree_memory(void* user, ssize_t bytes, bool /*post*/) {
  static_cast<Impl*>(user)->embree_bytes += bytes;
  return true;
}

// A triangle hit this close to the ray's origin may be the surface the ray
// left. pbrt-v3's own triangle test rejects t within its error bound of zero;
// Embree's has no such bound and reports a hit at t ~ 0 when an offset origin
// lies exactly on its surface (an axis-aligned plane through a zero
// coordinate, whose error bound along the normal is 0). Such hits are
// re-tested with pbrt-v3's test (watertight_triangle, in the space Embree
// hands the filter: the geometry's own), and dropped if it rejects them.
// Hits farther out than near_t (a few ulps of the origin's magnitude) are
// taken as they are, so a wall close to the origin is still hit, however far
// from the world's origin the scene sits.
bool near_hit_rejected(const RTCFilterFunctionNArguments* args) {
  const auto* ctx = reinterpret_cast<const QueryContext*>(args->context);
  const RTCRay* ray = reinterpret_cast<const RTCRay*>(args->ray);
  if (ray->tfar > ctx->near_t) return false;
  const auto* g = static_cast<const GeomData*>(args->geometryUserPtr);
  const RTCHit* hit = reinterpret_cast<const RTCHit*>(args->hit);
  const MeshView& m = (*g->impl->shapes)[g->shape].mesh;
  const uint32_t* idx = m.indices + 3 * size_t(hit->primID);
  auto p = [&](uint32_t v) {
    return Vec3{g->positions[3 * v], g->positions[3 * v + 1], g->positions[3 * v + 2]};
  };
  float t, b1, b2;
  return !watertight_triangle(Vec3{ray->org_x, ray->org_y, ray->org_z},
                              Vec3{ray->dir_x, ray->dir_y, ray->dir_z}, kInfinity, p(idx[0]),
                              p(idx[1]), p(idx[2]), &t, &b1, &b2);
}

void near_filter(const RTCFilterFunctionNArguments* args) {
  if (args->valid[0] && near_hit_rejected(args)) args->valid[0] = 0;
}

// Alpha filters: rebuild the hit as pbrt-v3 would and evaluate the mask there.
void alpha_filter(const RTCFilterFunctionNArguments* args, bool shadow) {
  if (!args->valid[0]) return;
  if (near_hit_rejected(args)) {
    args->valid[0] = 0;
    return;
  }
  const auto* g = static_cast<const GeomData*>(args->geometryUserPtr);
  const auto* ctx = reinterpret_cast<const QueryContext*>(args->context);
  const Impl* impl = g->impl;
  const RTCHit* hit = reinterpret_cast<const RTCHit*>(args->hit);
  if (impl->mask_drops(*g, impl->instance_of(args->context->instID[0]), hit->primID, hit->u, hit->v,
                       *ctx->ray, reinterpret_cast<const RTCRay*>(args->ray)->tfar, shadow))
    args->valid[0] = 0;
}

// PrimList's mask test (PrimList::MaskTest): a listed mesh's masks.
bool listed_mask_drops(const void* ctx, uint32_t tag, uint32_t prim, float t, float b1, float b2,
                       const Ray& ray, bool shadow) {
  const auto* impl = static_cast<const Impl*>(ctx);
  return impl->mask_drops(*impl->listed_geoms[tag], nullptr, prim, b1, b2, ray, t, shadow);
}
void alpha_filter_intersect(const RTCFilterFunctionNArguments* args) {
  alpha_filter(args, false);
}
void alpha_filter_occluded(const RTCFilterFunctionNArguments* args) {
  alpha_filter(args, true);
}

void quadric_bounds(const RTCBoundsFunctionArguments* args) {
  const auto* g = static_cast<const GeomData*>(args->geometryUserPtr);
  const Bounds3& b = g->box;
  *args->bounds_o = {b.lo.x, b.lo.y, b.lo.z, 0, b.hi.x, b.hi.y, b.hi.z, 0};
}

// Where a moving or instanced shape is at a ray's time: its motion there (or its own
// transform) under its instance's transform then.
Transform world_from_shape_at(const ShapeInfo& s, const InstanceData* inst, float time) {
  const Transform shape = s.motion ? s.motion->at(time) : s.object_to_world;
  return inst ? inst->at(time) * shape : shape;
}

// A curve piece's box in the space of the scene holding it, over the whole motion.
Bounds3 curve_piece_bounds(const ShapeInfo& s, uint32_t piece) {
  const Bounds3 box = s.curve->piece_bounds(piece);
  return s.motion ? s.motion->motion_bounds(box) : s.object_to_world.bounds(box);
}

// The ray in an instance's space, as pbrt-v3's TransformedPrimitive takes it there: its
// origin moved forward past the transform's rounding and tmax shortened by as much, so a hit
// found there at t is at t in the world ray's terms too, as pbrt-v3 reports it.
Ray ray_to_instance(const Transform& world_to_instance, const Ray& r) {
  Ray ri;
  Vec3 o_err;
  const Vec3 o = world_to_instance.point(r.o, &o_err);
  ri.d = world_to_instance.vector(r.d);
  const float past = past_error_distance(ri.d, o_err);
  ri.o = o + ri.d * past;
  ri.tmax = r.tmax - past;
  ri.time = r.time;
  return ri;
}

// An instance-space interaction to world space, as pbrt-v3 transforms a SurfaceInteraction:
// the point with its error bound carried through, normals by the inverse transpose, and the
// shading normal then kept on the geometric normal's side.
void interaction_to_world(const Transform& x, const Ray& world_ray, SurfaceInteraction* si) {
  Vec3 err;
  si->p = x.point(si->p, si->p_error, &err);
  si->p_error = err;
  si->n = normalize(x.normal(si->n));
  si->wo = normalize(-world_ray.d);
  si->dpdu = x.vector(si->dpdu);
  si->dpdv = x.vector(si->dpdv);
  si->dndu = x.normal(si->dndu);
  si->dndv = x.normal(si->dndv);
  ShadingFrame& sh = si->shading;
  sh.n = face_forward(normalize(x.normal(sh.n)), si->n);
  sh.dpdu = x.vector(sh.dpdu);
  sh.dpdv = x.vector(sh.dpdv);
  sh.dndu = x.normal(sh.dndu);
  sh.dndv = x.normal(sh.dndv);
}

// Quadric g (shape s) inside an instance placed by to_world, hit by world ray r.
bool quadric_hit_in(const Transform& to_world, const GeomData& g, const ShapeInfo& s, const Ray& r,
                    float* t, SurfaceInteraction* si) {
  const Ray ri = ray_to_instance(to_world.inverse(), r);
  if (!intersect_quadric(s, g.prepared.shape, g.prepared.world_to_object, ri, t, si)) return false;
  if (si) interaction_to_world(to_world, r, si);
  return true;
}

// The quadric hit by a world ray. Outside instances the shape's prepared form is used as it
// is. Inside one, the shape is tested in the instance's space with its own prepared transform
// and the hit taken out through the instance's transform (or its motion at the ray's time),
// as pbrt-v3 nests its transforms; orientation flags stay the shape's own. Composing the two
// transforms per test instead cost two 4x4 products each (7% of own/motion-in-objects).
bool world_quadric_hit(const GeomData& g, unsigned inst_id, uint32_t /*prim*/, const Ray& r,
                       float* t, SurfaceInteraction* si) {
  const ShapeInfo& s = (*g.impl->shapes)[g.shape];
  const InstanceData* inst = g.impl->instance_of(inst_id);
  if (!s.motion && !inst)
    return intersect_quadric(s, g.prepared.shape, g.prepared.world_to_object, r, t, si);
  // The normalised parameters do not depend on the transform: only the transform is made per
  // ray. (A moving shape's handedness flag is already off: ShapeTable clears it, as pbrt-v3
  // builds a moving shape with the identity transform.)
  if (s.motion)
    return intersect_quadric(s, g.prepared.shape, world_from_shape_at(s, inst, r.time).inverse(), r,
                             t, si);
  if (inst->motion) return quadric_hit_in(inst->at(r.time), g, s, r, t, si);
  return quadric_hit_in(inst->to_world, g, s, r, t, si);
}

void curve_bounds(const RTCBoundsFunctionArguments* args) {
  const auto* g = static_cast<const GeomData*>(args->geometryUserPtr);
  const Bounds3 b = curve_piece_bounds((*g->impl->shapes)[g->shape], args->primID);
  *args->bounds_o = {b.lo.x, b.lo.y, b.lo.z, 0, b.hi.x, b.hi.y, b.hi.z, 0};
}

// A curve piece hit by the world ray, under the transforms world_quadric_hit
// would use: the motion at the ray's time, the instance's composed on, or the
// shape's own.
bool world_curve_piece_hit(const GeomData& g, unsigned inst_id, uint32_t piece, const Ray& r,
                           float* t, SurfaceInteraction* si) {
  const ShapeInfo& s = (*g.impl->shapes)[g.shape];
  const InstanceData* inst = g.impl->instance_of(inst_id);
  if (!s.motion && !inst)
    return world_curve_hit(s, s.object_to_world, g.prepared.world_to_object, piece, r, t, si);
  const Transform m = world_from_shape_at(s, inst, r.time);
  return world_curve_hit(s, m, m.inverse(), piece, r, t, si);
}

// A quadric's or a curve piece's hit by the world ray (t may be left unset for an any-hit
// query, si null).
using UserHit = bool (*)(const GeomData&, unsigned, uint32_t, const Ray&, float*,
                         SurfaceInteraction*);

// Whether the query's skip_shape names g's world shape (not a copy under an instance).
bool skipped(const GeomData& g, const QueryContext& ctx, unsigned inst_id) {
  return g.shape == ctx.skip_shape && inst_id == RTC_INVALID_GEOMETRY_ID && g.placed == kNone;
}

// Whether Embree's ray (in the instance's space inside one) misses quadric g's box. Embree
// tests no box before calling a user primitive that shares a leaf with others, and a scene of
// a few primitives is one leaf: on own/motion-in-objects every ray called an instanced
// sphere's test, and 1 in 140 met it. The box is the one Embree's nodes test, with the same
// ray; not under a motion sampled in time steps, whose steps stand in for the exact motion
// only to within InstanceData::step_error.
bool misses_box(const GeomData& g, const InstanceData* inst, const RTCRay& r) {
  return g.quadric && !(inst && inst->step_error > 0) &&
         !g.box.meets({r.org_x, r.org_y, r.org_z}, {r.dir_x, r.dir_y, r.dir_z}, r.tfar);
}

// Embree's callbacks for user geometries: the closest hit, its interaction left in the query
// context for intersect(), and any hit. Embree does not rescale instanced rays, so t is the
// same in every space.
template <UserHit kHit>
void user_intersect(const RTCIntersectFunctionNArguments* args) {
  if (!args->valid[0]) return;
  const auto* g = static_cast<const GeomData*>(args->geometryUserPtr);
  const auto* ctx = reinterpret_cast<const QueryContext*>(args->context);
  RTCRayHit* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);
  unsigned inst_id = args->context->instID[0];
  if (skipped(*g, *ctx, inst_id) || misses_box(*g, g->impl->instance_of(inst_id), rh->ray)) return;
  Ray r = *ctx->ray;
  r.tmax = rh->ray.tfar;
  SurfaceInteraction si;
  float t;
  if (!kHit(*g, inst_id, args->primID, r, &t, &si) || !(t < rh->ray.tfar)) return;
  rh->ray.tfar = t;
  rh->hit.u = rh->hit.v = 0;
  rh->hit.Ng_x = si.n.x;
  rh->hit.Ng_y = si.n.y;
  rh->hit.Ng_z = si.n.z;
  rh->hit.primID = args->primID;
  rh->hit.geomID = args->geomID;
  rh->hit.instID[0] = inst_id;
  if (ctx->quadric_si) *ctx->quadric_si = si;
}

template <UserHit kHit>
void user_occluded(const RTCOccludedFunctionNArguments* args) {
  if (!args->valid[0]) return;
  const auto* g = static_cast<const GeomData*>(args->geometryUserPtr);
  const auto* ctx = reinterpret_cast<const QueryContext*>(args->context);
  RTCRay* ray = reinterpret_cast<RTCRay*>(args->ray);
  const unsigned inst_id = args->context->instID[0];
  if (skipped(*g, *ctx, inst_id) || misses_box(*g, g->impl->instance_of(inst_id), *ray)) return;
  Ray r = *ctx->ray;
  r.tmax = ray->tfar;
  float t = 0;
  if (kHit(*g, inst_id, args->primID, r, &t, nullptr) && t < ray->tfar) ray->tfar = -kInfinity;
}

// Embree accepts t <= tfar; pbrt-v3's interval is open at tmax.
float open_tfar(float tmax) {
  return std::isinf(tmax) ? tmax : next_float_down(tmax);
}

// Embree's interval starts at 0: hits at t ~ 0 on triangles go through
// near_filter, quadrics have pbrt-v3's conservative t tests of their own.
void init_ray(const Ray& ray, RTCRay* r) {
  r->org_x = ray.o.x;
  r->org_y = ray.o.y;
  r->org_z = ray.o.z;
  r->dir_x = ray.d.x;
  r->dir_y = ray.d.y;
  r->dir_z = ray.d.z;
  r->tnear = 0;
  r->tfar = open_tfar(ray.tmax);
  r->time = 0;
  r->mask = 0xFFFFFFFFu;
  r->id = 0;
  r->flags = 0;
}

// The t below which a triangle hit is re-tested (near_hit_rejected).
float near_t(const Ray& ray) {
  const float scale =
      std::max(std::fabs(ray.o.x), std::max(std::fabs(ray.o.y), std::fabs(ray.o.z)));
  return gamma_bound(7) * scale / length(ray.d);
}

void to_row_major_3x4(const Matrix4& m, float out[12]) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) out[4 * i + j] = m.m[i][j];
}

}  // namespace

// ---- Building ----

namespace {

// Builds the Embree scenes; a helper class so build() reads as its steps.
class Builder {
 public:
  Builder(Impl* impl, GeometryStats* stats, Bounds3* bounds, std::string* error)
      : impl_(impl),
        a_(*impl->archive),
        shapes_(*impl->shapes),
        stats_(stats),
        bounds_(bounds),
        error_(error) {}

  bool run();

 private:
  bool check_shapes();
  bool check_instances(std::vector<Transform>* transforms,
                       std::vector<const AnimatedTransform*>* motions);
  RTCScene new_scene();
  // placed: an instance (index into Impl::instances) the copy also goes through. bounds may be
  // null (a placed copy: the world bound takes the object's box instead).
  unsigned attach_mesh(RTCScene scene, uint32_t shape, bool copy, Bounds3* bounds,
                       uint32_t placed = kNone);
  unsigned attach_quadric(RTCScene scene, uint32_t shape, Bounds3* bounds);
  // Quadric geometry g (its prepared form set) as an Embree user geometry of scene.
  unsigned attach_user_quadric(RTCScene scene, const GeomData& g);
  unsigned attach_curve(RTCScene scene, uint32_t shape, Bounds3* bounds);
  void attach_instance(uint32_t child, const Transform& to_world, uint32_t archive_instance);
  // A placed object's box in its own space, as an Embree child scene of it would bound it.
  Bounds3 object_bounds(uint32_t object) const;
  // Object instance i of a placed object (Impl::placed_copies), whose box is object_box: its
  // meshes copied into the top level, its quadrics tested there through the instance's
  // transform times their own.
  void place_instance(uint32_t i, const Transform& to_world, const Bounds3& object_box);
  void place_quadric(uint32_t shape, uint32_t placed, const Transform& to_world);
  // A moving mesh inside an object whose instance's transform is a right-handed similarity
  // (rotation, uniform scale, translation: M = T R s) that, if it moves, only translates: the
  // instance's keyframes times the mesh's as one motion, or null for another instance. Its
  // interpolation is the instance's times the mesh's, as pbrt-v3 composes them (translation
  // t(t) + R s t'(t), rotation R R'(t) by slerp, scale s S'(t): each still what pbrt-v3
  // interpolates), so Embree's quaternion motion may move it exactly.
  const AnimatedTransform* placed_motion(uint32_t shape, uint32_t instance);
  // outer, outer_motion: an instance's transform or motion to compose onto the motion (a moving
  // mesh inside an object definition); then the composition is always sampled in time steps.
  void attach_moving(uint32_t child, const AnimatedTransform& motion, uint32_t archive_instance,
                     const Transform* outer = nullptr,
                     const AnimatedTransform* outer_motion = nullptr);
  void record_top(unsigned id, const GeomData* g, uint32_t instance);
  bool embree_ok();
  // Listed shapes (Impl::listing): a still world quadric, or a world mesh's triangles (its
  // Embree geometry g, whose vertex buffer holds world positions).
  void list_quadric(uint32_t shape);
  // Quadric geometry g (its prepared form set) listed behind box; skip_shape: its ShapeTable
  // index for occluded()'s skip_shape, or kNone.
  void list_quadric(const GeomData& g, const Bounds3& box, uint32_t skip_shape);
  void list_triangles(GeomData& g);

  Impl* impl_;
  const pbrta::SceneArchive& a_;
  const ShapeTable& shapes_;
  GeometryStats* stats_;
  Bounds3* bounds_;
  std::string* error_;
};

bool Builder::embree_ok() {
  std::lock_guard<std::mutex> lock(impl_->error_mutex);
  if (impl_->embree_error.empty()) return true;
  *error_ = impl_->embree_error;
  return false;
}

bool Builder::check_shapes() {
  for (uint32_t i = 0; i < shapes_.size(); ++i) {
    const ShapeInfo& s = shapes_[i];
    if (s.kind == ShapeKind::kTriangles && a_.shapes[i].mesh == pbrta::kNoIndex) {
      *error_ = "not supported yet: " + std::string(a_.type_name(s.entity)) + " shape (" +
                a_.where(s.entity) + ")";
      return false;
    }
    // Moving quadrics and curves are intersected where they are at each ray's time (inside
    // instances too); moving meshes sit under a moving Embree instance (inside objects: one per
    // instance of the object, in the top level); moving emitters are not yet.
    if (s.animated && s.area_light != kNone) {
      *error_ = "not supported yet: animated transform (motion blur) on an area light (" +
                a_.where(s.entity) + ")";
      return false;
    }
    if ((s.alpha_texture != kNone || s.shadow_alpha_texture != kNone) && !impl_->textures) {
      *error_ = a_.where(s.entity) + ": error: alpha texture but no textures were loaded";
      return false;
    }
  }
  return true;
}

// Instance transforms; a moving instance also gets its motion.
bool Builder::check_instances(std::vector<Transform>* transforms,
                              std::vector<const AnimatedTransform*>* motions) {
  for (uint32_t i = 0; i < a_.instances.size; ++i) {
    const pbrta::InstanceRecord& r = a_.instances[i];
    const pbrta::TransformRecord& t = a_.transforms[r.transform];
    Transform x = Transform::from_doubles(t.start);
    Transform end = Transform::from_doubles(t.end);
    if (!x.invertible() || x.is_projective() || !end.invertible() || end.is_projective()) {
      *error_ =
          a_.where(r.provenance) + ": error: object instance transform is singular or projective";
      return false;
    }
    transforms->push_back(x);
    motions->push_back(nullptr);
    if (!moves(t)) continue;
    motions->back() = &impl_->instance_motions.emplace_back(t.start, t.end, float(t.start_time),
                                                            float(t.end_time));
  }
  return true;
}

RTCScene Builder::new_scene() {
  RTCScene scene = rtcNewScene(impl_->device);
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
  // Spatial splits: the Cornell box, killeroo and teapot render 2-3% faster, while no reference
  // scene's build took more than 6 ms longer (the 4.5M-triangle mesh200: no change).
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  return scene;
}

void Builder::record_top(unsigned id, const GeomData* g, uint32_t instance) {
  if (impl_->top_geoms.size() <= id) {
    impl_->top_geoms.resize(id + 1, nullptr);
    impl_->top_instance.resize(id + 1, kNone);
  }
  impl_->top_geoms[id] = g;
  impl_->top_instance[id] = instance;
}

// A triangle mesh: the archive's arrays in place, or (copy) its positions
// through the shape's transform. bounds grows by its vertices in the space
// the geometry lives in.
unsigned Builder::attach_mesh(RTCScene scene, uint32_t shape, bool copy, Bounds3* bounds,
                              uint32_t placed) {
  const ShapeInfo& s = shapes_[shape];
  const MeshView& m = s.mesh;
  const float* positions = m.positions;
  const Transform* to_world = placed != kNone ? &impl_->instances[placed].to_world : nullptr;
  if (copy || to_world) {
    // 4 floats of zero padding: Embree loads vertices 16 bytes at a time.
    std::vector<float>& c = impl_->copies.emplace_back(3 * size_t(m.num_vertices) + 4, 0.f);
    for (uint32_t v = 0; v < m.num_vertices; ++v) {
      // Each transform on its own, as triangle_interaction takes an instanced vertex to world.
      Vec3 p = copy ? s.object_to_world.point(m.position(v)) : m.position(v);
      if (to_world) p = to_world->point(p);
      c[3 * v] = p.x;
      c[3 * v + 1] = p.y;
      c[3 * v + 2] = p.z;
    }
    positions = c.data();
    if (copy) ++stats_->copied_meshes;
  }
  if (bounds)
    for (uint32_t v = 0; v < m.num_vertices; ++v)
      bounds->extend(Vec3{positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]});

  GeomData& g = impl_->geoms.emplace_back();
  g.impl = impl_;
  g.shape = shape;
  g.positions = positions;
  g.copied = copy;
  g.placed = placed;
  RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  // Embree only reads these buffers; its API is not const-correct.
  rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                             const_cast<float*>(positions), 0, 3 * sizeof(float), m.num_vertices);
  rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                             const_cast<uint32_t*>(m.indices), 0, 3 * sizeof(uint32_t),
                             m.num_triangles);
  rtcSetGeometryUserData(geom, &g);
  rtcSetGeometryIntersectFilterFunction(geom,
                                        s.has_alpha_mask() ? alpha_filter_intersect : near_filter);
  rtcSetGeometryOccludedFilterFunction(
      geom, s.has_alpha_mask() || s.has_shadow_mask() ? alpha_filter_occluded : near_filter);
  rtcCommitGeometry(geom);
  unsigned id = rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
  // Embree's robust test leaks at shared vertices; masked meshes keep its own.
  if (impl_->watertight && !s.has_alpha_mask() && !s.has_shadow_mask())
    attach_vertex_patches(impl_->device, scene, positions, m.indices, m.num_vertices,
                          m.num_triangles, id, &impl_->patches.emplace_back());
  stats_->triangles += m.num_triangles;
  return id;
}

void Builder::list_quadric(uint32_t shape) {
  const ShapeInfo& s = shapes_[shape];
  const Bounds3 box = quadric_world_bounds(s);
  bounds_->extend(box);
  GeomData& g = impl_->geoms.emplace_back();
  g.impl = impl_;
  g.shape = shape;
  g.quadric = true;
  g.prepared = prepare_quadric(s);
  list_quadric(g, box, shape);
}

void Builder::list_quadric(const GeomData& g, const Bounds3& box, uint32_t skip_shape) {
  impl_->listed.add_quadric(shapes_[g.shape], g.prepared, box, uint32_t(impl_->listed_geoms.size()),
                            skip_shape);
  impl_->listed_geoms.push_back(&g);
  ++stats_->quadrics;
}

void Builder::list_triangles(GeomData& g) {
  const ShapeInfo& s = shapes_[g.shape];
  auto p = [&](uint32_t v) {
    return Vec3{g.positions[3 * v], g.positions[3 * v + 1], g.positions[3 * v + 2]};
  };
  const uint32_t tag = uint32_t(impl_->listed_geoms.size());
  const bool masked = s.has_alpha_mask() || s.has_shadow_mask();
  for (uint32_t t = 0; t < s.mesh.num_triangles; ++t) {
    const uint32_t* i = s.mesh.indices + 3 * size_t(t);
    const Vec3 v[3] = {p(i[0]), p(i[1]), p(i[2])};
    impl_->listed.add_triangle(v[0], v[1], v[2], tag, t, masked);
    g.frames.push_back(triangle_frame(s.mesh, t, v));
  }
  impl_->listed_geoms.push_back(&g);
}

unsigned Builder::attach_quadric(RTCScene scene, uint32_t shape, Bounds3* bounds) {
  const ShapeInfo& s = shapes_[shape];
  GeomData& g = impl_->geoms.emplace_back();
  g.impl = impl_;
  g.shape = shape;
  g.quadric = true;
  g.prepared = prepare_quadric(s);
  g.box = quadric_world_bounds(s);
  bounds->extend(g.box);
  return attach_user_quadric(scene, g);
}

unsigned Builder::attach_user_quadric(RTCScene scene, const GeomData& g) {
  RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(geom, 1);
  // Embree's API is not const-correct; the callbacks only read it.
  rtcSetGeometryUserData(geom, const_cast<GeomData*>(&g));
  rtcSetGeometryBoundsFunction(geom, quadric_bounds, nullptr);
  rtcSetGeometryIntersectFunction(geom, user_intersect<world_quadric_hit>);
  rtcSetGeometryOccludedFunction(geom, user_occluded<world_quadric_hit>);
  rtcCommitGeometry(geom);
  unsigned id = rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
  ++stats_->quadrics;
  return id;
}

// A curve: one Embree user primitive per piece (curve.h), in the space of the
// scene it joins (world, or an object's instance space), as quadrics are.
unsigned Builder::attach_curve(RTCScene scene, uint32_t shape, Bounds3* bounds) {
  const ShapeInfo& s = shapes_[shape];
  const CurveShape& c = *s.curve;
  for (uint32_t i = 0; i < c.num_pieces(); ++i) bounds->extend(curve_piece_bounds(s, i));
  GeomData& g = impl_->geoms.emplace_back();
  g.impl = impl_;
  g.shape = shape;
  g.curve = true;
  g.prepared.world_to_object = s.object_to_world.inverse();
  RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(geom, c.num_pieces());
  rtcSetGeometryUserData(geom, &g);
  rtcSetGeometryBoundsFunction(geom, curve_bounds, nullptr);
  rtcSetGeometryIntersectFunction(geom, user_intersect<world_curve_piece_hit>);
  rtcSetGeometryOccludedFunction(geom, user_occluded<world_curve_piece_hit>);
  rtcCommitGeometry(geom);
  unsigned id = rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
  stats_->curves += c.num_pieces();
  return id;
}

// An Embree instance of child scene `child` for the archive's object instance
// `archive_instance`. Its object's box goes through the transform into the world bound, as
// pbrt-v3's TransformedPrimitive does.
void Builder::attach_instance(uint32_t child, const Transform& to_world,
                              uint32_t archive_instance) {
  InstanceData d;
  d.to_world = to_world;
  d.child = child;
  d.archive_instance = archive_instance;
  d.mirrors = to_world.swaps_handedness();
  impl_->instances.push_back(d);
  RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(geom, impl_->children[child].scene);
  float xfm[12];
  to_row_major_3x4(to_world.matrix(), xfm);
  rtcSetGeometryTransform(geom, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, xfm);
  rtcCommitGeometry(geom);
  unsigned id = rtcAttachGeometry(impl_->top, geom);
  rtcReleaseGeometry(geom);
  record_top(id, nullptr, uint32_t(impl_->instances.size() - 1));
  bounds_->extend(to_world.bounds(impl_->children[child].bounds));
}

Bounds3 Builder::object_bounds(uint32_t object) const {
  const pbrta::ObjectRecord& rec = a_.objects[object];
  Bounds3 box;
  for (uint32_t k = 0; k < rec.num_shapes; ++k) {
    const ShapeInfo& s = shapes_[a_.object_shapes[rec.first_shape + k]];
    if (is_quadric(s.kind)) {
      box.extend(quadric_world_bounds(s));
    } else if (!empty_mesh(s)) {
      const bool copy = !s.object_to_world.is_identity();  // as attach_mesh's buffer
      for (uint32_t v = 0; v < s.mesh.num_vertices; ++v)
        box.extend(copy ? s.object_to_world.point(s.mesh.position(v)) : s.mesh.position(v));
    }
  }
  return box;
}

void Builder::place_instance(uint32_t i, const Transform& to_world, const Bounds3& object_box) {
  InstanceData d;
  d.to_world = to_world;
  d.archive_instance = i;
  d.mirrors = to_world.swaps_handedness();
  impl_->instances.push_back(d);
  const uint32_t index = uint32_t(impl_->instances.size() - 1);
  const pbrta::ObjectRecord& rec = a_.objects[a_.instances[i].object];
  for (uint32_t k = 0; k < rec.num_shapes; ++k) {
    const uint32_t shape = a_.object_shapes[rec.first_shape + k];
    const ShapeInfo& s = shapes_[shape];
    if (is_quadric(s.kind)) {
      place_quadric(shape, index, to_world);
    } else if (!empty_mesh(s)) {
      const unsigned id =
          attach_mesh(impl_->top, shape, !s.object_to_world.is_identity(), nullptr, index);
      record_top(id, &impl_->geoms.back(), kNone);
      if (impl_->listing == Impl::Listing::kAll) list_triangles(impl_->geoms.back());
    }
  }
  // pbrt-v3's world bound takes the object's box through the instance's transform, as
  // attach_instance does, not the (tighter) box of the copied vertices.
  bounds_->extend(to_world.bounds(object_box));
  ++stats_->instances;
  ++stats_->placed_instances;
}

// The instance's transform times the shape's, prepared once: one transform per test, where an
// Embree instance takes the ray through both. Its box holds the surface under the composed
// transform (with that transform's rounding) and under the two (pbrt-v3's world bound).
void Builder::place_quadric(uint32_t shape, uint32_t placed, const Transform& to_world) {
  ShapeInfo composed = shapes_[shape];
  composed.object_to_world = to_world * composed.object_to_world;
  GeomData& g = impl_->geoms.emplace_back();
  g.impl = impl_;
  g.shape = shape;
  g.quadric = true;
  g.placed = placed;
  g.prepared = prepare_quadric(composed);
  g.box = quadric_world_bounds(composed);
  g.box.extend(to_world.bounds(quadric_world_bounds(shapes_[shape])));
  if (impl_->listing != Impl::Listing::kNone) {
    list_quadric(g, g.box, kNone);
  } else {
    record_top(attach_user_quadric(impl_->top, g), &g, kNone);
  }
}

// Time steps for a motion Embree's quaternion decomposition cannot hold. Between steps Embree
// interpolates the matrices linearly; pbrt-v3's path (slerped rotation times linearly
// interpolated stretch) bends away from that chord. The steps double until, at every segment's
// middle, the child's box corners lie within kStepError of the object's size of where they
// should be (or reach kMaxTimeSteps); twice the largest such distance is the error reported
// (the farthest point of a segment may lie off its middle).
constexpr float kStepError = 2e-5f;
constexpr int kMaxTimeSteps = RTC_MAX_TIME_STEP_COUNT;

std::vector<Transform> motion_steps(const InstanceData& motion, const Bounds3& box, float* error) {
  Vec3 corners[8];
  for (int c = 0; c < 8; ++c)
    corners[c] = {c & 1 ? box.hi.x : box.lo.x, c & 2 ? box.hi.y : box.lo.y,
                  c & 4 ? box.hi.z : box.lo.z};
  const float t0 = motion.motion->start_time(), t1 = motion.motion->end_time();
  auto time_of = [&](double f) { return f >= 1 ? t1 : t0 + (t1 - t0) * float(f); };
  // The object's own size (its box's diagonal where it is largest), not the extent it sweeps:
  // a small thing moving far needs as fine steps as one standing still.
  float size = 0;
  for (int k = 0; k <= 16; ++k) {
    Bounds3 at_k;
    for (const Vec3& p : corners) at_k.extend(motion.at(time_of(k / 16.0)).point(p));
    size = std::max(size, length(at_k.diagonal()));
  }
  const float tolerance = kStepError * size;
  for (int steps = 2;; steps = std::min(2 * steps - 1, kMaxTimeSteps)) {
    std::vector<Transform> at(static_cast<size_t>(steps));
    for (int k = 0; k < steps; ++k) at[size_t(k)] = motion.at(time_of(double(k) / (steps - 1)));
    float worst = 0;
    for (int k = 0; k + 1 < steps; ++k) {
      const Transform mid = motion.at(time_of((k + 0.5) / (steps - 1)));
      for (const Vec3& p : corners)
        worst = std::max(
            worst,
            length((at[size_t(k)].point(p) + at[size_t(k) + 1].point(p)) * 0.5f - mid.point(p)));
    }
    if (!(worst > tolerance) || steps == kMaxTimeSteps) {
      // The corners' deviation bounds every point's: Embree's and the exact transforms are
      // affine at each time, and a point of the box is a blend of its corners.
      *error = 2 * worst;  // margin: the farthest point of a segment may lie off its middle
      return at;
    }
  }
}

// A moving mesh's or instance's child scene under an Embree instance that moves with it; hits
// are rebuilt with AnimatedTransform::at, pbrt-v3's interpolation, at the ray's time.
// Keyframes whose scale part is diagonal go to Embree's quaternion motion blur: translation and
// scale linear, rotation by slerp, exactly as pbrt-v3 interpolates. Others (a scale along axes
// the rotation turns: pbrt-v3's symmetric S has off-diagonal terms, Embree's decomposition
// cannot hold them) get matrices sampled from at() at time steps (motion_steps).
void Builder::attach_moving(uint32_t child, const AnimatedTransform& motion,
                            uint32_t archive_instance, const Transform* outer,
                            const AnimatedTransform* outer_motion) {
  InstanceData d;
  d.child = child;
  d.archive_instance = archive_instance;
  d.motion = &motion;
  d.composed = outer != nullptr || outer_motion != nullptr;
  if (outer) d.outer = *outer;
  d.outer_motion = outer_motion;
  d.to_world = d.at(motion.start_time());
  d.mirrors = d.to_world.swaps_handedness();
  impl_->instances.push_back(d);
  impl_->has_moving_meshes = true;
  impl_->motion_t0 = motion.start_time();
  impl_->motion_t1 = motion.end_time();
  RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(geom, impl_->children[child].scene);
  float t[2][3], q[2][4], sc[2][3];
  if (!d.composed && motion.diagonal_keyframe(0, t[0], q[0], sc[0]) &&
      motion.diagonal_keyframe(1, t[1], q[1], sc[1])) {
    rtcSetGeometryTimeStepCount(geom, 2);
    for (int k = 0; k < 2; ++k) {
      RTCQuaternionDecomposition x;
      rtcInitQuaternionDecomposition(&x);
      x.scale_x = sc[k][0];
      x.scale_y = sc[k][1];
      x.scale_z = sc[k][2];
      x.quaternion_i = q[k][0];
      x.quaternion_j = q[k][1];
      x.quaternion_k = q[k][2];
      x.quaternion_r = q[k][3];
      x.translation_x = t[k][0];
      x.translation_y = t[k][1];
      x.translation_z = t[k][2];
      rtcSetGeometryTransformQuaternion(geom, unsigned(k), &x);
    }
  } else {
    InstanceData& placed = impl_->instances.back();
    const std::vector<Transform> steps =
        motion_steps(placed, impl_->children[child].bounds, &placed.step_error);
    ++stats_->sampled_motions;
    rtcSetGeometryTimeStepCount(geom, unsigned(steps.size()));
    for (size_t k = 0; k < steps.size(); ++k) {
      float xfm[12];
      to_row_major_3x4(steps[k].matrix(), xfm);
      rtcSetGeometryTransform(geom, unsigned(k), RTC_FORMAT_FLOAT3X4_ROW_MAJOR, xfm);
    }
  }
  rtcCommitGeometry(geom);
  unsigned id = rtcAttachGeometry(impl_->top, geom);
  rtcReleaseGeometry(geom);
  record_top(id, nullptr, uint32_t(impl_->instances.size() - 1));
}

const AnimatedTransform* Builder::placed_motion(uint32_t shape, uint32_t instance) {
  const pbrta::TransformRecord& outer = a_.transforms[a_.instances[instance].transform];
  const pbrta::TransformRecord& inner = a_.transforms[a_.shapes[shape].transform];
  // Columns of the upper 3x3 orthogonal, of one length, right-handed; the same 3x3 at the end
  // (only the translation moves); no projective row.
  const double* m = outer.start;
  double len2[3];
  for (int j = 0; j < 3; ++j) {
    len2[j] = 0;
    for (int i = 0; i < 3; ++i) len2[j] += m[4 * i + j] * m[4 * i + j];
  }
  const double tol = 1e-9 * len2[0];
  for (int j = 0; j < 3; ++j) {
    if (!(std::fabs(len2[j] - len2[0]) <= tol)) return nullptr;
    for (int k = j + 1; k < 3; ++k) {
      double d = 0;
      for (int i = 0; i < 3; ++i) d += m[4 * i + j] * m[4 * i + k];
      if (std::fabs(d) > tol) return nullptr;
    }
  }
  // check_instances() refused singular transforms already.
  if (Transform::from_doubles(m).swaps_handedness()) return nullptr;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (outer.end[4 * i + j] != m[4 * i + j]) return nullptr;
  for (const double* x : {outer.start, outer.end})
    if (x[12] != 0 || x[13] != 0 || x[14] != 0 || x[15] != 1) return nullptr;
  auto times = [&](const double* a, const double* b, double* out) {
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        double v = 0;
        for (int k = 0; k < 4; ++k) v += a[4 * i + k] * b[4 * k + j];
        out[4 * i + j] = v;
      }
  };
  double start[16], end[16];
  times(outer.start, inner.start, start);
  times(outer.end, inner.end, end);
  return &impl_->instance_motions.emplace_back(start, end, float(inner.start_time),
                                               float(inner.end_time));
}

bool Builder::run() {
  std::vector<Transform> instance_transforms;
  std::vector<const AnimatedTransform*> instance_motions;
  if (!check_shapes() || !check_instances(&instance_transforms, &instance_motions)) return false;

  impl_->top = new_scene();
  auto add_child = [&] {
    impl_->children.push_back({new_scene(), {}, {}});
    return uint32_t(impl_->children.size() - 1);
  };
  auto record_child = [&](uint32_t child, unsigned id, const GeomData* g) {
    auto& geoms = impl_->children[child].geoms;
    if (geoms.size() <= id) geoms.resize(id + 1, nullptr);
    geoms[id] = g;
  };

  // World shapes, in the top level: quadrics and curves (their callbacks take world rays), and
  // still meshes, those with a transform copied through it as pbrt-v3 transforms them at
  // load. (Grouping meshes by transform under Embree instances instead kept the archive's
  // arrays in place, but cost every ray the instance level and every hit three vertex
  // transforms: the Cornell box, whose walls each have a transform, rendered 13% slower,
  // killeroo 8%, for 0.3 MB less peak memory at most over the reference scenes.)
  std::vector<std::pair<uint32_t, uint32_t>> moving;  // (child, shape) of moving meshes
  for (uint32_t i = 0; i < shapes_.size(); ++i) {
    const ShapeInfo& s = shapes_[i];
    if (s.object != kNone) continue;
    if (is_quadric(s.kind) && impl_->listing != Impl::Listing::kNone && listable(s)) {
      list_quadric(i);
    } else if (is_quadric(s.kind) || s.kind == ShapeKind::kCurve) {
      unsigned id = s.kind == ShapeKind::kCurve ? attach_curve(impl_->top, i, bounds_)
                                                : attach_quadric(impl_->top, i, bounds_);
      record_top(id, &impl_->geoms.back(), kNone);
    } else if (!empty_mesh(s) && s.motion) {
      uint32_t child = add_child();
      Bounds3 object_box;
      unsigned id = attach_mesh(impl_->children[child].scene, i, false, &object_box);
      impl_->children[child].bounds.extend(object_box);
      record_child(child, id, &impl_->geoms.back());
      moving.push_back({child, i});
      bounds_->extend(s.motion->motion_bounds(object_box));
    } else if (!empty_mesh(s)) {
      unsigned id = attach_mesh(impl_->top, i, !s.object_to_world.is_identity(), bounds_);
      record_top(id, &impl_->geoms.back(), kNone);
      if (impl_->listing == Impl::Listing::kAll) list_triangles(impl_->geoms.back());
    }
  }

  // Object definitions: one child scene each, in instance space.
  std::vector<uint32_t> object_child(a_.objects.size, kNone);
  // Per object: (child, shape) of its moving meshes.
  std::vector<std::vector<std::pair<uint32_t, uint32_t>>> moving_in_object(a_.objects.size);
  std::vector<bool> instanced(a_.objects.size, false);
  for (const pbrta::InstanceRecord& r : a_.instances) instanced[r.object] = true;
  // Placed objects: their boxes, once each, for their instances' world bounds.
  std::vector<Bounds3> placed_box(a_.objects.size);
  for (uint32_t o = 0; o < a_.objects.size; ++o) {
    if (impl_->placed_copies[o] > 0) {
      placed_box[o] = object_bounds(o);
      continue;
    }
    if (!instanced[o]) continue;  // defined, never used
    const pbrta::ObjectRecord& rec = a_.objects[o];
    uint32_t child = kNone;
    for (uint32_t k = 0; k < rec.num_shapes; ++k) {
      uint32_t shape = a_.object_shapes[rec.first_shape + k];
      const ShapeInfo& s = shapes_[shape];
      if (s.kind == ShapeKind::kTriangles && empty_mesh(s)) continue;
      if (s.kind == ShapeKind::kTriangles && s.motion) {
        // A scene of its own, in its own space, placed per instance below.
        const uint32_t own = add_child();
        unsigned id =
            attach_mesh(impl_->children[own].scene, shape, false, &impl_->children[own].bounds);
        record_child(own, id, &impl_->geoms.back());
        moving_in_object[o].push_back({own, shape});
        continue;
      }
      if (child == kNone) child = add_child();
      Impl::Child& c = impl_->children[child];
      unsigned id = is_quadric(s.kind) ? attach_quadric(c.scene, shape, &c.bounds)
                    : s.kind == ShapeKind::kCurve
                        ? attach_curve(c.scene, shape, &c.bounds)
                        : attach_mesh(c.scene, shape, !s.object_to_world.is_identity(), &c.bounds);
      record_child(child, id, &impl_->geoms.back());
    }
    object_child[o] = child;
  }
  for (Impl::Child& c : impl_->children) rtcCommitScene(c.scene);
  if (!embree_ok()) return false;

  // Embree's ray time spans one keyframe interval, shared by every moving mesh and instance.
  std::vector<const AnimatedTransform*> all_moving;
  for (auto [child, shape] : moving) all_moving.push_back(shapes_[shape].motion);
  for (const auto& in_object : moving_in_object)
    for (auto [child, shape] : in_object) all_moving.push_back(shapes_[shape].motion);
  for (const AnimatedTransform* m : instance_motions)
    if (m) all_moving.push_back(m);
  for (const AnimatedTransform* m : all_moving)
    if (m->start_time() != all_moving[0]->start_time() ||
        m->end_time() != all_moving[0]->end_time()) {
      *error_ = "not supported yet: moving meshes or instances with different TransformTimes";
      return false;
    }
  for (auto [child, shape] : moving) attach_moving(child, *shapes_[shape].motion, kNone);
  for (uint32_t i = 0; i < a_.instances.size; ++i) {
    const uint32_t object = a_.instances[i].object;
    const AnimatedTransform* m = instance_motions[i];
    if (impl_->placed_copies[object] > 0) {
      place_instance(i, instance_transforms[i], placed_box[object]);
      continue;
    }
    for (auto [own, shape] : moving_in_object[object]) {
      const ShapeInfo& s = shapes_[shape];
      if (const AnimatedTransform* whole = placed_motion(shape, i)) {
        attach_moving(own, *whole, i);  // one motion, exact
      } else {
        attach_moving(own, *s.motion, i, m ? nullptr : &instance_transforms[i], m);
      }
      const Bounds3 box = s.motion->motion_bounds(impl_->children[own].bounds);
      bounds_->extend(m ? m->motion_bounds(box) : instance_transforms[i].bounds(box));
    }
    uint32_t child = object_child[object];
    if (child == kNone && moving_in_object[object].empty()) continue;  // an empty object
    ++stats_->instances;
    if (child == kNone) continue;
    if (m) {
      attach_moving(child, *m, i);
      bounds_->extend(m->motion_bounds(impl_->children[child].bounds));
    } else {
      attach_instance(child, instance_transforms[i], i);
    }
  }
  rtcCommitScene(impl_->top);
  return embree_ok();
}

}  // namespace

// ---- SceneGeometry ----

SceneGeometry::SceneGeometry() = default;
SceneGeometry::~SceneGeometry() = default;

namespace {

// Objects whose every shape is a still quadric or still triangle mesh (quadrics without masks)
// and whose every instance is still, in the archive's order, while their copies (triangles,
// or one a quadric, times instances) fit in max_placed: by object, its instance count if
// placed, else 0 (Impl::placed_copies).
std::vector<uint32_t> choose_placed(const pbrta::SceneArchive& a, const ShapeTable& shapes,
                                    size_t max_placed) {
  std::vector<uint32_t> placed(a.objects.size, 0);
  std::vector<uint32_t> uses(a.objects.size, 0);
  std::vector<bool> moving(a.objects.size, false);
  for (const pbrta::InstanceRecord& r : a.instances) {
    ++uses[r.object];
    if (moves(a.transforms[r.transform])) moving[r.object] = true;
  }
  uint64_t budget = max_placed;
  for (uint32_t o = 0; o < a.objects.size; ++o) {
    if (uses[o] == 0 || moving[o]) continue;
    const pbrta::ObjectRecord& rec = a.objects[o];
    uint64_t copies = 0;
    bool still = true;
    for (uint32_t k = 0; k < rec.num_shapes; ++k) {
      const ShapeInfo& s = shapes[a.object_shapes[rec.first_shape + k]];
      if (is_quadric(s.kind)) {
        still = still && !s.motion && !s.has_alpha_mask() && !s.has_shadow_mask();
        ++copies;
      } else {
        still = still && s.kind == ShapeKind::kTriangles && !s.motion;
        copies += empty_mesh(s) ? 0 : s.mesh.num_triangles;
      }
    }
    if (!still || copies == 0 || copies * uses[o] > budget) continue;
    budget -= copies * uses[o];
    placed[o] = uses[o];
  }
  return placed;
}

// Which shapes build() lists (Impl::listing). callgrind over the reference scenes that
// qualify (instructions at --spp 2, listed against all in Embree): listed whole, the scenes
// of a few triangles and quadrics take 3-13% fewer. A room of 14 triangles takes 9-16% more
// instructions listed (Embree's tree tests four triangles at once), yet renders 6-12% faster
// built for the CPU (the nine hm-* rooms, 1 thread, 3 interleaved rounds; veach-mis's 17
// primitives 3%), so up to 16 triangles are listed. Quadrics alone listed beside the tree:
// 5-9% fewer where they are few and were Embree's only user geometry (a cloud's disk, a
// room's light sphere); where curves or moving quadrics keep Embree calling back anyway, or
// with more quadrics, 1-6% more (all-shapes, anim-bluespheres, veach-mis's five).
Impl::Listing choose_listing(const Impl& impl, size_t max_listed) {
  if (max_listed == 0 || impl.watertight) return Impl::Listing::kNone;
  const ShapeTable& shapes = *impl.shapes;
  const pbrta::SceneArchive& a = *impl.archive;
  // Placed objects' shapes count as world shapes, once per instance.
  bool instanced = false;
  for (const pbrta::InstanceRecord& r : a.instances)
    instanced = instanced || impl.placed_copies[r.object] == 0;
  size_t quadrics = 0, triangles = 0;
  bool unlisted_user_geometry = false, other_meshes = false;
  for (uint32_t i = 0; i < shapes.size(); ++i) {
    const ShapeInfo& s = shapes[i];
    const bool placed = s.object != kNone && impl.placed_copies[s.object] > 0;
    const uint32_t copies = placed ? impl.placed_copies[s.object] : 1;
    if (is_quadric(s.kind) && (listable(s) || placed)) {
      quadrics += copies;
    } else if (is_quadric(s.kind) || s.kind == ShapeKind::kCurve) {
      unlisted_user_geometry = unlisted_user_geometry || s.object == kNone || instanced;
    } else if (listable(s) || placed) {
      triangles += empty_mesh(s) ? 0 : size_t(s.mesh.num_triangles) * copies;
    } else if (s.object == kNone || placed) {
      other_meshes = true;
    }
  }
  if (!instanced && !unlisted_user_geometry && !other_meshes &&
      triangles <= SceneGeometry::kMaxListedTriangles && quadrics + triangles <= max_listed)
    return Impl::Listing::kAll;
  if (quadrics > 0 && quadrics <= SceneGeometry::kMaxListedBesideTree && !unlisted_user_geometry)
    return Impl::Listing::kQuadrics;
  return Impl::Listing::kNone;
}

}  // namespace

bool SceneGeometry::build(const pbrta::SceneArchive& archive, const ShapeTable& shapes,
                          const TextureSet* textures, std::string* error) {
  auto start = std::chrono::steady_clock::now();
  impl_ = std::make_unique<Impl>();
  world_bounds_ = Bounds3{};
  stats_ = GeometryStats{};
  impl_->archive = &archive;
  impl_->shapes = &shapes;
  impl_->textures = textures;
  impl_->device = rtcNewDevice(embree_config_.empty() ? nullptr : embree_config_.c_str());
  if (!impl_->device) {
    *error = "Embree: cannot create a device (error " +
             std::to_string(int(rtcGetDeviceError(nullptr))) + ")";
    impl_.reset();
    return false;
  }
  rtcSetDeviceErrorFunction(impl_->device, on_embree_error, impl_.get());
  rtcSetDeviceMemoryMonitorFunction(impl_->device, on_embree_memory, impl_.get());

  impl_->watertight = watertight_;
  impl_->placed_copies = choose_placed(archive, shapes, max_placed_);
  impl_->listing = choose_listing(*impl_, max_listed_);
  impl_->listed.set_mask_test(listed_mask_drops, impl_.get());
  Builder builder(impl_.get(), &stats_, &world_bounds_, error);
  if (!builder.run()) {
    impl_.reset();
    return false;
  }
  stats_.listed = impl_->listed.size();
  stats_.embree_bytes = uint64_t(std::max<int64_t>(0, impl_->embree_bytes.load()));
  stats_.build_seconds = seconds_since(start);
  return true;
}

bool SceneGeometry::intersect(const Ray& ray, SurfaceInteraction* si, uint32_t skip_shape) const {
  PendingHit pending;
  if (!intersect_ids(ray, si, &pending, skip_shape)) return false;
  complete(pending, ray, si);
  return true;
}

bool SceneGeometry::intersect_ids(const Ray& ray, SurfaceInteraction* si, PendingHit* pending,
                                  uint32_t skip_shape) const {
  if (!impl_ || !(ray.tmax > 0)) return false;
  PrimList::Hit h;
  if (impl_->listing == Impl::Listing::kAll) {
    if (!impl_->listed.closest(ray, &h, si, skip_shape)) return false;
    impl_->record_hit(impl_->listed_geoms[h.tag], nullptr, h.prim, h.b1, h.b2, h.t, si, pending);
    return true;
  }
  QueryContext ctx;
  rtcInitIntersectContext(&ctx.rtc);
  ctx.ray = &ray;
  ctx.quadric_si = si;
  ctx.near_t = near_t(ray);
  ctx.skip_shape = skip_shape;
  RTCRayHit rh;
  init_ray(ray, &rh.ray);
  rh.ray.time = impl_->embree_time(ray.time);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->top, &ctx.rtc, &rh);
  const bool found = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  if (impl_->listing == Impl::Listing::kQuadrics) {
    // The listed quadrics, up to Embree's hit: a nearer one replaces it (and its *si).
    Ray nearer = ray;
    if (found) nearer.tmax = rh.ray.tfar;
    if (impl_->listed.closest(nearer, &h, si, skip_shape)) {
      impl_->record_hit(impl_->listed_geoms[h.tag], nullptr, 0, 0, 0, h.t, si, pending);
      return true;
    }
  }
  if (!found) return false;

  // A quadric's or curve's callback left the accepted hit in *si.
  const InstanceData* inst = impl_->instance_of(rh.hit.instID[0]);
  impl_->record_hit(impl_->geom_of(inst, rh.hit.geomID), inst, rh.hit.primID, rh.hit.u, rh.hit.v,
                    rh.ray.tfar, si, pending);
  return true;
}

void SceneGeometry::complete(const PendingHit& pending, const Ray& ray,
                             SurfaceInteraction* si) const {
  if (!pending.geom) return;
  const auto* g = static_cast<const GeomData*>(pending.geom);
  const auto* inst = static_cast<const InstanceData*>(pending.inst);
  float t = pending.t;
  // fill_triangle leaves shape and instance as intersect_ids set them.
  impl_->fill_triangle(*g, inst, pending.prim, pending.u, pending.v, ray, &t, si);
  si->t_hit = t;
}

bool SceneGeometry::occluded(const Ray& ray, uint32_t skip_shape) const {
  if (!impl_ || !(ray.tmax > 0)) return false;
  if (impl_->listing != Impl::Listing::kNone && impl_->listed.any(ray, skip_shape)) return true;
  if (impl_->listing == Impl::Listing::kAll) return false;
  QueryContext ctx;
  rtcInitIntersectContext(&ctx.rtc);
  ctx.ray = &ray;
  ctx.quadric_si = nullptr;
  ctx.near_t = near_t(ray);
  ctx.skip_shape = skip_shape;
  RTCRay r;
  init_ray(ray, &r);
  r.time = impl_->embree_time(ray.time);
  rtcOccluded1(impl_->top, &ctx.rtc, &r);
  return r.tfar < 0;
}

}  // namespace rt
