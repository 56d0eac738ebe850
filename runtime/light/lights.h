// runtime/light/lights.h — every light of a scene, as pbrt-v3 builds them (book ch. 12, 14.2).
//
// LightSet holds the archive's LightSource entities (in archive order) and
// then one area light per emitting quadric and per emitting triangle (shape
// order, triangles in mesh order), as pbrt-v3 makes one DiffuseAreaLight per
// triangle. Lights are plain records dispatched by a switch on LightKind, so
// sampling costs no virtual call and no allocation.
//
// Contract, per light index in [0, count()):
//   sample_li: pbrt-v3's Sample_Li: incident radiance at ref from a point on
//     the light (s->p_light, time = ref.time), direction s->wi, solid-angle
//     s->pdf (1 for delta lights, s->delta set). s->pdf == 0: no contribution.
//     The returned Rgb equals s->li.
//   pdf_li: the solid-angle pdf sample_li would have for wi; for an area light
//     `hit` is where the ray along wi met that light (0 when hit is nullptr);
//     0 for delta lights.
//   area_light_at / area_le: emission seen at a surface hit (one-sided: the
//     side hit.n faces, unless twosided). Instanced shapes never emit (pbrtc
//     drops area lights inside object definitions, as pbrt-v3 does).
//   power: pbrt-v3's Light::Power, for the "power" light distribution.
//   sample_le / pdf_le: pbrt-v3's Sample_Le / Pdf_Le, emission leaving the
//     light for light tracing (bdpt, sppm); see light_emission.cpp. Their
//     conventions are pbrt-v3's, which bdpt's weights rely on: positional
//     lights sample pdf_pos 1 but pdf_le reports 0 (a delta position has no
//     area density); distant lights sample pdf_dir 1 but pdf_le reports 0;
//     *n_light is the ray direction for every light but an area light (so
//     |cos(n_light, d)| is 1 there), whose n_light is the surface normal.
// Every light's `scale` multiplies its L/I. The spot falloff is pbrt-v3's
// fourth power of the linear ramp in cos theta. Environment maps are looked up
// (bilinear, level 0) and then multiplied by L * scale; their Distribution2D
// is the archive's precomputed distribution image. After build() the set is
// read-only and shared by render threads.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "format/scene_archive.h"
#include "runtime/core/interaction.h"
#include "runtime/core/rgb.h"
#include "runtime/core/sampling.h"
#include "runtime/core/transform.h"
#include "runtime/geometry/shape_sampling.h"
#include "runtime/geometry/shape_table.h"
#include "runtime/texture/mipmap.h"

