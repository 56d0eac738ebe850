// runtime/geometry/quadric_intersect.cpp — see quadric_intersect.h.
#include "runtime/geometry/quadric_intersect.h"

#include <cmath>

#include "runtime/core/fast_trig.h"
#include "runtime/geometry/efloat.h"
#include "runtime/geometry/quadric_shape.h"

namespace rt {

namespace {

bool is_quadric(ShapeKind k) {
  return k != ShapeKind::kTriangles && k != ShapeKind::kCurve;
}

float phi_of(float x, float y) {
  float phi = std::atan2(y, x);
  return phi < 0 ? phi + 2 * kPi : phi;
}

// phi for a hit's u only, on a whole turn, where no cut compares it with phimax: the polynomial
// arctangent (fast_trig.h), the same to rounding.
float whole_turn_phi(float x, float y) {
  float phi = fast_atan2(y, x);
  return phi < 0 ? phi + 2 * kPi : phi;
}

// The world ray in object space, its origin and direction as intervals. The
// origin is pushed forward along d past its own error (pbrt-v3's ray
// transform) so that t > 0 really is in front of it; tmax is kept.
struct ObjectRay {
  Vec3 o, d;
  EFloat ox, oy, oz, dx, dy, dz;
  // pbrt-v3's bounds for a float transform of the ray: the hit's error box
  // for shapes whose point comes from the ray equation (parametric_error).
  Vec3 box_o_err, box_d_err;
};

// The ray whose origin o is already past its error, with its intervals.
[[gnu::always_inline]] inline ObjectRay with_intervals(Vec3 o, Vec3 d, Vec3 o_err, Vec3 d_err) {
  ObjectRay r;
  r.o = o;
  r.d = d;
  r.ox = EFloat(o.x, o_err.x);
  r.oy = EFloat(o.y, o_err.y);
  r.oz = EFloat(o.z, o_err.z);
  r.dx = EFloat(d.x, d_err.x);
  r.dy = EFloat(d.y, d_err.y);
  r.dz = EFloat(d.z, d_err.z);
  r.box_o_err = o_err;
  r.box_d_err = d_err;
  return r;
}

[[gnu::always_inline]] inline ObjectRay with_errors(Vec3 o, Vec3 d, Vec3 o_err, Vec3 d_err) {
  return with_intervals(origin_past_error(o, d, o_err), d, o_err, d_err);
}

// The same ray with the transform evaluated in double: the origin is the
// float nearest the exact product, off by half an ulp instead of gamma(3)
// times the magnitudes. Used only where pbrt-v3's bounds leave the nearest
// root ambiguous (intersect_quadric); the hit's error box keeps pbrt-v3's.
ObjectRay to_object_precise(const Transform& world_to_object, const Ray& rw,
                            const ObjectRay& pbrt) {
  const Matrix4& inv = world_to_object.matrix();
  const double o[3] = {rw.o.x, rw.o.y, rw.o.z}, dw[3] = {rw.d.x, rw.d.y, rw.d.z};
  Vec3 of, df, o_err, d_err;
  for (int i = 0; i < 3; ++i) {
    double od = inv.m[i][3], dd = 0, omag = std::fabs(od), dmag = 0;
    for (int j = 0; j < 3; ++j) {
      od += double(inv.m[i][j]) * o[j];
      dd += double(inv.m[i][j]) * dw[j];
      omag += std::fabs(double(inv.m[i][j]) * o[j]);
      dmag += std::fabs(double(inv.m[i][j]) * dw[j]);
    }
    of[i] = float(od);
    df[i] = float(dd);
    // Rounding to float plus the double sums' own error (far below 2^-40).
    o_err[i] = next_float_up(float(std::fabs(double(of[i]) - od) + 0x1p-40 * omag));
    d_err[i] = next_float_up(float(std::fabs(double(df[i]) - dd) + 0x1p-40 * dmag));
  }
  ObjectRay r = with_errors(of, df, o_err, d_err);
  r.box_o_err = pbrt.box_o_err;
  r.box_d_err = pbrt.box_d_err;
  return r;
}

// Coefficients of the quadric's implicit equation along the ray, for T =
// EFloat (values with intervals) or T = float. EFloat computes its values with
// exactly these float operations in this order, so the float instance gives
// bit for bit the EFloat instance's values (may_hit relies on that).
template <class T>
void coefficients(const QuadricShape& q, T ox, T oy, T oz, T dx, T dy, T dz, T* a, T* b, T* c) {
  switch (q.kind) {
    case ShapeKind::kSphere: {
      T rad(q.radius);
      *a = dx * dx + dy * dy + dz * dz;
      *b = 2.f * (dx * ox + dy * oy + dz * oz);
      *c = ox * ox + oy * oy + oz * oz - rad * rad;
      break;
    }
    case ShapeKind::kCylinder: {
      T rad(q.radius);
      *a = dx * dx + dy * dy;
      *b = 2.f * (dx * ox + dy * oy);
      *c = ox * ox + oy * oy - rad * rad;
      break;
    }
    case ShapeKind::kCone: {
      T k = T(q.radius) / T(q.height);
      k = k * k;
      T oz_h = oz - T(q.height);
      *a = dx * dx + dy * dy - k * dz * dz;
      *b = 2.f * (dx * ox + dy * oy - k * dz * oz_h);
      *c = ox * ox + oy * oy - k * oz_h * oz_h;
      break;
    }
    case ShapeKind::kParaboloid: {
      T k = T(q.zmax) / (T(q.radius) * T(q.radius));
      *a = k * (dx * dx + dy * dy);
      *b = 2.f * k * (dx * ox + dy * oy) - dz;
      *c = k * (ox * ox + oy * oy) - oz;
      break;
    }
    default: {  // hyperboloid
      T ah(q.ah), ch(q.ch);
      *a = ah * dx * dx + ah * dy * dy - ch * dz * dz;
      *b = 2.f * (ah * dx * ox + ah * dy * oy - ch * dz * oz);
      *c = ah * ox * ox + ah * oy * oy - ch * oz * oz - T(1.f);
      break;
    }
  }
}

void coefficients(const QuadricShape& q, const ObjectRay& r, EFloat* a, EFloat* b, EFloat* c) {
  coefficients<EFloat>(q, r.ox, r.oy, r.oz, r.dx, r.dy, r.dz, a, b, c);
}

// False when the interval tests of intersect_quadric are sure to reject the hit, decided from
// the values alone (the float instances of coefficients and solve_quadratic): no real root,
// or a far root not past 0, which no interval containing it is, and for which
// intersect_quadric tries no second time. Most tests Embree asks for are rays through the box
// that miss the surface, or rays leaving the surface they start on (whose roots are behind
// them and at 0): they need no interval arithmetic at all.
// *root: the discriminant's square root, which the intervals' roots share (roots_from).
bool may_hit(const QuadricShape& q, Vec3 o, Vec3 d, double* root) {
  float a, b, c, t0, t1;
  coefficients<float>(q, o.x, o.y, o.z, d.x, d.y, d.z, &a, &b, &c);
  if (!discriminant_root(a, b, c, root)) return false;
  roots_from(a, b, c, *root, &t0, &t1);
  return t1 > 0;
}

// The phi of a (located) point p of the quadric; phi_at(x, y) is the angle of (x, y) in [0, 2pi).
template <float (*phi_at)(float, float)>
float quadric_phi(const QuadricShape& q, Vec3 p) {
  if (q.kind != ShapeKind::kHyperboloid) return phi_at(p.x, p.y);
  // The hyperboloid's is relative to the generating line's point at this z.
  float v = (p.z - q.p1.z) / (q.p2.z - q.p1.z);
  Vec3 pr = (1 - v) * q.p1 + v * q.p2;
  return phi_at(p.x * pr.x + p.y * pr.y, pr.x * p.y - p.x * pr.y);
}

// The phi a hit's u is made of: the one locate() compared with phimax, or on a whole turn
// (compared with nothing) the polynomial one.
float hit_phi(const QuadricShape& q, Vec3 p) {
  return q.phimax >= 2 * kPi ? quadric_phi<whole_turn_phi>(q, p) : quadric_phi<phi_of>(q, p);
}

// The hit point at t, refined onto the surface where the book does so; false when it lies
// outside the phimax / z cuts. A whole turn cuts nothing (phi, atan2 plus 2 pi in float,
// never exceeds 2 * kPi), and most points located are never hits (rays the z cuts reject,
// shadow rays): phi is left for the hit that needs it.
bool locate(const QuadricShape& q, const ObjectRay& r, float t, Vec3* p_out) {
  Vec3 p = r.o + r.d * t;
  bool outside;
  switch (q.kind) {
    case ShapeKind::kSphere:
      p *= q.radius / length(p);
      // Keep phi and dp/du defined at the poles.
      if (p.x == 0 && p.y == 0) p.x = 1e-5f * q.radius;
      outside = (q.zmin > -q.radius && p.z < q.zmin) || (q.zmax < q.radius && p.z > q.zmax);
      break;
    case ShapeKind::kCylinder: {
      float s = q.radius / std::sqrt(p.x * p.x + p.y * p.y);
      p.x *= s;
      p.y *= s;
      outside = p.z < q.zmin || p.z > q.zmax;
      break;
    }
    case ShapeKind::kCone:
      outside = p.z < 0 || p.z > q.height;
      break;
    default:  // paraboloid, hyperboloid
      outside = p.z < q.zmin || p.z > q.zmax;
      break;
  }
  *p_out = p;
  if (outside || p.has_nan()) return false;
  return q.phimax >= 2 * kPi || !(quadric_phi<phi_of>(q, p) > q.phimax);
}

Vec3 finite_or_zero(Vec3 v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) ? v : Vec3{};
}

// Object-space differential geometry to a world-space SurfaceInteraction;
// dn/du and dn/dv from the Weingarten equations. False where the surface has
// no normal (a cone's apex, hit exactly): no usable hit there.
bool fill_interaction(const ShapeInfo& s, const Transform& world_to_object, Vec3 p, Vec3 p_err,
                      Vec2 uv, Vec3 dpdu, Vec3 dpdv, Vec3 d2pduu, Vec3 d2pduv, Vec3 d2pdvv,
                      const Ray& rw, SurfaceInteraction* si) {
  Vec3 n = normalize(cross(dpdu, dpdv));
  if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z)) return false;
  float e1 = dot(dpdu, dpdu), f1 = dot(dpdu, dpdv), g1 = dot(dpdv, dpdv);
  float e2 = dot(n, d2pduu), f2 = dot(n, d2pduv), g2 = dot(n, d2pdvv);
  float inv = 1 / (e1 * g1 - f1 * f1);
  Vec3 dndu, dndv;
  if (std::isfinite(inv)) {
    dndu = finite_or_zero(((f2 * f1 - e2 * g1) * inv) * dpdu + ((e2 * f1 - f2 * e1) * inv) * dpdv);
    dndv = finite_or_zero(((g2 * f1 - f2 * g1) * inv) * dpdu + ((f2 * f1 - g2 * e1) * inv) * dpdv);
  }
  // Flipped in object space before the normal transform, as pbrt-v3 does:
  // mirroring reverses cross(dpdu, dpdv) in world space, so after this flip
  // the world normal is that world cross product, negated only by
  // ReverseOrientation (a mirrored sphere's normal points inwards).
  if (s.flip_normals()) n = -n;

  const Transform m = world_to_object.inverse();
  si->p = m.point(p, p_err, &si->p_error);
  si->n = normalize(m.normal(n));
  si->wo = normalize(-rw.d);
  si->time = rw.time;
  si->uv = uv;
  si->dpdu = m.vector(dpdu);
  si->dpdv = m.vector(dpdv);
  si->dndu = m.normal(dndu);
  si->dndv = m.normal(dndv);
  si->shading = ShadingFrame{si->n, si->dpdu, si->dpdv, si->dndu, si->dndv};
  si->dpdx = si->dpdy = Vec3{};
  si->dudx = si->dvdx = si->dudy = si->dvdy = 0;
  si->prim = 0;
  si->face_index = 0;
  return true;
}

