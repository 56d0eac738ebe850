// runtime/geometry/curve.cpp — see curve.h.
#include "runtime/geometry/curve.h"

#include <algorithm>
#include <cmath>

#include "format/entity_rules.h"
#include "runtime/core/math.h"

namespace rt {

namespace {

Vec3 lerp3(float t, Vec3 a, Vec3 b) {
  return (1 - t) * a + t * b;
}

// The cubic's polar form at (a, b, c): blossom(u0, u0, u0) .. blossom(u1, u1, u1)
// are the control points of the part over [u0, u1].
Vec3 blossom(const Vec3 cp[4], float a, float b, float c) {
  Vec3 a0 = lerp3(a, cp[0], cp[1]), a1 = lerp3(a, cp[1], cp[2]), a2 = lerp3(a, cp[2], cp[3]);
  Vec3 b0 = lerp3(b, a0, a1), b1 = lerp3(b, a1, a2);
  return lerp3(c, b0, b1);
}

// The two halves' control points: out[0..3] and out[3..6].
void split_half(const Vec3 cp[4], Vec3 out[7]) {
  out[0] = cp[0];
  out[1] = (cp[0] + cp[1]) * 0.5f;
  out[2] = (cp[0] + 2 * cp[1] + cp[2]) * 0.25f;
  out[3] = (cp[0] + 3 * cp[1] + 3 * cp[2] + cp[3]) * 0.125f;
  out[4] = (cp[1] + 2 * cp[2] + cp[3]) * 0.25f;
  out[5] = (cp[2] + cp[3]) * 0.5f;
  out[6] = cp[3];
}

// The point at u and the derivative there; where the last de Casteljau
// difference vanishes (coincident control points), the chord stands in for it.
Vec3 eval_bezier(const Vec3 cp[4], float u, Vec3* deriv) {
  Vec3 a[3] = {lerp3(u, cp[0], cp[1]), lerp3(u, cp[1], cp[2]), lerp3(u, cp[2], cp[3])};
  Vec3 b[2] = {lerp3(u, a[0], a[1]), lerp3(u, a[1], a[2])};
  if (deriv) *deriv = length_squared(b[1] - b[0]) > 0 ? 3 * (b[1] - b[0]) : cp[3] - cp[0];
  return lerp3(u, b[0], b[1]);
}

// Rounded log2 of v (0 below 1): the refinement depth is its half.
int log2_rounded(float v) {
  if (!(v >= 1)) return 0;
  int e;
  float m = std::frexp(v, &e);  // v = m 2^e, m in [0.5, 1)
  return e - 1 + (m >= 0.75f ? 1 : 0);
}

// Rotation of v by `radians` about unit axis a (right-handed).
Vec3 rotate_about(Vec3 v, Vec3 a, float radians) {
  float c = std::cos(radians), s = std::sin(radians);
  return v * c + cross(a, v) * s + a * (dot(a, v) * (1 - c));
}

// The frame the ray runs down: origin at the ray's origin, +z along it, +y
// across the piece's chord so that the piece lies nearly flat in xz.
struct RayFrame {
  Vec3 o, x, y, z;
  Vec3 point(Vec3 p) const {
    Vec3 q = p - o;
    return {dot(q, x), dot(q, y), dot(q, z)};
  }
  Vec3 vector(Vec3 v) const { return {dot(v, x), dot(v, y), dot(v, z)}; }
  Vec3 to_object(Vec3 v) const { return x * v.x + y * v.y + z * v.z; }
};

struct Search {
  const CurveShape* curve;
  const CurveSegment* seg;
  RayFrame frame;
  float ray_length;
  float z_max;  // shrinks to the closest hit found
  bool any;     // the caller wants any hit, not the closest
  bool found = false;
  float best_u = 0, best_v = 0, best_z = 0, best_width = 0;
};

float width_at(const CurveSegment& s, float u) {
  return lerp(u, s.width[0], s.width[1]);
}

Vec3 ribbon_normal(const CurveSegment& s, float u) {
  if (!(s.normal_angle > 0)) return s.n[0];
  float s0 = std::sin((1 - u) * s.normal_angle) * s.inv_sin_normal_angle;
  float s1 = std::sin(u * s.normal_angle) * s.inv_sin_normal_angle;
  return s0 * s.n[0] + s1 * s.n[1];
}

// Whether the box of cp grown by half of max_width can hold a hit: it must
// straddle the ray (x = y = 0) within z in [0, z_max].
bool box_overlaps(const Vec3 cp[4], float max_width, float z_max) {
  float h = 0.5f * max_width;
  Vec3 lo = vmin(vmin(cp[0], cp[1]), vmin(cp[2], cp[3]));
  Vec3 hi = vmax(vmax(cp[0], cp[1]), vmax(cp[2], cp[3]));
  // y first: the frame makes it the thinnest extent.
  return hi.y + h >= 0 && lo.y - h <= 0 && hi.x + h >= 0 && lo.x - h <= 0 && hi.z + h >= 0 &&
         lo.z - h <= z_max;
}

// The leaf test: the ray against the piece taken as its chord, then the
// curve's point nearest the ray there.
void leaf(Search& s, const Vec3 cp[4], float u0, float u1) {
  // The ray must pass between the lines through each end perpendicular to the tangent there.
  if ((cp[1].y - cp[0].y) * -cp[0].y + cp[0].x * (cp[0].x - cp[1].x) < 0) return;
  if ((cp[2].y - cp[3].y) * -cp[3].y + cp[3].x * (cp[3].x - cp[2].x) < 0) return;
  float cx = cp[3].x - cp[0].x, cy = cp[3].y - cp[0].y;
  float denom = cx * cx + cy * cy;
  if (denom == 0) return;
  float w = -(cp[0].x * cx + cp[0].y * cy) / denom;
  float u = clamp(lerp(w, u0, u1), u0, u1);
  float hit_width = width_at(*s.seg, u);
  if (s.curve->type == CurveType::kRibbon)
    hit_width *= std::fabs(dot(ribbon_normal(*s.seg, u), s.frame.z));
  Vec3 dpcdw;
  Vec3 pc = eval_bezier(cp, clamp(w, 0.f, 1.f), &dpcdw);
  float dist2 = pc.x * pc.x + pc.y * pc.y;
  if (dist2 > hit_width * hit_width * 0.25f) return;
  if (pc.z < 0 || pc.z > s.z_max) return;
  // v runs across the curve, 0.5 on its centre line; the side is the sign of
  // the point's offset against the tangent.
  float dist = std::sqrt(dist2);
  float edge = dpcdw.x * -pc.y + pc.x * dpcdw.y;
  s.best_v = edge > 0 ? 0.5f + dist / hit_width : 0.5f - dist / hit_width;
  s.best_u = u;
  s.best_z = pc.z;
  s.best_width = hit_width;
  s.found = true;
  s.z_max = pc.z;
}

void refine(Search& s, const Vec3 cp[4], float u0, float u1, int depth) {
  if (depth == 0) return leaf(s, cp, u0, u1);
  Vec3 halves[7];
  split_half(cp, halves);
  float u[3] = {u0, 0.5f * (u0 + u1), u1};
  for (int k = 0; k < 2; ++k) {
    const Vec3* c = halves + 3 * k;
    float max_width = std::max(width_at(*s.seg, u[k]), width_at(*s.seg, u[k + 1]));
    if (!box_overlaps(c, max_width, s.z_max)) continue;
    refine(s, c, u[k], u[k + 1], depth - 1);
    if (s.found && s.any) return;
  }
}

}  // namespace

Bounds3 CurveShape::piece_bounds(uint32_t piece) const {
  const CurveSegment& s = segment_of(piece);
  float a = u0(piece), b = u1(piece);
  Bounds3 box;
  for (int i = 0; i < 4; ++i) box.extend(points_of(piece)[i]);
  float h = 0.5f * std::max(width_at(s, a), width_at(s, b));
  box.lo = box.lo - Vec3{h, h, h};
  box.hi = box.hi + Vec3{h, h, h};
  return box;
}

bool make_curve(const pbrta::SceneArchive& a, uint32_t e, CurveShape* out, std::string* error) {
  *out = CurveShape{};
  const pbrta::ValueRecord* pv = a.value(e, "P");
  const pbrta::ValueRecord* nv = a.value(e, "N");
  pbrta::CurveCounts counts;
  counts.degree = a.get_int(e, "degree", 3);
  std::string_view basis = a.get_string(e, "basis"), type = a.get_string(e, "type");
  if (!basis.empty()) counts.basis = basis;
  if (!type.empty()) counts.type = type;
  counts.control_points = pv ? pv->count : 0;  // elements (points), not floats
  counts.normals_given = nv && nv->count > 0;
  counts.normals = nv ? nv->count : 0;
  pbrta::RuleViolation v;
  if (!pbrta::check_curve_rules(counts, &v)) {
    *error = a.where(e) + ": error: \"" + v.param + "\": " + v.message;
    return false;
  }
  out->type = counts.type == "ribbon"     ? CurveType::kRibbon
              : counts.type == "cylinder" ? CurveType::kCylinder
                                          : CurveType::kFlat;
  // pbrt-v3 makes 2^splitdepth shapes per segment; beyond 2^16 that is only memory.
  out->split_depth = std::clamp(a.get_int(e, "splitdepth", 3), 0, 16);
  const float w = a.get_float(e, "width", 1);
  const float w0 = a.given(e, "width0") ? a.get_float(e, "width0") : w;
  const float w1 = a.given(e, "width1") ? a.get_float(e, "width1") : w;
  const float* P = a.floats(*pv);
  const float* N = counts.normals_given ? a.floats(*nv) : nullptr;
  auto point = [&](uint64_t i) { return Vec3{P[3 * i], P[3 * i + 1], P[3 * i + 2]}; };
  const int degree = counts.degree;
  const bool bezier = counts.basis == "bezier";
  const uint64_t n = counts.control_points;
  const uint64_t segments = bezier ? (n - 1) / degree : n - degree;
  out->segments.resize(segments);
  for (uint64_t k = 0; k < segments; ++k) {
    CurveSegment& s = out->segments[k];
    const uint64_t first = bezier ? k * degree : k;
    Vec3 p[4];
    for (int i = 0; i <= degree; ++i) p[i] = point(first + i);
    if (bezier && degree == 2) {
      // Degree elevation: the same parabola as a cubic.
      s.cp[0] = p[0];
      s.cp[1] = (p[0] + 2 * p[1]) / 3;
      s.cp[2] = (2 * p[1] + p[2]) / 3;
      s.cp[3] = p[2];
    } else if (bezier) {
      for (int i = 0; i < 4; ++i) s.cp[i] = p[i];
    } else if (degree == 2) {
      // A uniform quadratic B-spline span is the Bézier (p0+p1)/2, p1, (p1+p2)/2; then elevated.
      Vec3 b0 = (p[0] + p[1]) * 0.5f, b2 = (p[1] + p[2]) * 0.5f;
      s.cp[0] = b0;
      s.cp[1] = (b0 + 2 * p[1]) / 3;
      s.cp[2] = (2 * p[1] + b2) / 3;
      s.cp[3] = b2;
    } else {
      // The uniform cubic B-spline span's Bézier points.
      s.cp[0] = (p[0] + 4 * p[1] + p[2]) / 6;
      s.cp[1] = (2 * p[1] + p[2]) / 3;
      s.cp[2] = (p[1] + 2 * p[2]) / 3;
      s.cp[3] = (p[1] + 4 * p[2] + p[3]) / 6;
    }
    s.width[0] = lerp(float(k) / float(segments), w0, w1);
    s.width[1] = lerp(float(k + 1) / float(segments), w0, w1);
    if (N && out->type == CurveType::kRibbon) {
      for (int i = 0; i < 2; ++i)
        s.n[i] = normalize(Vec3{N[3 * (k + i)], N[3 * (k + i) + 1], N[3 * (k + i) + 2]});
      // As pbrt-v3: normals more than 90 degrees apart interpolate as if 90 apart.
      s.normal_angle = std::acos(clamp(dot(s.n[0], s.n[1]), 0.f, 1.f));
      s.inv_sin_normal_angle = 1 / std::sin(s.normal_angle);
    }
  }
  out->piece_points.resize(4 * size_t(out->num_pieces()));
  for (uint32_t piece = 0; piece < out->num_pieces(); ++piece) {
    const Vec3* cp = out->segment_of(piece).cp;
    const float a = out->u0(piece), b = out->u1(piece);
    Vec3* p = &out->piece_points[4 * size_t(piece)];
    p[0] = blossom(cp, a, a, a);
    p[1] = blossom(cp, a, a, b);
    p[2] = blossom(cp, a, b, b);
    p[3] = blossom(cp, b, b, b);
  }
  return true;
}

bool intersect_curve_piece(const CurveShape& c, uint32_t piece, const Ray& ray, CurveHit* hit) {
  const CurveSegment& seg = c.segment_of(piece);
  const float u0 = c.u0(piece), u1 = c.u1(piece);
  const Vec3* cp_obj = c.points_of(piece);
  Search s;
  s.curve = &c;
  s.seg = &seg;
  s.ray_length = length(ray.d);
  if (!(s.ray_length > 0)) return false;
  s.frame.o = ray.o;
  s.frame.z = ray.d / s.ray_length;
  Vec3 up = cross(ray.d, cp_obj[3] - cp_obj[0]);
  if (!(length_squared(up) > 0)) {
    Vec3 unused;
    coordinate_system(s.frame.z, &up, &unused);
  }
  s.frame.x = normalize(cross(normalize(up), s.frame.z));
  s.frame.y = cross(s.frame.z, s.frame.x);
  Vec3 cp[4];
  for (int i = 0; i < 4; ++i) cp[i] = s.frame.point(cp_obj[i]);
  s.z_max = s.ray_length * ray.tmax;
  s.any = hit == nullptr;
  const float max_width = std::max(width_at(seg, u0), width_at(seg, u1));
  if (!box_overlaps(cp, max_width, s.z_max)) return false;

  // Refine until the pieces' flatness (their largest second difference, a
  // bound on the chord's distance from the curve) is a 20th of the width.
  float l0 = 0;
  for (int i = 0; i < 2; ++i) {
    Vec3 d2 = abs(cp[i] - 2 * cp[i + 1] + cp[i + 2]);
    l0 = std::max(l0, max_component(d2));
  }
  const float eps = std::max(seg.width[0], seg.width[1]) * 0.05f;
  const int depth = std::clamp(log2_rounded(1.41421356237f * 6.f * l0 / (8.f * eps)) / 2, 0, 10);
  refine(s, cp, u0, u1, depth);
  if (!s.found) return false;
  if (!hit) return true;

  const float u = s.best_u, v = s.best_v, width = s.best_width;
  hit->t = s.best_z / s.ray_length;
  hit->p = ray.at(hit->t);
  // pbrt-v3's bound: the hit is the point on the ray, within a couple of widths of the surface.
  hit->p_error = Vec3{2 * width, 2 * width, 2 * width};
  hit->uv = {u, v};
  eval_bezier(seg.cp, u, &hit->dpdu);
  if (c.type == CurveType::kRibbon) {
    hit->dpdv = normalize(cross(ribbon_normal(seg, u), hit->dpdu)) * width;
  } else {
    // Across the curve in the plane facing the ray; a cylinder turns it about
    // the curve by -90..90 degrees with v, so its normal sweeps a half circle.
    Vec3 dpdu_plane = s.frame.vector(hit->dpdu);
    Vec3 dpdv_plane = normalize(Vec3{-dpdu_plane.y, dpdu_plane.x, 0}) * width;
    if (c.type == CurveType::kCylinder)
      dpdv_plane = rotate_about(dpdv_plane, normalize(dpdu_plane), -radians(lerp(v, -90, 90)));
    hit->dpdv = s.frame.to_object(dpdv_plane);
  }
  return true;
}

}  // namespace rt