namespace rt {

enum class LightKind : uint8_t {
  kPoint,
  kSpot,
  kDistant,
  kArea,
  kInfinite,
  kProjection,
  kGoniometric
};

struct LightSample {
  Rgb li;
  Vec3 wi;
  float pdf = 0;
  Interaction p_light;
  bool delta = false;
  // An area light's own sphere or disk: it cannot block the shadow ray to
  // p_light (SceneGeometry::occluded's skip_shape). kNone otherwise.
  uint32_t own_shape = kNone;
  // sample_li(..., defer_map) of an environment map: li is still the light's scale, without
  // the texel lookup, which finish_li() adds (kNone: li is whole).
  uint32_t pending_map = kNone;
  Vec2 map_uv;
};

// A unit direction w's (u, v) in one infinite light's map and its sin theta, as
// LightSet::prefetch_infinite computes them: given back to infinite_le_one for the same light
// and a ray along the same w, they spare it the acos and atan2 (any other ray ignores them).
struct MapDirection {
  Vec3 w;  // zero: no direction
  Vec2 st;
  float sin_theta = 0;
};

class LightSet {
 public:
  // world_bounds: the scene's bounds (distant and infinite lights sit outside its sphere).
  [[nodiscard]] bool build(const pbrta::SceneArchive& archive, const ShapeTable& shapes,
                           const Bounds3& world_bounds, std::string* error);
  uint32_t count() const { return uint32_t(entries_.size()); }
  LightKind kind(uint32_t light) const { return entries_[light].kind; }
  bool is_delta(uint32_t light) const;
  int nsamples(uint32_t light) const;
  // defer_map: an environment map's texels (a cache miss) are read by finish_li(*s) instead,
  // which a caller calls once it knows the sample counts (its shadow ray is clear): the miss
  // then loads behind the ray, and a blocked sample never reads it. *s's li is already
  // non-black exactly when the light's scale is.
  Rgb sample_li(uint32_t light, const Interaction& ref, Vec2 u, LightSample* s,
                bool defer_map = false) const;
  Rgb finish_li(const LightSample& s) const {
    return s.pending_map == kNone ? s.li : maps_[s.pending_map].lookup_trilinear(s.map_uv) * s.li;
  }
  // sample_li in two steps, for callers that sample one light with the same u from many
  // points (the spatial light grid): a light on a triangle samples the same point for a given
  // u wherever ref is. triangle_point gives that point and its area pdf (false for other
  // lights); li_at_triangle_point then gives what sample_li gives, bit for bit.
  bool triangle_point(uint32_t light, Vec2 u, Interaction* it, float* pdf_area) const;
  Rgb li_at_triangle_point(uint32_t light, const Interaction& ref, Interaction it, float pdf_area,
                           LightSample* s) const;
  // All the grid reads of that sample, from a point in free space: li.luminance() / pdf, the
  // same value (0 where the sample's pdf is 0).
  float triangle_point_weight(uint32_t light, Vec3 ref_p, const Interaction& it,
                              float pdf_area) const;
  float pdf_li(uint32_t light, const Interaction& ref, Vec3 wi, const Interaction* hit) const;
  uint32_t area_light_at(const SurfaceInteraction& hit) const;  // kNone if not emitting
  // false only when `ray` (t > 0, any length) cannot meet area light `light`'s shape: it misses
  // a box padded well beyond rounding around it. pbrt-v3's EstimateDirect asks the light's
  // shape alone (Pdf_Li) before it traces a scattering sample through the scene, and traces
  // only a direction that meets it; the box answers the same for the directions that matter
  // (the shape's neighbourhood) at a slab test's cost. true for every other kind of light.
  bool may_meet(uint32_t light, const Ray& ray) const;
  Rgb area_le(const SurfaceInteraction& hit, Vec3 w) const;
  Rgb infinite_le(const RayDifferential& ray) const;
  // One infinite light's radiance along an escaping ray (0 for other kinds):
  // direct lighting's BSDF sample counts only the light it is estimating. With pdf_li, also
  // pdf_li(light, any, ray.d) from the same spherical angles (an escaping BSDF sample needs
  // both for its MIS weight; the angles' acos and atan2 are then paid once).
  Rgb infinite_le_one(uint32_t light, const RayDifferential& ray, float* pdf_li = nullptr,
                      const MapDirection& known = {}) const;
  // A hint: starts loading what infinite_le_one and pdf_li read for a ray leaving along a unit
  // w (world) should light `light` be an infinite map, so that a caller who traces the ray
  // first finds them in cache. An environment map and its distribution are tens of MB, read
  // at random: each read is a miss, and tracing hides it. Returns w's map coordinates (no
  // direction for other lights).
  MapDirection prefetch_infinite(uint32_t light, Vec3 w) const;
  // A hint, no result: starts loading what sample_li(light, it, u, ...) will read of an
  // environment map's sampling table, so that work between the two calls hides the miss.
  void prefetch_sample(uint32_t light, Vec2 u) const;
  bool has_infinite() const { return !infinite_lights_.empty(); }
  const std::vector<uint32_t>& infinite_lights() const { return infinite_lights_; }
  Rgb power(uint32_t light) const;
  // pbrt-v3's Sample_Le: a ray leaving light `light` at time `time` (ray->time = time),
  // *n_light (an area light: its surface normal at ray->o, never flipped for a
  // two-sided light's back; every other light: ray->d, as pbrt-v3 sets it), the
  // area pdf *pdf_pos of ray->o (1 for delta positions; 1 / (pi r^2) of the disk
  // of the world sphere for distant and infinite lights) and the solid-angle pdf
  // *pdf_dir of ray->d (1 for a distant light's delta direction). Returns the
  // radiance (point-like lights: intensity) leaving along the ray; 0 with zero
  // pdfs when there is nothing to sample. u1 places the origin (point-like
  // lights: the direction), u2 the direction (distant lights: unused; infinite:
  // the disk point), as in pbrt-v3.
  Rgb sample_le(uint32_t light, Vec2 u1, Vec2 u2, float time, Ray* ray, Vec3* n_light,
                float* pdf_pos, float* pdf_dir) const;
  // pbrt-v3's Pdf_Le for a ray leaving the light (an area light: ray.o on its
  // surface with normal n_light; ignored by the others). Delta positions give
  // *pdf_pos 0 and a distant light *pdf_dir 0, as in pbrt-v3.
  void pdf_le(uint32_t light, const Ray& ray, Vec3 n_light, float* pdf_pos, float* pdf_dir) const;
  // The light's own shape when a ray sample_le started (from its surface, normal n_light)
  // cannot meet it again, for SceneGeometry::intersect's skip_shape: a disk (a plane is met
  // once), or a sphere the ray leaves outward (the line's other crossing is behind it); else
  // kNone. Light tracing's first ray tests its light's shape for nothing otherwise (12% of an
  // mlt render under a sphere light, perf).
  uint32_t shape_left_behind(uint32_t light, const Ray& ray, Vec3 n_light) const;
  // The medium a ray sample_le started along w (from a point with normal n_light) travels in,
  // as pbrt-v3 has it: a positional light's own medium (the outside medium of the
  // MediumInterface at its LightSource, which pbrt-v3 gives the light as both of its sides),
  // none for distant and infinite lights, and for an area light the side of its shape that w
  // leaves through.
  uint32_t emission_medium(uint32_t light, Vec3 w, Vec3 n_light) const;

