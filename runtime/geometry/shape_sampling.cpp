// runtime/geometry/shape_sampling.cpp — see shape_sampling.h.
//
// Quadrics follow pbrt-v3 to the letter, quirks included, because the goal
// is pbrt-v3's images: a quadric's area is its object-space area (pbrt-v3's
// Shape::Area ignores the transform's scale), the sphere and disk sample the
// whole sphere / full disk whatever the z, phimax and inner-radius cuts, and
// the sphere's cone sampling uses the object-space radius around the world
// centre. With unscaled transforms and uncut shapes all of this is exact.
#include "runtime/geometry/shape_sampling.h"

#include <cmath>

#include "runtime/core/sampling.h"
#include "runtime/geometry/quadric_shape.h"

namespace rt {

namespace {

Vec3 mesh_normal(const ShapeInfo& s, uint32_t vertex) {
  const float* n = s.mesh.normals + 3 * size_t(vertex);
  return s.object_to_world.normal({n[0], n[1], n[2]});
}

float quadric_area(const QuadricShape& q) {
  switch (q.kind) {
    case ShapeKind::kSphere:
    case ShapeKind::kCylinder:
      return q.phimax * q.radius * (q.zmax - q.zmin);
    case ShapeKind::kDisk:
      return q.phimax * 0.5f * (q.radius * q.radius - q.inner_radius * q.inner_radius);
    case ShapeKind::kCone:
      return q.radius * std::sqrt(q.height * q.height + q.radius * q.radius) * q.phimax / 2;
    case ShapeKind::kParaboloid: {
      float r2 = q.radius * q.radius, k = 4 * q.zmax / r2;
      return (r2 * r2 * q.phimax / (12 * q.zmax * q.zmax)) *
             (std::pow(k * q.zmax + 1, 1.5f) - std::pow(k * q.zmin + 1, 1.5f));
    }
    default: {
      // Hyperboloid: the surface of revolution of the p1-p2 line, integrated
      // with Simpson's rule (never used for sampling; pbrt-v3 cannot sample it).
      auto integrand = [&](float v) {
        Vec3 a = (1 - v) * q.p1 + v * q.p2, d = q.p2 - q.p1;
        float r = std::sqrt(a.x * a.x + a.y * a.y);
        float dr = r > 0 ? (a.x * d.x + a.y * d.y) / r : std::sqrt(d.x * d.x + d.y * d.y);
        return r * std::sqrt(dr * dr + d.z * d.z);
      };
      const int n = 64;
      double sum = integrand(0) + integrand(1);
      for (int i = 1; i < n; ++i) sum += (i % 2 ? 4 : 2) * integrand(float(i) / n);
      return float(q.phimax * sum / (3 * n));
    }
  }
}

bool can_sample(ShapeKind k) {
  return k == ShapeKind::kTriangles || k == ShapeKind::kSphere || k == ShapeKind::kDisk ||
         k == ShapeKind::kCylinder;
}

// The sphere's centre in world space, and whether ref (pushed off its surface
// towards it, as a ray from ref would start) is inside pbrt-v3's sphere.
bool ref_inside_sphere(const ShapeInfo& s, float radius, const Interaction& ref, Vec3* center) {
  *center = s.object_to_world.point(Vec3{0, 0, 0});
  Vec3 origin = offset_ray_origin(ref.p, ref.p_error, ref.n, *center - ref.p);
  return distance_squared(origin, *center) <= radius * radius;
}

// pbrt-v3's Shape::Sample(ref, u): the area sample's pdf as solid angle.
Interaction area_sample_as_solid_angle(const ShapeInfo& s, uint32_t prim, const Interaction& ref,
                                       Vec2 u, float* pdf, const WorldTriangle* t) {
  Interaction it = sample_shape_area(s, prim, u, pdf, t);
  *pdf = area_pdf_as_solid_angle(it, ref.p, *pdf);
  return it;
}

}  // namespace

Vec3 interpolated_mesh_normal(const ShapeInfo& s, uint32_t prim, float b0, float b1, float b2) {
  const uint32_t* v = s.mesh.indices + 3 * size_t(prim);
  return b0 * mesh_normal(s, v[0]) + b1 * mesh_normal(s, v[1]) + b2 * mesh_normal(s, v[2]);
}

WorldTriangle world_triangle(const ShapeInfo& s, uint32_t prim) {
  const uint32_t* v = s.mesh.indices + 3 * size_t(prim);
  const Transform& m = s.object_to_world;
  WorldTriangle t;
  t.p0 = m.point(s.mesh.position(v[0]));
  t.p1 = m.point(s.mesh.position(v[1]));
  t.p2 = m.point(s.mesh.position(v[2]));
  const Vec3 c = cross(t.p1 - t.p0, t.p2 - t.p0);
  t.n = normalize(c);
  t.area = 0.5f * length(c);
  return t;
}

float shape_area(const ShapeInfo& s, uint32_t prim, const WorldTriangle* t) {
  if (s.kind == ShapeKind::kTriangles) return t ? t->area : world_triangle(s, prim).area;
  if (s.kind == ShapeKind::kCurve) return 0;
  QuadricShape q = make_quadric_shape(s);
  return q.valid ? quadric_area(q) : 0;
}

Interaction sample_shape_area(const ShapeInfo& s, uint32_t prim, Vec2 u, float* pdf_area,
                              const WorldTriangle* tri) {
  Interaction it;
  *pdf_area = 0;
  if (!can_sample(s.kind)) return it;
  const Transform& m = s.object_to_world;
  // Every path returns `it` itself, which the caller's return slot then holds (a second
  // returned object made a copy of this one, reloaded in pieces just after its fields' stores).
  if (s.kind == ShapeKind::kTriangles) {
    it = sample_triangle_area(s, prim, tri ? *tri : world_triangle(s, prim), u, pdf_area);
    return it;
  }
  QuadricShape q = make_quadric_shape(s);
  Vec3 p_obj, p_obj_err;
  switch (s.kind) {
    case ShapeKind::kSphere: {
      Vec3 dir = uniform_sample_sphere(u);
      it.n = normalize(m.normal(dir));
      p_obj = q.radius * dir;
      p_obj *= q.radius / length(p_obj);
      p_obj_err = gamma_bound(5) * abs(p_obj);
      break;
    }
    case ShapeKind::kDisk: {
      Vec2 d = concentric_sample_disk(u);
      p_obj = {d.x * q.radius, d.y * q.radius, q.height};
      it.n = normalize(m.normal({0, 0, 1}));
      break;
    }
    default: {  // cylinder
      float z = lerp(u.x, q.zmin, q.zmax), phi = u.y * q.phimax;
      p_obj = {q.radius * std::cos(phi), q.radius * std::sin(phi), z};
      it.n = normalize(m.normal({p_obj.x, p_obj.y, 0}));
      float scale = q.radius / std::sqrt(p_obj.x * p_obj.x + p_obj.y * p_obj.y);
      p_obj.x *= scale;
      p_obj.y *= scale;
      p_obj_err = gamma_bound(3) * abs(Vec3{p_obj.x, p_obj.y, 0});
      break;
    }
  }
  // pbrt-v3's quadric Sample flips for ReverseOrientation only (not for a
  // mirroring transform, unlike its Intersect): the normal-transformed
  // outward normal stays outward here.
  if (s.reverse_orientation) it.n = -it.n;
  it.p = m.point(p_obj, p_obj_err, &it.p_error);
  float area = quadric_area(q);
  *pdf_area = area > 0 ? 1 / area : 0;
  return it;
}

Interaction sample_shape_from(const ShapeInfo& s, uint32_t prim, const Interaction& ref, Vec2 u,
                              float* pdf, const WorldTriangle* t) {
  *pdf = 0;
  if (!can_sample(s.kind)) return Interaction{};
  if (s.kind != ShapeKind::kSphere) return area_sample_as_solid_angle(s, prim, ref, u, pdf, t);

  float radius = s.q.radius;
  Vec3 center;
  if (ref_inside_sphere(s, radius, ref, &center))
    return area_sample_as_solid_angle(s, prim, ref, u, pdf, nullptr);

  // Outside: sample the cone of directions the sphere subtends, then find
  // the point on the sphere from the angle alpha at the centre (pbrt-v3,
  // 3rd ed. 14.2.2), which avoids a ray-sphere intersection.
  float dc2 = distance_squared(ref.p, center), dc = std::sqrt(dc2);
  float sin2_max = radius * radius / dc2;
  float cos_max = safe_sqrt(1 - sin2_max);
  float cos_theta = (1 - u.x) + u.x * cos_max;
  float sin_theta = safe_sqrt(1 - cos_theta * cos_theta);
  float phi = u.y * 2 * kPi;
  float ds = dc * cos_theta - safe_sqrt(radius * radius - dc2 * sin_theta * sin_theta);
  float cos_alpha = (dc2 + radius * radius - ds * ds) / (2 * dc * radius);
  float sin_alpha = safe_sqrt(1 - cos_alpha * cos_alpha);
  Vec3 wc = normalize(center - ref.p), wc_x, wc_y;
  coordinate_system(wc, &wc_x, &wc_y);
  Vec3 n =
      (sin_alpha * std::cos(phi)) * -wc_x + (sin_alpha * std::sin(phi)) * -wc_y + cos_alpha * -wc;
  Interaction it;
  it.p = center + radius * n;
  it.p_error = gamma_bound(5) * abs(it.p);
  it.n = s.reverse_orientation ? -n : n;
  *pdf = uniform_cone_pdf(cos_max);
  if (!std::isfinite(*pdf)) *pdf = 0;
  return it;
}

float shape_pdf_from(const ShapeInfo& s, uint32_t prim, const Interaction& ref, Vec3 wi,
                     const Interaction& on_shape, const WorldTriangle* t) {
  if (!can_sample(s.kind)) return 0;
  if (s.kind == ShapeKind::kSphere) {
    Vec3 center;
    if (!ref_inside_sphere(s, s.q.radius, ref, &center)) {
      float sin2_max = s.q.radius * s.q.radius / distance_squared(ref.p, center);
      float pdf = uniform_cone_pdf(safe_sqrt(1 - sin2_max));
      return std::isfinite(pdf) ? pdf : 0;
    }
  }
  float area = shape_area(s, prim, t);
  float pdf = distance_squared(ref.p, on_shape.p) / (abs_dot(on_shape.n, -wi) * area);
  return std::isfinite(pdf) ? pdf : 0;
}

}  // namespace rt
