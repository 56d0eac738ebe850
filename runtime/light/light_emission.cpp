// runtime/light/light_emission.cpp — rays leaving the lights, for the
// integrators that trace from the lights (pbrt-v3's Sample_Le and Pdf_Le,
// book 3rd ed. 16.1.2-16.1.3; see lights.h for the contract).
//
// The pdfs are over the ray's origin (area) and its direction (solid angle)
// separately, because bdpt weighs the two ends of a light subpath apart.
// Distant and infinite lights have no surface: their rays start on a disk of
// the world sphere's radius facing the scene, just outside the sphere, so
// every ray crossing the scene is reachable and pdf_pos is 1 / (pi r^2).
#include <algorithm>
#include <cmath>

#include "runtime/geometry/shape_sampling.h"
#include "runtime/light/lights.h"

namespace rt {

namespace {

// A point of the disk of radius r centred on c and perpendicular to w (unit),
// uniform by area.
Vec3 disk_point(Vec3 c, float r, Vec3 w, Vec2 u) {
  Vec3 v1, v2;
  coordinate_system(w, &v1, &v2);
  Vec2 d = concentric_sample_disk(u);
  return c + r * (d.x * v1 + d.y * v2);
}

// A cosine-weighted direction about n, on both sides of the surface when
// twosided: u.x's lower half picks the front, its upper half the back, each
// half stretched back to [0, 1) so the hemisphere sample stays stratified.
// *pdf is the solid-angle pdf, halved for the side choice.
Vec3 sample_emission_direction(Vec3 n, bool twosided, Vec2 u, float* pdf) {
  bool back = false;
  if (twosided) {
    back = u.x >= .5f;
    u.x = std::min(back ? (u.x - .5f) * 2 : u.x * 2, kOneMinusEpsilon);
  }
  Vec3 w = cosine_sample_hemisphere(u);
  if (back) w.z = -w.z;
  *pdf = (twosided ? .5f : 1.f) * cosine_hemisphere_pdf(std::fabs(w.z));
  Vec3 v1, v2;
  coordinate_system(n, &v1, &v2);
  return w.x * v1 + w.y * v2 + w.z * n;
}

}  // namespace

Rgb LightSet::sample_le(uint32_t light, Vec2 u1, Vec2 u2, float time, Ray* ray, Vec3* n_light,
                        float* pdf_pos, float* pdf_dir) const {
  const Entry& e = entries_[light];
  *ray = Ray{};
  ray->time = time;
  *n_light = Vec3{};
  *pdf_pos = 0;
  *pdf_dir = 0;
  switch (e.kind) {
    case LightKind::kPoint:
    case LightKind::kGoniometric:
    case LightKind::kSpot:
    case LightKind::kProjection: {
      const PositionalLight& pl = positional_[e.data];
      ray->o = pl.p;
      if (e.kind == LightKind::kPoint || e.kind == LightKind::kGoniometric) {
        // The whole sphere, in world space: a goniometric diagram is not
        // importance sampled in pbrt-v3.
        ray->d = uniform_sample_sphere(u1);
        *pdf_dir = uniform_sphere_pdf();
      } else {
        // The cone around light-space +z that holds all the light's emission
        // (a projection's cone circumscribes its screen window).
        ray->d = pl.world_to_light.inverse().vector(uniform_sample_cone(u1, pl.cos_total));
        *pdf_dir = uniform_cone_pdf(pl.cos_total);
      }
      // A delta position: pbrt-v3 reports pdf_pos 1 and a normal along the
      // ray, so bdpt's |cos(n, d)| / pdf_pos leaves the intensity as it is.
      *n_light = ray->d;
      *pdf_pos = 1;
      return pl.intensity * positional_factor(e.kind, pl, ray->d);
    }
    case LightKind::kDistant: {
      const DistantLight& d = distant_[e.data];
      Vec3 p_disk = disk_point(world_center_, world_radius_, d.w, u1);
      ray->o = p_disk + world_radius_ * d.w;
      ray->d = -d.w;
      *n_light = ray->d;
      *pdf_pos = 1 / (kPi * world_radius_ * world_radius_);
      *pdf_dir = 1;
      return d.l;
    }
    case LightKind::kArea: {
      const ShapeInfo& shape = (*shapes_)[e.shape];
      float pdf_area = 0;
      Interaction it = sample_shape_area(shape, e.prim, u1, &pdf_area, triangle(light, shape));
      if (pdf_area == 0) return Rgb();
      it.time = time;
      const AreaEmitter& em = emitters_[e.data];
      float pdf_w = 0;
      Vec3 w = sample_emission_direction(it.n, em.twosided, u2, &pdf_w);
      *ray = it.spawn_ray(w);
      *n_light = it.n;
      *pdf_pos = pdf_area;
      *pdf_dir = pdf_w;
      return em.l_along(it.n, w);
    }
    case LightKind::kInfinite: {
      const InfiniteLight& il = infinite_[e.data];
      Vec2 uv;
      Vec3 wi;
      float pdf_w = 0;
      if (!sample_infinite(il, u1, &uv, &wi, &pdf_w)) return Rgb();
      // The ray comes in from the sampled direction wi, through a disk
      // facing it: its origin lies outside the world sphere.
      Vec3 p_disk = disk_point(world_center_, world_radius_, wi, u2);
      ray->o = p_disk + world_radius_ * wi;
      ray->d = -wi;
      *n_light = ray->d;
      *pdf_pos = 1 / (kPi * world_radius_ * world_radius_);
      *pdf_dir = pdf_w;
      return infinite_at(il, uv);
    }
  }
  return Rgb();
}

uint32_t LightSet::shape_left_behind(uint32_t light, const Ray& ray, Vec3 n_light) const {
  const Entry& e = entries_[light];
  if (e.kind != LightKind::kArea) return kNone;
  const ShapeInfo& shape = (*shapes_)[e.shape];
  if (shape.kind == ShapeKind::kDisk) return e.shape;
  // sample_shape_area's sphere normal is outward but for ReverseOrientation.
  const Vec3 outward = shape.reverse_orientation ? -n_light : n_light;
  return shape.kind == ShapeKind::kSphere && dot(ray.d, outward) > 0 ? e.shape : kNone;
}

void LightSet::pdf_le(uint32_t light, const Ray& ray, Vec3 n_light, float* pdf_pos,
                      float* pdf_dir) const {
  const Entry& e = entries_[light];
  *pdf_pos = 0;
  *pdf_dir = 0;
  switch (e.kind) {
    case LightKind::kPoint:
    case LightKind::kGoniometric:
      // pdf_pos stays 0: a delta position has no density by area.
      *pdf_dir = uniform_sphere_pdf();
      return;
    case LightKind::kSpot:
    case LightKind::kProjection: {
      // pbrt-v3 tests the light-space direction's z unnormalised, as here.
      const PositionalLight& pl = positional_[e.data];
      if (pl.world_to_light.vector(ray.d).z >= pl.cos_total)
        *pdf_dir = uniform_cone_pdf(pl.cos_total);
      return;
    }
    case LightKind::kDistant:
      // pdf_dir stays 0: the direction is a delta.
      *pdf_pos = 1 / (kPi * world_radius_ * world_radius_);
      return;
    case LightKind::kArea: {
      const ShapeInfo& shape = (*shapes_)[e.shape];
      float area = shape_area(shape, e.prim, triangle(light, shape));
      *pdf_pos = area > 0 ? 1 / area : 0;
      float cos_theta = dot(n_light, ray.d);
      // pbrt-v3 lets a one-sided light's pdf go negative behind it, where it
      // emits nothing; 0 there gives the same images without the sign trap.
      if (emitters_[e.data].twosided)
        *pdf_dir = .5f * cosine_hemisphere_pdf(std::fabs(cos_theta));
      else
        *pdf_dir = cosine_hemisphere_pdf(std::max(cos_theta, 0.f));
      return;
    }
    case LightKind::kInfinite:
      *pdf_pos = 1 / (kPi * world_radius_ * world_radius_);
      *pdf_dir = infinite_pdf(infinite_[e.data], -ray.d);
      return;
  }
}

uint32_t LightSet::emission_medium(uint32_t light, Vec3 w, Vec3 n_light) const {
  const Entry& e = entries_[light];
  switch (e.kind) {
    case LightKind::kArea: {
      const ShapeInfo& s = (*shapes_)[e.shape];
      if (!s.medium_transition()) return s.outside_medium;
      return dot(w, n_light) > 0 ? s.outside_medium : s.inside_medium;
    }
    case LightKind::kDistant:
    case LightKind::kInfinite:
      return kNone;
    default:
      return light < media_.size() ? media_[light] : kNone;
  }
}

}  // namespace rt