 private:
  // A light: its kind, and an index into that kind's table (for area lights
  // also the shape and triangle). 16 bytes, so a million emitting triangles
  // stay cheap.
  struct Entry {
    LightKind kind;
    uint32_t data;   // index into the kind's table (area: into emitters_)
    uint32_t shape;  // area lights: the archive shape
    uint32_t prim;   // area lights: the triangle (0 for quadrics)
  };
  // Point, spot, projection and goniometric lights: a position and an
  // intensity, shaped by a direction-dependent factor.
  struct PositionalLight {
    Vec3 p;
    Rgb intensity;                               // I * scale
    Transform world_to_light;                    // for the direction-dependent factor
    float cos_total = 0, cos_falloff_start = 0;  // spot
    // projection: light space -> screen, the screen window, near plane, cone
    Transform projection;
    float screen_lo[2] = {0, 0}, screen_hi[2] = {0, 0};
    float hither = 0;
    uint32_t map = kNone;  // into maps_ (projection, goniometric), kNone: none
  };
  struct DistantLight {
    Vec3 w;  // towards the light, unit
    Rgb l;
  };
  struct AreaEmitter {
    Rgb l;
    bool twosided = false;
    int nsamples = 1;
    // pbrt-v3's DiffuseAreaLight::L: radiance leaving a point of normal n along w.
    Rgb l_along(Vec3 n, Vec3 w) const { return twosided || dot(n, w) > 0 ? l : Rgb(); }
  };
  struct InfiniteLight {
    Transform light_to_world, world_to_light;
    Rgb l;                 // L * scale, multiplied after the map lookup
    uint32_t map = kNone;  // into maps_, kNone: constant L
    int nsamples = 1;
    Distribution2D distribution;  // the map's (none for a constant light: sampled uniformly)
  };

  // The intensity's factor toward w: 1 for a point light, here, without a call (the shaped
  // lights' function realigns its stack for its locals, and a point light's return through it
  // took 2% of a whitted room, perf).
  Rgb positional_factor(LightKind kind, const PositionalLight& pl, Vec3 w) const {
    return kind == LightKind::kPoint ? Rgb(1) : shaped_factor(kind, pl, w);
  }
  // Spot, projection and goniometric lights' factor.
  Rgb shaped_factor(LightKind kind, const PositionalLight& pl, Vec3 w) const;
  // The radiance along w_world (towards the light); with pdf, also infinite_pdf's value.
  Rgb infinite_lookup(const InfiniteLight& il, Vec3 w_world, float* pdf = nullptr,
                      const MapDirection& known = {}) const;
  // An infinite light's importance sampling, shared by the Li and Le paths: a
  // direction wi towards the light drawn from the map's distribution, its map (u, v)
  // and solid-angle pdf (0 at the poles); false when the distribution gives 0. A
  // constant light (no map) draws wi uniformly over the sphere (uv is then u).
  bool sample_infinite(const InfiniteLight& il, Vec2 u, Vec2* uv, Vec3* wi, float* pdf) const;
  float infinite_pdf(const InfiniteLight& il, Vec3 wi) const;  // wi towards the light
  Rgb infinite_at(const InfiniteLight& il, Vec2 uv) const;     // radiance at map (u, v)
  bool add_light(const pbrta::SceneArchive& a, uint32_t index, std::string* error);
  bool add_area_lights(const pbrta::SceneArchive& a, std::string* error);

  const ShapeTable* shapes_ = nullptr;
  Vec3 world_center_;
  float world_radius_ = 0;
  std::vector<Entry> entries_;
  std::vector<PositionalLight> positional_;
  std::vector<DistantLight> distant_;
  std::vector<AreaEmitter> emitters_;  // one per archive area light
  std::vector<InfiniteLight> infinite_;
  std::vector<uint32_t> infinite_lights_;  // their light indices
  std::vector<MipMap> maps_;
  std::vector<uint32_t> area_first_;  // per shape: its first light index, or kNone
  // By light index, for emitting triangles (empty when there are none): the world-space
  // triangle every sample and pdf of that light would otherwise transform and measure again.
  std::vector<WorldTriangle> triangles_;
  // By light index (area lights; empty boxes for the others): the shape's box, padded
  // (may_meet).
  std::vector<Bounds3> reach_;
  // The radiance an area light's point `it` sends toward ref_p and the direction *wi to it;
  // false where the sample gives nothing (pdf 0, or it is at ref_p).
  bool area_point_li(uint32_t light, Vec3 ref_p, const Interaction& it, float pdf, Vec3* wi,
                     Rgb* li) const;
  // sample_li's area light case from a sampled point it with solid-angle pdf.
  Rgb area_li(uint32_t light, const Interaction& ref, Interaction it, float pdf,
              LightSample* s) const;
  const WorldTriangle* triangle(uint32_t light, const ShapeInfo& shape) const {
    return shape.kind == ShapeKind::kTriangles ? &triangles_[light] : nullptr;
  }
  std::vector<uint32_t> media_;  // per archive light: the medium it emits into
};

}  // namespace rt