// The ray-parametric point's interval width: the error bound of the hit for
// shapes whose point is not re-projected.
Vec3 parametric_error(const ObjectRay& r, EFloat t) {
  Vec3 e;
  for (int i = 0; i < 3; ++i)
    e[i] = (EFloat(r.o[i], r.box_o_err[i]) + t * EFloat(r.d[i], r.box_d_err[i])).abs_error();
  return e;
}

bool surface_geometry(const QuadricShape& q, const ShapeInfo& s, const Transform& world_to_object,
                      const ObjectRay& r, EFloat t, Vec3 p, float phi, const Ray& rw,
                      SurfaceInteraction* si) {
  float pm = q.phimax;
  float u = phi / pm, v = 0;
  Vec3 dpdu{-pm * p.y, pm * p.x, 0};
  Vec3 d2pduu = -pm * pm * Vec3{p.x, p.y, 0};
  Vec3 dpdv, d2pduv, d2pdvv, p_err;
  switch (q.kind) {
    case ShapeKind::kSphere: {
      // theta only makes v (the z cuts compared p.z): the polynomial arccosine; and
      // r sin theta is the point's distance from the axis.
      float theta = fast_acos(p.z / q.radius);
      float dtheta = q.theta_zmax - q.theta_zmin;
      v = (theta - q.theta_zmin) / dtheta;
      float zr = std::sqrt(p.x * p.x + p.y * p.y), inv_zr = 1 / zr;
      float cos_phi = p.x * inv_zr, sin_phi = p.y * inv_zr;
      dpdv = dtheta * Vec3{p.z * cos_phi, p.z * sin_phi, -zr};
      d2pduv = dtheta * p.z * pm * Vec3{-sin_phi, cos_phi, 0};
      d2pdvv = -dtheta * dtheta * p;
      p_err = gamma_bound(5) * abs(p);
      break;
    }
    case ShapeKind::kCylinder:
      v = (p.z - q.zmin) / (q.zmax - q.zmin);
      dpdv = {0, 0, q.zmax - q.zmin};
      p_err = gamma_bound(3) * abs(Vec3{p.x, p.y, 0});
      break;
    case ShapeKind::kCone: {
      v = p.z / q.height;
      float inv_1v = 1 / (1 - v);
      dpdv = {-p.x * inv_1v, -p.y * inv_1v, q.height};
      d2pduv = pm * inv_1v * Vec3{p.y, -p.x, 0};
      p_err = parametric_error(r, t);
      break;
    }
    case ShapeKind::kParaboloid: {
      float dz = q.zmax - q.zmin;
      v = (p.z - q.zmin) / dz;
      float inv_2z = 1 / (2 * p.z);
      dpdv = dz * Vec3{p.x * inv_2z, p.y * inv_2z, 1};
      d2pduv = dz * pm * Vec3{-p.y * inv_2z, p.x * inv_2z, 0};
      d2pdvv = -dz * dz * Vec3{p.x * inv_2z * inv_2z, p.y * inv_2z * inv_2z, 0};
      p_err = parametric_error(r, t);
      break;
    }
    default: {  // hyperboloid
      v = (p.z - q.p1.z) / (q.p2.z - q.p1.z);
      float cos_phi = std::cos(phi), sin_phi = std::sin(phi);
      Vec3 dp = q.p2 - q.p1;
      dpdv = {dp.x * cos_phi - dp.y * sin_phi, dp.x * sin_phi + dp.y * cos_phi, dp.z};
      d2pduv = pm * Vec3{-dpdv.y, dpdv.x, 0};
      p_err = parametric_error(r, t);
      break;
    }
  }
  return fill_interaction(s, world_to_object, p, p_err, {u, v}, dpdu, dpdv, d2pduu,
                          finite_or_zero(d2pduv), finite_or_zero(d2pdvv), rw, si);
}

