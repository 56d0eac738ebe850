// runtime/light/light_sample.cpp — sampling, pdfs, emission and power of the
// lights in a LightSet, one switch per call (pbrt-v3's Light methods).
#include <cmath>
#include <utility>

#include "runtime/core/fast_trig.h"
#include "runtime/geometry/shape_sampling.h"
#include "runtime/light/lights.h"

namespace rt {

namespace {

// *it becomes a point in free space (delta lights, points beyond the scene). Written field by
// field in place: a temporary's copy reloaded its zeroed fields in 32-byte pieces across the
// separate stores that had just written it, a stalled store-to-load forward per light sample
// (a fifth of sample_li's time in a whitted room, perf).
void place_at(Interaction* it, Vec3 p, float time) {
  it->p = p;
  it->p_error = it->n = it->wo = Vec3{};
  it->time = time;
}

}  // namespace

bool LightSet::is_delta(uint32_t light) const {
  LightKind k = entries_[light].kind;
  return k != LightKind::kArea && k != LightKind::kInfinite;
}

int LightSet::nsamples(uint32_t light) const {
  const Entry& e = entries_[light];
  if (e.kind == LightKind::kArea) return emitters_[e.data].nsamples;
  if (e.kind == LightKind::kInfinite) return infinite_[e.data].nsamples;
  return 1;
}

// The direction-dependent factor of a positional light for emission along w
// (world space, from the light outwards): pbrt-v3's Falloff, Projection, Scale.
Rgb LightSet::shaped_factor(LightKind kind, const PositionalLight& pl, Vec3 w) const {
  Rgb factor(1);
  Vec3 wl = pl.world_to_light.vector(w);
  if (kind == LightKind::kSpot) {
    float cos_theta = normalize(wl).z;
    if (cos_theta < pl.cos_total) {
      factor = Rgb(0);
    } else if (cos_theta < pl.cos_falloff_start) {
      // pbrt-v3's falloff is the fourth power of the linear ramp in cos
      // (the book, 12.2.1), not pbrt-v4's smoothstep.
      float d = (cos_theta - pl.cos_total) / (pl.cos_falloff_start - pl.cos_total);
      factor = Rgb((d * d) * (d * d));
    }
  } else if (kind == LightKind::kProjection) {
    if (wl.z < pl.hither) {
      factor = Rgb(0);
    } else {
      Vec3 ps = pl.projection.point(wl);
      if (ps.x < pl.screen_lo[0] || ps.x > pl.screen_hi[0] || ps.y < pl.screen_lo[1] ||
          ps.y > pl.screen_hi[1]) {
        factor = Rgb(0);
      } else if (pl.map != kNone) {
        Vec2 st{(ps.x - pl.screen_lo[0]) / (pl.screen_hi[0] - pl.screen_lo[0]),
                (ps.y - pl.screen_lo[1]) / (pl.screen_hi[1] - pl.screen_lo[1])};
        factor = maps_[pl.map].lookup_trilinear(st);
      }
    }
  } else if (kind == LightKind::kGoniometric && pl.map != kNone) {
    // The goniometric diagram has its pole along light-space +y.
    Vec3 wp = normalize(wl);
    std::swap(wp.y, wp.z);
    factor = maps_[pl.map].lookup_trilinear(
        Vec2{spherical_phi(wp) * kInv2Pi, spherical_theta(wp) * kInvPi});
  }
  return factor;
}

namespace {
// A density over the map's (u, v) = (phi / 2pi, theta / pi) as one over solid angle: the
// Jacobian from the unit square to the sphere is 1 / (2 pi^2 sin theta); 0 at the poles.
// Not only sin theta == 0: a direction exactly at the -z pole has theta = pi rounded to a
// float, whose sine is -8.7e-8, which would make the pdf hugely negative.
float map_pdf_to_solid_angle(float map_pdf, float sin_theta) {
  return sin_theta <= 0 ? 0 : map_pdf / (2 * kPi * kPi * sin_theta);
}

// The map's (u, v) = (phi / 2pi, theta / pi) of a world direction, and sin theta.
Vec2 map_coordinates(const Transform& world_to_light, Vec3 w_world, float* sin_theta) {
  const Vec3 w = normalize(world_to_light.vector(w_world));
  // sin(acos z), without a sine: the same to rounding, and 0 (no density) at the poles.
  *sin_theta = std::sqrt(std::max(0.f, (1 - w.z) * (1 + w.z)));
  const float phi = fast_atan2(w.y, w.x);
  return {(phi < 0 ? phi + 2 * kPi : phi) * kInv2Pi, fast_acos(w.z) * kInvPi};
}
}  // namespace

Rgb LightSet::infinite_lookup(const InfiniteLight& il, Vec3 w_world, float* pdf,
                              const MapDirection& known) const {
  if (il.map == kNone) {
    if (pdf) *pdf = uniform_sphere_pdf();
    return il.l;
  }
  float sin_theta = known.sin_theta;
  const Vec2 st =
      known.w == w_world ? known.st : map_coordinates(il.world_to_light, w_world, &sin_theta);
  if (pdf) *pdf = map_pdf_to_solid_angle(il.distribution.pdf(st), sin_theta);
  return il.map == kNone ? il.l : maps_[il.map].lookup_trilinear(st) * il.l;
}

bool LightSet::sample_infinite(const InfiniteLight& il, Vec2 u, Vec2* uv, Vec3* wi,
                               float* pdf) const {
  if (il.map == kNone) {
    // A constant light is sampled uniformly over the sphere, as pbrt-v4's uniform infinite
    // light is: the same expectation as pbrt-v3's sampling of its one-texel map (which
    // crowds samples at the poles), with a constant Li / pdf, one sine and cosine, and a
    // constant density for MIS, where the map's took an arccosine and an arctangent.
    *uv = u;
    *wi = uniform_sample_sphere(u);
    *pdf = uniform_sphere_pdf();
    return true;
  }
  float map_pdf = 0;
  *uv = il.distribution.sample_continuous(u, &map_pdf);
  if (map_pdf == 0) return false;
  // The radiance lookup that follows misses the cache (the map's texels, the distribution's
  // table and a scene's textures do not fit it together): start it before the trigonometry.
  if (il.map != kNone) maps_[il.map].prefetch_bilinear(*uv);
  // (u, v) is (phi / 2pi, theta / pi) of the map's spherical parameterisation.
  float theta = uv->y * kPi, phi = uv->x * 2 * kPi;
  float sin_theta = std::sin(theta);
  *wi = il.light_to_world.vector(
      Vec3{sin_theta * std::cos(phi), sin_theta * std::sin(phi), std::cos(theta)});
  *pdf = map_pdf_to_solid_angle(map_pdf, sin_theta);
  return true;
}

float LightSet::infinite_pdf(const InfiniteLight& il, Vec3 wi) const {
  if (il.map == kNone) return uniform_sphere_pdf();
  float sin_theta;
  const Vec2 st = map_coordinates(il.world_to_light, wi, &sin_theta);
  return map_pdf_to_solid_angle(il.distribution.pdf(st), sin_theta);
}

Rgb LightSet::infinite_at(const InfiniteLight& il, Vec2 uv) const {
  return il.map == kNone ? il.l : maps_[il.map].lookup_trilinear(uv) * il.l;
}

namespace {
void clear(LightSample* s) {
  s->li = Rgb();
  s->pdf = 0;
  s->delta = false;
  s->own_shape = kNone;
  s->pending_map = kNone;
}
}  // namespace

bool LightSet::triangle_point(uint32_t light, Vec2 u, Interaction* it, float* pdf_area) const {
  const Entry& e = entries_[light];
  if (e.kind != LightKind::kArea) return false;
  const ShapeInfo& shape = (*shapes_)[e.shape];
  if (shape.kind != ShapeKind::kTriangles) return false;
  *it = sample_triangle_area(shape, e.prim, triangles_[light], u, pdf_area);
  return true;
}

Rgb LightSet::li_at_triangle_point(uint32_t light, const Interaction& ref, Interaction it,
                                   float pdf_area, LightSample* s) const {
  clear(s);
  return area_li(light, ref, it, area_pdf_as_solid_angle(it, ref.p, pdf_area), s);
}

// Inline: the light grid calls it for every sample of every voxel.
[[gnu::always_inline]] inline bool LightSet::area_point_li(uint32_t light, Vec3 ref_p,
                                                           const Interaction& it, float pdf,
                                                           Vec3* wi, Rgb* li) const {
  if (pdf == 0 || length_squared(it.p - ref_p) == 0) return false;
  *wi = normalize(it.p - ref_p);
  *li = emitters_[entries_[light].data].l_along(it.n, -*wi);
  return true;
}

float LightSet::triangle_point_weight(uint32_t light, Vec3 ref_p, const Interaction& it,
                                      float pdf_area) const {
  // What li_at_triangle_point's sample gives the grid, li.luminance() / pdf, in its arithmetic.
  const float pdf = area_pdf_as_solid_angle(it, ref_p, pdf_area);
  Vec3 wi;
  Rgb li;
  return area_point_li(light, ref_p, it, pdf, &wi, &li) ? li.luminance() / pdf : 0;
}

Rgb LightSet::area_li(uint32_t light, const Interaction& ref, Interaction it, float pdf,
                      LightSample* s) const {
  const Entry& e = entries_[light];
  const ShapeInfo& shape = (*shapes_)[e.shape];
  it.time = ref.time;
  Rgb li;
  if (!area_point_li(light, ref.p, it, pdf, &s->wi, &li)) return s->li;
  s->pdf = pdf;
  s->p_light = it;
  if (shape.kind == ShapeKind::kSphere || shape.kind == ShapeKind::kDisk) s->own_shape = e.shape;
  s->li = li;
  return s->li;
}

Rgb LightSet::sample_li(uint32_t light, const Interaction& ref, Vec2 u, LightSample* s,
                        bool defer_map) const {
  const Entry& e = entries_[light];
  clear(s);
  switch (e.kind) {
    case LightKind::kPoint:
    case LightKind::kSpot:
    case LightKind::kProjection:
    case LightKind::kGoniometric: {
      const PositionalLight& pl = positional_[e.data];
      s->delta = true;
      s->wi = normalize(pl.p - ref.p);
      s->pdf = 1;
      place_at(&s->p_light, pl.p, ref.time);
      Rgb factor = positional_factor(e.kind, pl, -s->wi);
      s->li = pl.intensity * factor / distance_squared(pl.p, ref.p);
      return s->li;
    }
    case LightKind::kDistant: {
      const DistantLight& d = distant_[e.data];
      s->delta = true;
      s->wi = d.w;
      s->pdf = 1;
      place_at(&s->p_light, ref.p + d.w * (2 * world_radius_), ref.time);
      s->li = d.l;
      return s->li;
    }
    case LightKind::kArea: {
      Interaction it;
      float pdf = 0;
      if (triangle_point(light, u, &it, &pdf)) return li_at_triangle_point(light, ref, it, pdf, s);
      it = sample_shape_from((*shapes_)[e.shape], e.prim, ref, u, &pdf);
      return area_li(light, ref, it, pdf, s);
    }
    case LightKind::kInfinite: {
      const InfiniteLight& il = infinite_[e.data];
      Vec2 uv;
      if (!sample_infinite(il, u, &uv, &s->wi, &s->pdf)) return s->li;
      place_at(&s->p_light, ref.p + s->wi * (2 * world_radius_), ref.time);
      if (defer_map && il.map != kNone) {
        s->pending_map = il.map;
        s->map_uv = uv;
        s->li = il.l;
      } else {
        s->li = infinite_at(il, uv);
      }
      return s->li;
    }
  }
  return s->li;
}

float LightSet::pdf_li(uint32_t light, const Interaction& ref, Vec3 wi,
                       const Interaction* hit) const {
  const Entry& e = entries_[light];
  if (e.kind == LightKind::kArea) {
    if (!hit) return 0;
    const ShapeInfo& shape = (*shapes_)[e.shape];
    return shape_pdf_from(shape, e.prim, ref, wi, *hit, triangle(light, shape));
  }
  if (e.kind == LightKind::kInfinite) return infinite_pdf(infinite_[e.data], wi);
  return 0;
}

bool LightSet::may_meet(uint32_t light, const Ray& ray) const {
  return entries_[light].kind != LightKind::kArea || reach_[light].meets(ray.o, ray.d, kInfinity);
}

uint32_t LightSet::area_light_at(const SurfaceInteraction& hit) const {
  if (hit.instance != kNone || hit.shape >= area_first_.size()) return kNone;
  uint32_t first = area_first_[hit.shape];
  if (first == kNone) return kNone;
  return (*shapes_)[hit.shape].kind == ShapeKind::kTriangles ? first + hit.prim : first;
}

Rgb LightSet::area_le(const SurfaceInteraction& hit, Vec3 w) const {
  uint32_t light = area_light_at(hit);
  if (light == kNone) return Rgb();
  return emitters_[entries_[light].data].l_along(hit.n, w);
}

Rgb LightSet::infinite_le(const RayDifferential& ray) const {
  Rgb l;
  for (uint32_t light : infinite_lights_)
    l += infinite_lookup(infinite_[entries_[light].data], ray.d);
  return l;
}

Rgb LightSet::infinite_le_one(uint32_t light, const RayDifferential& ray, float* pdf_li,
                              const MapDirection& known) const {
  const Entry& e = entries_[light];
  if (e.kind != LightKind::kInfinite) return Rgb();
  return infinite_lookup(infinite_[e.data], ray.d, pdf_li, known);
}

MapDirection LightSet::prefetch_infinite(uint32_t light, Vec3 w_world) const {
  const Entry& e = entries_[light];
  if (e.kind != LightKind::kInfinite) return {};
  const InfiniteLight& il = infinite_[e.data];
  if (il.map == kNone) return {};
  MapDirection d;
  d.st = map_coordinates(il.world_to_light, w_world, &d.sin_theta);
  d.w = w_world;
  maps_[il.map].prefetch_bilinear(d.st);
  il.distribution.prefetch_value(d.st);
  return d;
}

void LightSet::prefetch_sample(uint32_t light, Vec2 u) const {
  const Entry& e = entries_[light];
  if (e.kind == LightKind::kInfinite && infinite_[e.data].map != kNone)
    infinite_[e.data].distribution.prefetch_sample(u);
}

Rgb LightSet::power(uint32_t light) const {
  const Entry& e = entries_[light];
  switch (e.kind) {
    case LightKind::kPoint:
      return 4 * kPi * positional_[e.data].intensity;
    case LightKind::kSpot: {
      const PositionalLight& pl = positional_[e.data];
      return pl.intensity * 2 * kPi * (1 - .5f * (pl.cos_falloff_start + pl.cos_total));
    }
    case LightKind::kProjection: {
      const PositionalLight& pl = positional_[e.data];
      Rgb m = pl.map == kNone ? Rgb(1) : maps_[pl.map].lookup_trilinear(Vec2{.5f, .5f}, .5f);
      return m * pl.intensity * 2 * kPi * (1 - pl.cos_total);
    }
    case LightKind::kGoniometric: {
      const PositionalLight& pl = positional_[e.data];
      Rgb m = pl.map == kNone ? Rgb(1) : maps_[pl.map].lookup_trilinear(Vec2{.5f, .5f}, .5f);
      return 4 * kPi * pl.intensity * m;
    }
    case LightKind::kDistant:
      return distant_[e.data].l * kPi * world_radius_ * world_radius_;
    case LightKind::kArea: {
      const AreaEmitter& em = emitters_[e.data];
      const ShapeInfo& shape = (*shapes_)[e.shape];
      float area = shape_area(shape, e.prim, triangle(light, shape));
      return (em.twosided ? 2.f : 1.f) * em.l * area * kPi;
    }
    case LightKind::kInfinite: {
      const InfiniteLight& il = infinite_[e.data];
      Rgb m = il.map == kNone ? Rgb(1) : maps_[il.map].lookup_trilinear(Vec2{.5f, .5f}, .5f);
      return kPi * world_radius_ * world_radius_ * m * il.l;
    }
  }
  return Rgb();
}

}  // namespace rt
