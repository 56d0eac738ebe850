// runtime/geometry/triangle_hit.cpp — see triangle_hit.h.
#include "runtime/geometry/triangle_hit.h"

#include <algorithm>
#include <cmath>

namespace rt {

namespace {

Vec3 load3(const float* a, uint32_t i) {
  return {a[3 * i], a[3 * i + 1], a[3 * i + 2]};
}

// |M| v + |translation|, row by row: the magnitude a point transform's
// rounding error is proportional to.
Vec3 abs_point_sum(const Matrix4& m, Vec3 p) {
  Vec3 r;
  for (int i = 0; i < 3; ++i)
    r[i] = std::fabs(m.m[i][0] * p.x) + std::fabs(m.m[i][1] * p.y) + std::fabs(m.m[i][2] * p.z) +
           std::fabs(m.m[i][3]);
  return r;
}

Vec3 abs_vector(const Matrix4& m, Vec3 v) {
  Vec3 r;
  for (int i = 0; i < 3; ++i)
    r[i] = std::fabs(m.m[i][0]) * v.x + std::fabs(m.m[i][1]) * v.y + std::fabs(m.m[i][2]) * v.z;
  return r;
}

// The computed hit point is off the exact one by up to its error bound in
// every direction, tangents included: near an edge it can land beyond the
// plane of the adjacent wall (a box's inside corner far from the origin), and
// a ray spawned there, offset only along this triangle's normal, starts on
// the wrong side of that wall and leaks. So a hit closer to an edge than
// twice its error bound is moved toward the centroid until it is that far
// inside: a point of the triangle as good as the computed one (both lie within
// the bound of the true hit, up to the margin). True when *b0..*b2 changed.
// The frame's area2 and e2: edge i is opposite vertex i; b_i is the distance to it over the
// height h_i = 2A / |e_i|. The margin in barycentrics: mu_i = 2|error| / h_i.
bool keep_off_edges(const TriangleFrame& f, Vec3 p_error, float* b0, float* b1, float* b2) {
  const float m2 = 4 * length_squared(p_error);  // (2 |error|)^2
  const float area2 = f.area2;
  if (!(area2 > 0)) return false;
  const float* e2 = f.edge2;
  float b[3] = {*b0, *b1, *b2};
  const float k = m2 / area2;  // one division for the three margins
  float s = 0;
  for (int i = 0; i < 3; ++i) {
    const float mu2 = k * e2[i];
    if (b[i] > 0 && b[i] * b[i] >= mu2) continue;
    const float mu = std::sqrt(mu2);
    s = mu >= 1.f / 3 ? 1 : std::max(s, (mu - b[i]) / (1.f / 3 - b[i]));
  }
  if (s <= 0) return false;
  s = std::min(s, 1.f);
  *b0 = b[0] + s * (1.f / 3 - b[0]);
  *b1 = b[1] + s * (1.f / 3 - b[1]);
  *b2 = b[2] + s * (1.f / 3 - b[2]);
  return true;
}

// Embree's hit measured again on the world vertices: t and the barycentrics of the ray's
// point in the triangle's plane (Moller-Trumbore: one division, no branches), in our own
// arithmetic, which does not depend on the CPU as Embree's kernels do. False where the ray
// is parallel to the plane, meets it at t <= 0 or the values overflow; then nothing is
// written.
bool hit_values(Vec3 o, Vec3 d, const Vec3 p[3], float* t, float* b0, float* b1, float* b2) {
  const Vec3 e1 = p[1] - p[0], e2 = p[2] - p[0], pv = cross(d, e2);
  const float det = dot(e1, pv);
  const Vec3 tv = o - p[0], qv = cross(tv, e1);
  const float inv = 1 / det, u = dot(tv, pv) * inv, v = dot(d, qv) * inv, th = dot(e2, qv) * inv;
  if (!(th > 0) || !std::isfinite(th + u + v)) return false;  // det 0, or a sliver's overflow
  *t = th;
  *b0 = 1 - u - v;
  *b1 = u;
  *b2 = v;
  return true;
}

// The uv of vertices v (pbrt-v3's (0,0) (1,0) (1,1) for a mesh without).
void vertex_uvs(const MeshView& m, const uint32_t v[3], Vec2 uv[3]) {
  uv[0] = {0, 0};
  uv[1] = {1, 0};
  uv[2] = {1, 1};
  if (m.uv)
    for (int i = 0; i < 3; ++i) uv[i] = {m.uv[2 * v[i]], m.uv[2 * v[i] + 1]};
}

// The geometric normal from the edges, or +z for a degenerate triangle.
Vec3 edge_normal(const Vec3 p[3]) {
  const Vec3 n = cross(p[0] - p[2], p[1] - p[2]);
  return length_squared(n) > 0 ? normalize(n) : Vec3{0, 0, 1};
}

// The frame's part that a surface only passed through reads: its edges and normal.
void fill_edges(const Vec3 p[3], TriangleFrame* f) {
  f->area2 = length_squared(cross(p[1] - p[0], p[2] - p[0]));  // (2A)^2
  f->edge2[0] = length_squared(p[2] - p[1]);
  f->edge2[1] = length_squared(p[0] - p[2]);
  f->edge2[2] = length_squared(p[1] - p[0]);
  f->n = edge_normal(p);
}

// triangle_frame's work, in place (the hit's own frame is made per hit: no copy out).
inline void fill_frame(const MeshView& m, uint32_t prim, const Vec3 p[3], TriangleFrame* out) {
  TriangleFrame& f = *out;
  fill_edges(p, &f);
  Vec2 uv[3];
  vertex_uvs(m, m.indices + 3 * size_t(prim), uv);
  // dp/du, dp/dv from the uv differences (pbrt-v3's degenerate-uv rule).
  const Vec3 dp02 = p[0] - p[2], dp12 = p[1] - p[2];
  const Vec2 duv02 = uv[0] - uv[2], duv12 = uv[1] - uv[2];
  f.uv_det = duv02.x * duv12.y - duv02.y * duv12.x;
  f.degenerate_uv = std::fabs(f.uv_det) < 1e-8f;
  if (!f.degenerate_uv) {
    float inv = 1 / f.uv_det;
    f.dpdu = (duv12.y * dp02 - duv02.y * dp12) * inv;
    f.dpdv = (duv02.x * dp12 - duv12.x * dp02) * inv;
  }
  if (f.degenerate_uv || length_squared(cross(f.dpdu, f.dpdv)) == 0) {
    Vec3 ng = cross(p[2] - p[0], p[1] - p[0]);
    if (length_squared(ng) > 0) coordinate_system(normalize(ng), &f.dpdu, &f.dpdv);
  }
}

}  // namespace

TriangleFrame triangle_frame(const MeshView& m, uint32_t prim, const Vec3 p[3]) {
  TriangleFrame f;
  fill_frame(m, prim, p, &f);
  return f;
}

void triangle_interaction(const ShapeInfo& s, const TriangleSpace& space, uint32_t prim, float b1,
                          float b2, const Ray& ray, float* t_hit, SurfaceInteraction* si) {
  const MeshView& m = s.mesh;
  const uint32_t* idx = m.indices + 3 * size_t(prim);
  const uint32_t v[3] = {idx[0], idx[1], idx[2]};
  float b0 = 1 - b1 - b2;

  // Buffer space: where Embree intersected the triangle.
  const Transform* buffer_to_world = space.positions_in_world ? nullptr : space.to_world;
  Vec3 pb[3], p[3];
  for (int i = 0; i < 3; ++i) {
    pb[i] = load3(space.positions, v[i]);
    p[i] = buffer_to_world ? buffer_to_world->point(pb[i]) : pb[i];
  }
  if (!space.measured) hit_values(ray.o, ray.d, p, t_hit, &b0, &b1, &b2);
  const bool passed_only = s.passes_through && !m.normals && !m.tangents;
  // Stored frames are of the buffer's own vertices: read only where those are the world's.
  const TriangleFrame* stored = buffer_to_world ? nullptr : space.frames;
  TriangleFrame made;
  if (!stored) {
    if (passed_only)
      fill_edges(p, &made);  // what the early return below reads
    else
      fill_frame(m, prim, p, &made);
  }
  const TriangleFrame& frame = stored ? stored[prim] : made;

  // Hit point and its error bound (pbrt book 3.9.2), on the world vertices.
  si->p = b0 * p[0] + b1 * p[1] + b2 * p[2];
  si->p_error = gamma_bound(7) * (abs(b0 * p[0]) + abs(b1 * p[1]) + abs(b2 * p[2]));
  if (keep_off_edges(frame, si->p_error, &b0, &b1, &b2)) {
    si->p = b0 * p[0] + b1 * p[1] + b2 * p[2];
    si->p_error = gamma_bound(7) * (abs(b0 * p[0]) + abs(b1 * p[1]) + abs(b2 * p[2]));
  }
  const float b[3] = {b0, b1, b2};
  if (buffer_to_world) {
    // Embree intersected the buffer-space triangle with a ray it took to
    // buffer space itself; our world vertices are rounded images of that
    // triangle. Widen the bound by both roundings (vertices out, ray origin in)
    // so spawned rays clear the surface Embree sees, not just ours.
    const Transform& x = *buffer_to_world;
    Vec3 hb = b0 * pb[0] + b1 * pb[1] + b2 * pb[2];
    Vec3 out = gamma_bound(3) * abs_point_sum(x.matrix(), hb);
    Vec3 in = gamma_bound(3) * abs_point_sum(x.inverse_matrix(), si->p);
    si->p_error += out + abs_vector(x.matrix(), in);
  }

  si->wo = -normalize(ray.d);
  si->time = ray.time;
  si->prim = prim;
  si->face_index = m.face_indices ? m.face_indices[prim] : 0;
  si->dpdx = si->dpdy = Vec3{};
  si->dudx = si->dvdx = si->dudy = si->dvdy = 0;

  Vec3 n = frame.n;
  if (space.instance_mirrors) n = -n;
  const bool flip = s.flip_normals();
  if (passed_only) {
    // A medium's boundary, passed through: a ray leaves it from p, offset along n, and n's
    // side says which medium it enters; nothing reads its uv or shading frame (which, without
    // vertex normals or tangents, do not change n's orientation below).
    if (flip) n = -n;
    si->n = n;
    si->shading.n = n;
    return;
  }

  Vec2 uv[3];
  vertex_uvs(m, v, uv);
  si->uv = b0 * uv[0] + b1 * uv[1] + b2 * uv[2];

  const Vec3 dpdu = frame.dpdu, dpdv = frame.dpdv;
  const bool degenerate_uv = frame.degenerate_uv;
  si->dpdu = dpdu;
  si->dpdv = dpdv;
  si->dndu = si->dndv = Vec3{};
  si->shading = {n, dpdu, dpdv, Vec3{}, Vec3{}};

  if (m.normals || m.tangents) {
    // Per-vertex normals and tangents to world: shape transform first (when
    // the buffer does not already include it), then buffer-to-world.
    auto normal_to_world = [&](Vec3 a) {
      if (space.buffer_has_shape_transform) a = s.object_to_world.normal(a);
      return space.to_world ? space.to_world->normal(a) : a;
    };
    auto vector_to_world = [&](Vec3 a) {
      if (space.buffer_has_shape_transform) a = s.object_to_world.vector(a);
      return space.to_world ? space.to_world->vector(a) : a;
    };
    Vec3 nw[3];
    Vec3 ns = n;
    if (m.normals) {
      for (int i = 0; i < 3; ++i) nw[i] = normal_to_world(load3(m.normals, v[i]));
      Vec3 sum = b0 * nw[0] + b1 * nw[1] + b2 * nw[2];
      if (length_squared(sum) > 0) ns = normalize(sum);
    }
    Vec3 ss;
    if (m.tangents) {
      Vec3 sum;
      for (int i = 0; i < 3; ++i) sum += b[i] * vector_to_world(load3(m.tangents, v[i]));
      ss = length_squared(sum) > 0 ? normalize(sum) : normalize(dpdu);
    } else {
      ss = normalize(dpdu);
    }
    // Gram-Schmidt: ts perpendicular to ss and ns, then ss perpendicular to both.
    Vec3 ts = cross(ss, ns);
    if (length_squared(ts) > 0) {
      ts = normalize(ts);
      ss = cross(ts, ns);
    } else {
      coordinate_system(ns, &ss, &ts);
    }
    Vec3 dndu, dndv;
    if (m.normals && !degenerate_uv) {
      Vec3 dn1 = nw[0] - nw[2], dn2 = nw[1] - nw[2];
      const Vec2 duv02 = uv[0] - uv[2], duv12 = uv[1] - uv[2];
      float inv = 1 / frame.uv_det;
      dndu = (duv12.y * dn1 - duv02.y * dn2) * inv;
      dndv = (duv02.x * dn2 - duv12.x * dn1) * inv;
    }
    // pbrt-v3's SetShadingGeometry(ss, ts, dndu, dndv, true), whose shading
    // normal also takes the shape's orientation flip.
    Vec3 sn = normalize(cross(ss, ts));
    if (flip) sn = -sn;
    n = face_forward(n, sn);
    si->shading = {sn, ss, ts, dndu, dndv};
  }

  // pbrt-v3's final orientation: with N the geometric normal follows the
  // shading normal; without, both flip with ReverseOrientation XOR handedness.
  if (m.normals) {
    n = face_forward(n, si->shading.n);
  } else if (flip) {
    n = -n;
    si->shading.n = n;
  }
  si->n = n;
  // An instance's transform is applied to pbrt-v3's finished interaction,
  // which then keeps the shading normal on the geometric normal's side.
  if (space.instance) si->shading.n = face_forward(si->shading.n, si->n);
}

}  // namespace rt