// o, d: the ray in object space, its origin past its error (a plane needs no intervals).
bool intersect_disk(const QuadricShape& q, const ShapeInfo& s, const Transform& world_to_object,
                    Vec3 o, Vec3 d, const Ray& rw, float* t_hit, SurfaceInteraction* si) {
  if (d.z == 0) return false;
  float t = (q.height - o.z) / d.z;
  if (!(t > 0) || t >= rw.tmax) return false;
  Vec3 p = o + d * t;
  float dist2 = p.x * p.x + p.y * p.y;
  if (dist2 > q.radius * q.radius || dist2 < q.inner_radius * q.inner_radius) return false;
  float phi = phi_of(p.x, p.y);
  if (phi > q.phimax) return false;
  if (!si) {
    *t_hit = t;
    return true;
  }
  // At the exact centre dp/dv has no direction; borrow the one just beside it.
  float x = p.x, y = p.y;
  if (dist2 == 0) x = 1e-5f * q.radius;
  float r_hit = std::sqrt(x * x + y * y);
  float pm = q.phimax;
  float v = 1 - (std::sqrt(dist2) - q.inner_radius) / (q.radius - q.inner_radius);
  Vec3 dpdu{-pm * y, pm * x, 0};
  Vec3 dpdv = Vec3{x, y, 0} * ((q.inner_radius - q.radius) / r_hit);
  // The plane's z is known exactly, so the refined point has no error there
  // and (pbrt-v3) none is claimed in x and y either.
  p.z = q.height;
  *t_hit = t;
  return fill_interaction(s, world_to_object, p, Vec3{}, {phi / pm, v}, dpdu, dpdv, Vec3{}, Vec3{},
                          Vec3{}, rw, si);
}

