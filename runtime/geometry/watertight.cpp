// runtime/geometry/watertight.cpp — see watertight.h.
#include "runtime/geometry/watertight.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "runtime/core/math.h"

namespace rt {

bool watertight_triangle(Vec3 o, Vec3 d, float tmax, Vec3 p0, Vec3 p1, Vec3 p2, float* t, float* b1,
                         float* b2) {
  // Ray space: origin at 0, the largest direction component as z, then a
  // shear that makes the ray the +z axis. Edge functions of the sheared
  // vertices' xy decide the hit; the same shared-edge values come out for
  // both triangles of an edge, so nothing passes between them.
  Vec3 a = p0 - o, b = p1 - o, c = p2 - o;
  const int kz = max_dimension(abs(d)), kx = (kz + 1) % 3, ky = (kx + 1) % 3;
  d = permute(d, kx, ky, kz);
  a = permute(a, kx, ky, kz);
  b = permute(b, kx, ky, kz);
  c = permute(c, kx, ky, kz);
  if (d.z == 0) return false;
  const float sx = -d.x / d.z, sy = -d.y / d.z, sz = 1 / d.z;
  a.x += sx * a.z;
  a.y += sy * a.z;
  b.x += sx * b.z;
  b.y += sy * b.z;
  c.x += sx * c.z;
  c.y += sy * c.z;
  float e0 = b.x * c.y - b.y * c.x, e1 = c.x * a.y - c.y * a.x, e2 = a.x * b.y - a.y * b.x;
  if (e0 == 0 || e1 == 0 || e2 == 0) {
    // Exactly on an edge in float: decide it in double, as the book does.
    e0 = float(double(b.x) * c.y - double(b.y) * c.x);
    e1 = float(double(c.x) * a.y - double(c.y) * a.x);
    e2 = float(double(a.x) * b.y - double(a.y) * b.x);
  }
  if ((e0 < 0 || e1 < 0 || e2 < 0) && (e0 > 0 || e1 > 0 || e2 > 0)) return false;
  const float det = e0 + e1 + e2;
  if (det == 0) return false;
  a.z *= sz;
  b.z *= sz;
  c.z *= sz;
  const float t_scaled = e0 * a.z + e1 * b.z + e2 * c.z;
  if (det < 0 && (t_scaled >= 0 || t_scaled < tmax * det)) return false;
  if (det > 0 && (t_scaled <= 0 || t_scaled > tmax * det)) return false;
  const float inv_det = 1 / det;
  const float t_hit = t_scaled * inv_det;
  // t must exceed its own rounding error (book 3.9.6), so a ray leaving the
  // triangle never hits it again.
  const float max_zt = std::max({std::fabs(a.z), std::fabs(b.z), std::fabs(c.z)});
  const float max_xt = std::max({std::fabs(a.x), std::fabs(b.x), std::fabs(c.x)});
  const float max_yt = std::max({std::fabs(a.y), std::fabs(b.y), std::fabs(c.y)});
  const float delta_z = gamma_bound(3) * max_zt;
  const float delta_x = gamma_bound(5) * (max_xt + max_zt);
  const float delta_y = gamma_bound(5) * (max_yt + max_zt);
  const float delta_e =
      2 * (gamma_bound(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
  const float max_e = std::max({std::fabs(e0), std::fabs(e1), std::fabs(e2)});
  const float delta_t = 3 * (gamma_bound(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) *
                        std::fabs(inv_det);
  if (!(t_hit > delta_t)) return false;
  *t = t_hit;
  *b1 = e1 * inv_det;
  *b2 = e2 * inv_det;
  return true;
}

namespace {

Vec3 vertex(const VertexPatches& p, uint32_t v) {
  return {p.positions[3 * v], p.positions[3 * v + 1], p.positions[3 * v + 2]};
}

void patch_bounds(const RTCBoundsFunctionArguments* args) {
  const auto* p = static_cast<const VertexPatches*>(args->geometryUserPtr);
  const Bounds3& b = p->boxes[args->primID];
  *args->bounds_o = {b.lo.x, b.lo.y, b.lo.z, 0, b.hi.x, b.hi.y, b.hi.z, 0};
}

// The closest watertight hit among the triangles of patch `prim`, in
// (tnear, tfar); the ray is in the space of the scene the patch lives in.
bool patch_hit(const VertexPatches& p, unsigned prim, const RTCRay& r, float* t, uint32_t* tri,
               float* b1, float* b2) {
  const Vec3 o{r.org_x, r.org_y, r.org_z}, d{r.dir_x, r.dir_y, r.dir_z};
  bool found = false;
  float tmax = r.tfar;
  for (uint32_t k = p.first[prim]; k < p.first[prim + 1]; ++k) {
    const uint32_t tr = p.triangles[k];
    const uint32_t* i = p.indices + 3 * tr;
    float th, u, v;
    if (watertight_triangle(o, d, tmax, vertex(p, i[0]), vertex(p, i[1]), vertex(p, i[2]), &th, &u,
                            &v) &&
        th > r.tnear) {
      found = true;
      tmax = th;
      *t = th;
      *tri = tr;
      *b1 = u;
      *b2 = v;
    }
  }
  return found;
}

void patch_intersect(const RTCIntersectFunctionNArguments* args) {
  if (!args->valid[0]) return;
  const auto* p = static_cast<const VertexPatches*>(args->geometryUserPtr);
  RTCRayHit* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);
  float t, b1, b2;
  uint32_t tri;
  if (!patch_hit(*p, args->primID, rh->ray, &t, &tri, &b1, &b2)) return;
  const uint32_t* i = p->indices + 3 * tri;
  Vec3 n = cross(vertex(*p, i[1]) - vertex(*p, i[0]), vertex(*p, i[2]) - vertex(*p, i[0]));
  rh->ray.tfar = t;
  rh->hit.u = b1;
  rh->hit.v = b2;
  rh->hit.Ng_x = n.x;
  rh->hit.Ng_y = n.y;
  rh->hit.Ng_z = n.z;
  rh->hit.primID = tri;
  rh->hit.geomID = p->triangle_geom_id;
  rh->hit.instID[0] = args->context->instID[0];
}

void patch_occluded(const RTCOccludedFunctionNArguments* args) {
  if (!args->valid[0]) return;
  const auto* p = static_cast<const VertexPatches*>(args->geometryUserPtr);
  RTCRay* r = reinterpret_cast<RTCRay*>(args->ray);
  float t, b1, b2;
  uint32_t tri;
  if (patch_hit(*p, args->primID, *r, &t, &tri, &b1, &b2)) r->tfar = -kInfinity;
}

}  // namespace

void attach_vertex_patches(RTCDevice device, RTCScene scene, const float* positions,
                           const uint32_t* indices, uint32_t num_vertices, uint32_t num_triangles,
                           unsigned triangle_geom_id, VertexPatches* p) {
  p->positions = positions;
  p->indices = indices;
  p->triangle_geom_id = triangle_geom_id;
  // Embree's cracks are a few ulps of the coordinates (relative to ray
  // origins inside the scene): 2^-18 of magnitude plus extent is ~32 ulps.
  Bounds3 mesh;
  for (uint32_t v = 0; v < num_vertices; ++v) mesh.extend(vertex(*p, v));
  const float magnitude = std::max(max_component(abs(mesh.lo)), max_component(abs(mesh.hi)));
  const float h = std::ldexp(magnitude + length(mesh.hi - mesh.lo), -18);
  const Vec3 pad{h, h, h};

  // Vertex patches: every triangle around each vertex (CSR by counting).
  p->first.assign(size_t(num_vertices) + 1, 0);
  for (uint32_t k = 0; k < 3 * num_triangles; ++k) ++p->first[indices[k] + 1];
  for (uint32_t v = 0; v < num_vertices; ++v) p->first[v + 1] += p->first[v];
  p->triangles.resize(3 * size_t(num_triangles));
  std::vector<uint32_t> fill(p->first.begin(), p->first.end() - 1);
  for (uint32_t k = 0; k < 3 * num_triangles; ++k) p->triangles[fill[indices[k]]++] = k / 3;
  p->boxes.resize(num_vertices);
  for (uint32_t v = 0; v < num_vertices; ++v)
    p->boxes[v] = {vertex(*p, v) - pad, vertex(*p, v) + pad};

  // Sliver-edge patches: the triangles sharing each edge of a sliver.
  std::vector<std::pair<uint64_t, uint32_t>> sliver_edges;  // (edge key, triangle)
  for (uint32_t t = 0; t < num_triangles; ++t) {
    const uint32_t* i = indices + 3 * t;
    Vec3 a = vertex(*p, i[0]), b = vertex(*p, i[1]), c = vertex(*p, i[2]);
    float longest2 =
        std::max({length_squared(b - a), length_squared(c - b), length_squared(a - c)});
    if (!(length(cross(b - a, c - a)) < std::ldexp(longest2, -10))) continue;
    for (int e = 0; e < 3; ++e) {
      uint32_t u = i[e], w = i[(e + 1) % 3];
      sliver_edges.push_back({(uint64_t(std::min(u, w)) << 32) | std::max(u, w), t});
    }
  }
  if (!sliver_edges.empty()) {
    std::vector<uint64_t> keys;
    for (const auto& e : sliver_edges) keys.push_back(e.first);
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    // Every triangle of the mesh on one of those edges (the sliver and its neighbours).
    std::vector<std::pair<uint64_t, uint32_t>> on_edge;
    for (uint32_t t = 0; t < num_triangles; ++t)
      for (int e = 0; e < 3; ++e) {
        uint32_t u = indices[3 * t + e], w = indices[3 * t + (e + 1) % 3];
        uint64_t key = (uint64_t(std::min(u, w)) << 32) | std::max(u, w);
        if (std::binary_search(keys.begin(), keys.end(), key)) on_edge.push_back({key, t});
      }
    std::sort(on_edge.begin(), on_edge.end());
    for (size_t k = 0; k < on_edge.size();) {
      const uint64_t key = on_edge[k].first;
      Bounds3 box;
      box.extend(vertex(*p, uint32_t(key >> 32)));
      box.extend(vertex(*p, uint32_t(key & 0xffffffffu)));
      p->boxes.push_back({box.lo - pad, box.hi + pad});
      for (; k < on_edge.size() && on_edge[k].first == key; ++k)
        p->triangles.push_back(on_edge[k].second);
      p->first.push_back(uint32_t(p->triangles.size()));
    }
  }

  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(geom, unsigned(p->boxes.size()));
  rtcSetGeometryUserData(geom, p);
  rtcSetGeometryBoundsFunction(geom, patch_bounds, nullptr);
  rtcSetGeometryIntersectFunction(geom, patch_intersect);
  rtcSetGeometryOccludedFunction(geom, patch_occluded);
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
}

}  // namespace rt