// intersect_quadric's rare second try, out of line so that its common path
// keeps the root solver inlined.
[[gnu::noinline]] bool roots_precise(const QuadricShape& q, const Transform& world_to_object,
                                     const Ray& rw, ObjectRay* r, EFloat* t0, EFloat* t1) {
  *r = to_object_precise(world_to_object, rw, *r);
  EFloat a, b, c;
  coefficients(q, *r, &a, &b, &c);
  return solve_quadratic(a, b, c, t0, t1);
}

}  // namespace

Bounds3 quadric_object_bounds(const ShapeInfo& s) {
  Bounds3 b;
  if (!is_quadric(s.kind)) return b;
  QuadricShape q = make_quadric_shape(s);
  float r = q.radius;
  switch (s.kind) {
    case ShapeKind::kDisk:
      b.lo = {-r, -r, q.height};
      b.hi = {r, r, q.height};
      break;
    case ShapeKind::kCone:
      b.lo = {-r, -r, 0};
      b.hi = {r, r, q.height};
      break;
    case ShapeKind::kHyperboloid:
      b.lo = {-q.rmax, -q.rmax, q.zmin};
      b.hi = {q.rmax, q.rmax, q.zmax};
      break;
    default:
      b.lo = {-r, -r, q.zmin};
      b.hi = {r, r, q.zmax};
      break;
  }
  return b;
}

Bounds3 quadric_world_bounds(const ShapeInfo& s) {
  Bounds3 ob = quadric_object_bounds(s), wb;
  if (ob.empty()) return wb;
  if (s.motion) return s.motion->motion_bounds(ob);  // padded far beyond rounding
  for (int c = 0; c < 8; ++c) {
    Vec3 corner{c & 1 ? ob.hi.x : ob.lo.x, c & 2 ? ob.hi.y : ob.lo.y, c & 4 ? ob.hi.z : ob.lo.z};
    Vec3 err;
    Vec3 w = s.object_to_world.point(corner, &err);
    wb.extend(w - err);
    wb.extend(w + err);
  }
  for (int i = 0; i < 3; ++i) {
    wb.lo[i] = next_float_down(wb.lo[i]);
    wb.hi[i] = next_float_up(wb.hi[i]);
  }
  return wb;
}

PreparedQuadric prepare_quadric(const ShapeInfo& s) {
  return {make_quadric_shape(s), s.object_to_world.inverse()};
}

bool intersect_quadric(const ShapeInfo& s, const Ray& rw, float* t_hit, SurfaceInteraction* si) {
  const PreparedQuadric prepared = prepare_quadric(s);
  return intersect_quadric(s, prepared.shape, prepared.world_to_object, rw, t_hit, si);
}

bool intersect_quadric(const ShapeInfo& s, const QuadricShape& q, const Transform& world_to_object,
                       const Ray& rw, float* t_hit, SurfaceInteraction* si) {
  if (!is_quadric(s.kind)) return false;
  if (!q.valid) return false;
  // The ray in object space as pbrt-v3 takes it there: a float transform, its gamma(3) error
  // bounds, the origin moved past them. The intervals the roots are solved with are made only
  // for rays that may meet the surface (most tests are rays through the box that miss it),
  // and never for a disk (in a scene under a large disk, every ray tests it).
  Vec3 o_err, d_err;
  const Vec3 d = world_to_object.vector(rw.d, &d_err);
  const Vec3 o = origin_past_error(world_to_object.point(rw.o, &o_err), d, o_err);
  if (s.kind == ShapeKind::kDisk) return intersect_disk(q, s, world_to_object, o, d, rw, t_hit, si);
  double root;
  if (!may_hit(q, o, d, &root)) return false;
  ObjectRay r = with_intervals(o, d, o_err, d_err);
  EFloat a, b, c, t0, t1;
  coefficients(q, r, &a, &b, &c);
  roots_from(a, b, c, root, &t0, &t1);
  if (!(t1.lower() > 0) && t1.v > 0) {
    // The far root is positive but its interval reaches 0: the transform's
    // rounding alone may hide a real hit. Far from the origin (errors of 1e-3
    // at 2e3) a ray leaving the inside of a sphere at a grazing angle lands
    // here and, rejected, would escape the closed sphere. Decide it again with
    // the exactly rounded object-space ray.
    if (!roots_precise(q, world_to_object, rw, &r, &t0, &t1)) return false;
  }
  // Conservative: a root is used only if its whole interval is in (0, tmax].
  if (!(t0.upper() <= rw.tmax) || !(t1.lower() > 0)) return false;
  EFloat t = t0;
  bool is_far_root = false;
  if (!(t.lower() > 0)) {
    t = t1;
    is_far_root = true;
    if (!(t.upper() <= rw.tmax)) return false;
  }
  Vec3 p;
  if (!locate(q, r, t.v, &p)) {
    // The near hit is cut away: the far one may still be on the surface.
    if (is_far_root || !(t1.upper() <= rw.tmax)) return false;
    t = t1;
    if (!locate(q, r, t.v, &p)) return false;
  }
  if (si && !surface_geometry(q, s, world_to_object, r, t, p, hit_phi(q, p), rw, si)) return false;
  *t_hit = t.v;
  return true;
}

}  // namespace rt
