#include "compiler/refine.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <unordered_map>
#include <utility>
#include <vector>

namespace pbrtc {

namespace {

// Refinement that would make more triangles than this is refused: pbrt-v3 would
// try and run out of memory, and the archive could not index the result.
constexpr uint64_t kMaxRefinedTriangles = uint64_t(1) << 28;

// ---- Float 3-vectors -------------------------------------------------------------------------
// Every operation is done in float, in the order pbrt-v3's Point3f/Vector3f code does it, so
// the refined geometry rounds the way pbrt-v3's does.

struct V3 {
  float x = 0, y = 0, z = 0;
};
V3 operator+(V3 a, V3 b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
V3 operator-(V3 a, V3 b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
V3 operator-(V3 a) {
  return {-a.x, -a.y, -a.z};
}
V3 operator*(float s, V3 a) {
  return {s * a.x, s * a.y, s * a.z};
}
V3& operator+=(V3& a, V3 b) {
  return a = a + b;
}

// pbrt-v3's Cross works in double and rounds the result to float.
V3 cross(V3 a, V3 b) {
  double ax = a.x, ay = a.y, az = a.z, bx = b.x, by = b.y, bz = b.z;
  return {float(ay * bz - az * by), float(az * bx - ax * bz), float(ax * by - ay * bx)};
}

bool finite(V3 a) {
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}

// pbrt-v3's Pi is a float constant.
constexpr float kPi = 3.14159265358979323846f;

// ---- Entity access ---------------------------------------------------------------------------

// An int array parameter (the resolver keeps kInt arrays in Entity::ints).
const int32_t* ints_of(const Entity& e, std::string_view name, uint32_t* count) {
  int s = e.slot(name);
  if (s < 0 || e.values[size_t(s)].count == 0) {
    *count = 0;
    return nullptr;
  }
  *count = e.values[size_t(s)].count;
  return e.ints.data() + e.values[size_t(s)].offset;
}

std::string str(uint64_t n) {
  return std::to_string(n);
}
std::string str(int64_t n) {
  return std::to_string(n);
}
std::string str(int n) {
  return std::to_string(n);
}
std::string str(float f) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", double(f));
  return buf;
}

// ---- Loop subdivision ------------------------------------------------------------------------
// The mesh is kept as pbrt-v3 keeps it: triangles knowing their three neighbours, vertices
// knowing one triangle they touch, which fixes where a vertex's one-ring starts (and so the
// order its neighbours are summed in and the angle its tangents are measured from).

int next_corner(int i) {
  return (i + 1) % 3;
}
int prev_corner(int i) {
  return (i + 2) % 3;
}

struct SdVertex {
  V3 p;
  int32_t start_face = -1;
  bool boundary = false;
};

struct SdFace {
  int32_t v[3];
  int32_t nbr[3] = {-1, -1, -1};  // nbr[i]: the triangle across the edge v[i] -> v[i + 1]
};

struct SdMesh {
  std::vector<SdVertex> verts;
  std::vector<SdFace> faces;

  int corner(int32_t f, int32_t v) const {
    const SdFace& face = faces[size_t(f)];
    return face.v[0] == v ? 0 : face.v[1] == v ? 1 : 2;
  }
  // Around a vertex, "next" turns across the edge leaving it in the triangle's winding.
  int32_t next_face(int32_t f, int32_t v) const { return faces[size_t(f)].nbr[corner(f, v)]; }
  int32_t prev_face(int32_t f, int32_t v) const {
    return faces[size_t(f)].nbr[prev_corner(corner(f, v))];
  }
  int32_t next_vert(int32_t f, int32_t v) const {
    return faces[size_t(f)].v[next_corner(corner(f, v))];
  }
  int32_t prev_vert(int32_t f, int32_t v) const {
    return faces[size_t(f)].v[prev_corner(corner(f, v))];
  }

  // The positions around vertex v in pbrt-v3's order; the valence is ring->size(). An interior
  // vertex's ring starts at its start face's next vertex and turns forwards; a boundary
  // vertex's starts at the far end of the forward turn and comes back. False only if the
  // topology is broken (validation makes that impossible; the bound keeps it from hanging).
  bool one_ring(int32_t v, std::vector<V3>* ring) const {
    ring->clear();
    const SdVertex& vert = verts[size_t(v)];
    int32_t f = vert.start_face;
    size_t guard = faces.size() + 1;
    if (!vert.boundary) {
      do {
        ring->push_back(verts[size_t(next_vert(f, v))].p);
        f = next_face(f, v);
        if (f < 0 || --guard == 0) return false;
      } while (f != vert.start_face);
      return true;
    }
    for (int32_t g; (g = next_face(f, v)) >= 0; f = g)
      if (--guard == 0) return false;
    ring->push_back(verts[size_t(next_vert(f, v))].p);
    guard = faces.size() + 1;
    do {
      ring->push_back(verts[size_t(prev_vert(f, v))].p);
      f = prev_face(f, v);
      if (--guard == 0) return false;
    } while (f >= 0);
    return true;
  }
};

// pbrt-v3's vertex weight: 3/(8n), except 3/16 for valence 3. For the regular valence 6 this
// is the 1/16 pbrt-v3 uses for regular vertices, so no separate case is needed.
float loop_beta(int valence) {
  return valence == 3 ? 3.f / 16.f : 3.f / (8.f * float(valence));
}

// The weight of each neighbour in the limit position of an interior vertex.
float loop_gamma(int valence) {
  return 1.f / (float(valence) + 3.f / (8.f * loop_beta(valence)));
}

V3 weight_one_ring(V3 p, const std::vector<V3>& ring, float beta) {
  int valence = int(ring.size());
  V3 r = (1 - float(valence) * beta) * p;
  for (const V3& q : ring) r += beta * q;
  return r;
}

// Boundary vertices see only their two neighbours along the boundary.
V3 weight_boundary(V3 p, const std::vector<V3>& ring, float beta) {
  V3 r = (1 - 2 * beta) * p;
  r += beta * ring.front();
  r += beta * ring.back();
  return r;
}

const char* kBrokenTopology = "loopsubdiv: internal error: inconsistent subdivision topology";

// Builds level 0: validates the triangles and links neighbours. A vertex's start face is the
// last triangle that uses it, as in pbrt-v3.
bool build_base_mesh(const int32_t* indices, size_t num_indices, const float* P,
                     size_t num_vertices, SdMesh* m, std::string* error) {
  if (num_indices % 3 != 0) {
    *error = "loopsubdiv has " + str(uint64_t(num_indices)) + " indices, not a multiple of 3";
    return false;
  }
  if (num_indices == 0) {
    *error = "loopsubdiv has no triangles";
    return false;
  }
  if (num_vertices > uint64_t(std::numeric_limits<int32_t>::max())) {
    *error = "loopsubdiv has too many vertices";
    return false;
  }
  size_t nf = num_indices / 3;
  m->verts.resize(num_vertices);
  for (size_t i = 0; i < num_vertices; ++i) m->verts[i].p = {P[3 * i], P[3 * i + 1], P[3 * i + 2]};
  m->faces.resize(nf);
  for (size_t f = 0; f < nf; ++f) {
    SdFace& face = m->faces[f];
    for (int j = 0; j < 3; ++j) {
      int32_t v = indices[3 * f + size_t(j)];
      if (v < 0 || uint64_t(v) >= num_vertices) {
        *error = "loopsubdiv index " + str(v) + " (entry " + str(uint64_t(3 * f + size_t(j))) +
                 ") is out of range: " + str(uint64_t(num_vertices)) + " vertices";
        return false;
      }
      face.v[j] = v;
      m->verts[size_t(v)].start_face = int32_t(f);
    }
    if (face.v[0] == face.v[1] || face.v[1] == face.v[2] || face.v[2] == face.v[0]) {
      // pbrt-v3 cannot tell a repeated vertex's corners apart and corrupts its topology.
      *error = "loopsubdiv triangle " + str(uint64_t(f)) + " uses vertex " +
               str(face.v[0] == face.v[1] || face.v[0] == face.v[2] ? face.v[0] : face.v[1]) +
               " twice";
      return false;
    }
  }
  for (size_t v = 0; v < num_vertices; ++v) {
    if (m->verts[v].start_face < 0) {
      // pbrt-v3 dereferences the missing triangle and crashes.
      *error = "loopsubdiv vertex " + str(uint64_t(v)) +
               " is not used by any triangle (pbrt-v3 cannot subdivide such a mesh)";
      return false;
    }
  }

  // Link triangles across shared edges. pbrt-v3 pairs the first two triangles on an edge and
  // takes a third for a boundary, and walks in circles when neighbours disagree on the edge's
  // direction; both are refused here so that the walks around vertices always end.
  struct EdgeUse {
    int32_t face;
    int8_t edge;
    bool paired;
  };
  std::unordered_map<uint64_t, EdgeUse> edges;
  edges.reserve(num_indices);
  for (size_t f = 0; f < nf; ++f) {
    SdFace& face = m->faces[f];
    for (int k = 0; k < 3; ++k) {
      int32_t a = face.v[k], b = face.v[next_corner(k)];
      uint64_t key = (uint64_t(uint32_t(std::min(a, b))) << 32) | uint32_t(std::max(a, b));
      auto [it, inserted] = edges.emplace(key, EdgeUse{int32_t(f), int8_t(k), false});
      if (inserted) continue;
      EdgeUse& use = it->second;
      std::string edge_name = "edge " + str(std::min(a, b)) + "-" + str(std::max(a, b));
      if (use.paired) {
        *error = "loopsubdiv " + edge_name + " is shared by more than two triangles (" +
                 "triangle " + str(uint64_t(f)) + " is the third); the mesh must be a manifold";
        return false;
      }
      SdFace& other = m->faces[size_t(use.face)];
      if (other.v[use.edge] == a) {
        *error = "loopsubdiv triangles " + str(use.face) + " and " + str(uint64_t(f)) + " run " +
                 edge_name + " in the same direction: their orientations disagree";
        return false;
      }
      use.paired = true;
      other.nbr[use.edge] = int32_t(f);
      face.nbr[k] = use.face;
    }
  }

  // A vertex is on the boundary if turning forwards from its start face runs off the mesh.
  for (size_t v = 0; v < num_vertices; ++v) {
    SdVertex& vert = m->verts[v];
    int32_t f = vert.start_face;
    size_t guard = nf + 1;
    do {
      f = m->next_face(f, int32_t(v));
    } while (f >= 0 && f != vert.start_face && --guard > 0);
    vert.boundary = f < 0;
  }
  return true;
}

// One round of Loop subdivision: every triangle becomes four. Vertex i of m becomes vertex i
// of the result; the new edge vertices follow in the order the triangles first reach their
// edges; triangle f becomes triangles 4f .. 4f+3 (three corners, then the middle one).
bool subdivide_once(const SdMesh& m, SdMesh* out, std::string* error) {
  size_t nv = m.verts.size(), nf = m.faces.size();
  out->verts.assign(nv, SdVertex{});
  out->faces.assign(4 * nf, SdFace{});
  std::vector<V3> ring;

  // Old vertices move by the one-ring rule (interior) or the 1/8-3/4-1/8 rule (boundary).
  for (size_t i = 0; i < nv; ++i) {
    const SdVertex& v = m.verts[i];
    if (!m.one_ring(int32_t(i), &ring)) {
      *error = kBrokenTopology;
      return false;
    }
    SdVertex& child = out->verts[i];
    child.boundary = v.boundary;
    child.p = v.boundary ? weight_boundary(v.p, ring, 1.f / 8.f)
                         : weight_one_ring(v.p, ring, loop_beta(int(ring.size())));
    child.start_face = int32_t(4 * size_t(v.start_face)) + m.corner(v.start_face, int32_t(i));
  }

  // One new vertex per edge: 3/8, 3/8 of its ends and 1/8, 1/8 of the two opposite vertices,
  // or the midpoint on a boundary edge.
  std::vector<int32_t> edge_vert(3 * nf, -1);
  for (size_t f = 0; f < nf; ++f) {
    const SdFace& face = m.faces[f];
    for (int k = 0; k < 3; ++k) {
      if (edge_vert[3 * f + size_t(k)] >= 0) continue;  // made by the neighbour
      int32_t a = face.v[k], b = face.v[next_corner(k)];
      int32_t n = face.nbr[k];
      SdVertex ev;
      ev.boundary = n < 0;
      ev.start_face = int32_t(4 * f + 3);
      const V3 pa = m.verts[size_t(a)].p, pb = m.verts[size_t(b)].p;
      if (ev.boundary) {
        ev.p = 0.5f * pa;
        ev.p += 0.5f * pb;
      } else {
        const SdFace& nface = m.faces[size_t(n)];
        int32_t far_here = face.v[prev_corner(k)];
        int nk = 0;  // the neighbour's corner where this edge ends (it runs b -> a there)
        while (nface.v[nk] != b) ++nk;
        int32_t far_there = nface.v[prev_corner(nk)];
        ev.p = 3.f / 8.f * pa;
        ev.p += 3.f / 8.f * pb;
        ev.p += 1.f / 8.f * m.verts[size_t(far_here)].p;
        ev.p += 1.f / 8.f * m.verts[size_t(far_there)].p;
        edge_vert[3 * size_t(n) + size_t(nk)] = int32_t(out->verts.size());
      }
      edge_vert[3 * f + size_t(k)] = int32_t(out->verts.size());
      out->verts.push_back(ev);
    }
  }

  // Child triangle j keeps corner j of its parent and the two edge vertices beside it; the
  // middle child is made of the three edge vertices. Neighbours across the parent's edges are
  // the neighbouring parent's children at the shared corners.
  for (size_t f = 0; f < nf; ++f) {
    const SdFace& face = m.faces[f];
    SdFace* c = &out->faces[4 * f];
    for (int j = 0; j < 3; ++j) {
      c[3].nbr[j] = int32_t(4 * f) + next_corner(j);
      c[j].nbr[next_corner(j)] = int32_t(4 * f + 3);
      int32_t n = face.nbr[j];
      c[j].nbr[j] = n >= 0 ? 4 * n + m.corner(n, face.v[j]) : -1;
      n = face.nbr[prev_corner(j)];
      c[j].nbr[prev_corner(j)] = n >= 0 ? 4 * n + m.corner(n, face.v[j]) : -1;

      c[j].v[j] = face.v[j];
      int32_t e = edge_vert[3 * f + size_t(j)];
      c[j].v[next_corner(j)] = e;
      c[next_corner(j)].v[j] = e;
      c[3].v[j] = e;
    }
  }
  return true;
}

}  // namespace

bool loop_subdivide(int levels, const int32_t* indices, size_t num_indices, const float* P,
                    size_t num_vertices, TriangleMesh* out, std::string* error) {
  if (levels < 0) {
    *error = "loopsubdiv \"levels\" is " + str(levels) + "; it must be 0 or more";
    return false;
  }
  uint64_t triangles = num_indices / 3;
  for (int i = 0; i < levels && triangles <= kMaxRefinedTriangles; ++i) triangles *= 4;
  if (triangles > kMaxRefinedTriangles) {
    *error = "loopsubdiv with " + str(levels) + " levels would make more than " +
             str(kMaxRefinedTriangles) + " triangles";
    return false;
  }
  SdMesh m;
  if (!build_base_mesh(indices, num_indices, P, num_vertices, &m, error)) return false;
  for (int i = 0; i < levels; ++i) {
    SdMesh next;
    if (!subdivide_once(m, &next, error)) return false;
    m = std::move(next);
  }

  // Move every vertex to its limit position (all from the last level's positions), then
  // measure tangents on the limit positions.
  size_t nv = m.verts.size();
  std::vector<V3> ring;
  std::vector<V3> limit(nv);
  for (size_t i = 0; i < nv; ++i) {
    const SdVertex& v = m.verts[i];
    if (!m.one_ring(int32_t(i), &ring)) {
      *error = kBrokenTopology;
      return false;
    }
    limit[i] = v.boundary ? weight_boundary(v.p, ring, 1.f / 5.f)
                          : weight_one_ring(v.p, ring, loop_gamma(int(ring.size())));
  }
  for (size_t i = 0; i < nv; ++i) m.verts[i].p = limit[i];

  out->P.resize(3 * nv);
  out->N.resize(3 * nv);
  for (size_t i = 0; i < nv; ++i) {
    const SdVertex& v = m.verts[i];
    m.one_ring(int32_t(i), &ring);  // succeeded above on the same topology
    int valence = int(ring.size());
    V3 s, t;
    if (!v.boundary) {
      // The first harmonics of the ring: two tangent directions of the limit surface.
      for (int j = 0; j < valence; ++j) {
        s += std::cos(2 * kPi * float(j) / float(valence)) * ring[size_t(j)];
        t += std::sin(2 * kPi * float(j) / float(valence)) * ring[size_t(j)];
      }
    } else {
      // Along the boundary, and across it with pbrt-v3's per-valence stencils.
      s = ring.back() - ring.front();
      const V3& p = v.p;
      if (valence == 2) {
        t = ring[0] + ring[1] - 2 * p;
      } else if (valence == 3) {
        t = ring[1] - p;
      } else if (valence == 4) {
        t = -1 * ring[0] + 2 * ring[1] + 2 * ring[2] + -1 * ring[3] + -2 * p;
      } else {
        float theta = kPi / float(valence - 1);
        t = std::sin(theta) * (ring.front() + ring.back());
        for (int k = 1; k < valence - 1; ++k) {
          float wt = (2 * std::cos(theta) - 2) * std::sin(float(k) * theta);
          t += wt * ring[size_t(k)];
        }
        t = -t;
      }
    }
    // Not normalized: pbrt-v3 stores this cross product as the vertex normal and normalizes
    // only after interpolating across a triangle.
    V3 n = cross(s, t);
    out->P[3 * i] = v.p.x, out->P[3 * i + 1] = v.p.y, out->P[3 * i + 2] = v.p.z;
    out->N[3 * i] = n.x, out->N[3 * i + 1] = n.y, out->N[3 * i + 2] = n.z;
  }
  out->indices.resize(3 * m.faces.size());
  for (size_t f = 0; f < m.faces.size(); ++f)
    for (int j = 0; j < 3; ++j) out->indices[3 * f + size_t(j)] = uint32_t(m.faces[f].v[j]);
  out->refine_level = uint32_t(levels);
  return true;
}

bool refine_loopsubdiv(const Entity& shape, TriangleMesh* out, std::string* error) {
  uint32_t num_indices = 0, num_points = 0;
  const int32_t* indices = ints_of(shape, "indices", &num_indices);
  const float* P = shape.get_floats("P", &num_points);
  return loop_subdivide(shape.get_int("levels"), indices, num_indices, P, num_points, out, error);
}

// ---- NURBS -----------------------------------------------------------------------------------
// pbrt-v3 evaluates a NURBS surface at a fixed grid of parameter values with de Boor's
// algorithm on homogeneous control points, one isoparametric curve at a time.

namespace {

struct H4 {
  float x = 0, y = 0, z = 0, w = 0;
};

// The knot span [knot[s], knot[s + 1]] that t is evaluated in: the first from order - 1 whose
// end is not below t. pbrt-v3 relies on t <= knot[np]; the bound keeps a t that rounding
// pushed past the last knot in the last span.
int knot_span(const float* knot, int order, int np, float t) {
  int s = order - 1;
  while (s < np - 1 && t > knot[s + 1]) ++s;
  return s;
}

// Evaluates the curve of np control points cp(0 .. np-1) at t; with deriv, also the
// derivative of the projected (3D) curve.
template <class ControlPoint>
H4 nurbs_evaluate(int order, const float* knot, int np, ControlPoint cp, float t, V3* deriv,
                  std::vector<H4>* work_storage) {
  int s = knot_span(knot, order, np, t);
  int first = s - order + 1;
  std::vector<H4>& w = *work_storage;
  w.resize(size_t(order));
  for (int i = 0; i < order; ++i) w[size_t(i)] = cp(first + i);

  // Each round blends neighbouring points with weights from the knots around the span, until
  // two remain; the last blend gives the point and their difference the derivative.
  auto blend = [](const H4& a, const H4& b, float alpha) {
    return H4{a.x * alpha + b.x * (1 - alpha), a.y * alpha + b.y * (1 - alpha),
              a.z * alpha + b.z * (1 - alpha), a.w * alpha + b.w * (1 - alpha)};
  };
  for (int i = 0; i < order - 2; ++i) {
    for (int j = 0; j < order - 1 - i; ++j) {
      float hi = knot[s + 1 + j], lo = knot[s + j + 2 - order + i];
      w[size_t(j)] = blend(w[size_t(j)], w[size_t(j) + 1], (hi - t) / (hi - lo));
    }
  }
  float alpha = (knot[s + 1] - t) / (knot[s + 1] - knot[s]);
  H4 val = blend(w[0], w[1], alpha);
  if (deriv) {
    float factor = float(order - 1) / (knot[s + 1] - knot[s]);
    H4 d{(w[1].x - w[0].x) * factor, (w[1].y - w[0].y) * factor, (w[1].z - w[0].z) * factor,
         (w[1].w - w[0].w) * factor};
    // The quotient rule for x/w.
    deriv->x = d.x / val.w - (val.x * d.w / (val.w * val.w));
    deriv->y = d.y / val.w - (val.y * d.w / (val.w * val.w));
    deriv->z = d.z / val.w - (val.z * d.w / (val.w * val.w));
  }
  return val;
}

struct NurbsAxis {
  int n = 0, order = 0;
  const float* knots = nullptr;
};

// The surface point at (u, v) with its partial derivatives. Control points are u-major:
// point (i, j) is cp[j * nu + i].
V3 nurbs_surface(const NurbsAxis& ua, const NurbsAxis& va, const std::vector<H4>& cp, float u,
                 float v, V3* dpdu, V3* dpdv, std::vector<H4>* iso, std::vector<H4>* work) {
  iso->resize(size_t(std::max(ua.order, va.order)));
  int u_first = knot_span(ua.knots, ua.order, ua.n, u) - ua.order + 1;
  // The columns that matter at u, each evaluated at v; then that curve at u.
  for (int i = 0; i < ua.order; ++i) {
    (*iso)[size_t(i)] = nurbs_evaluate(
        va.order, va.knots, va.n,
        [&](int j) { return cp[size_t(j) * size_t(ua.n) + size_t(u_first + i)]; }, v, nullptr,
        work);
  }
  H4 p = nurbs_evaluate(
      ua.order, ua.knots, ua.n, [&](int j) { return (*iso)[size_t(j - u_first)]; }, u, dpdu, work);
  // dp/dv the other way round: the rows that matter at v, each at u; then that curve at v.
  int v_first = knot_span(va.knots, va.order, va.n, v) - va.order + 1;
  for (int i = 0; i < va.order; ++i) {
    (*iso)[size_t(i)] = nurbs_evaluate(
        ua.order, ua.knots, ua.n,
        [&](int j) { return cp[size_t(v_first + i) * size_t(ua.n) + size_t(j)]; }, u, nullptr,
        work);
  }
  nurbs_evaluate(
      va.order, va.knots, va.n, [&](int j) { return (*iso)[size_t(j - v_first)]; }, v, dpdv, work);
  return {p.x / p.w, p.y / p.w, p.z / p.w};
}

// Checks one direction's control point count, order and knots, and finds its parameter range.
bool nurbs_axis(const Entity& e, char axis, NurbsAxis* a, float* t0, float* t1,
                std::string* error) {
  std::string n_name = std::string("n") + axis, order_name = std::string(1, axis) + "order",
              knots_name = std::string(1, axis) + "knots";
  a->n = e.get_int(n_name);
  a->order = e.get_int(order_name);
  uint32_t num_knots = 0;
  a->knots = e.get_floats(knots_name, &num_knots);
  if (a->order < 2) {
    *error = "nurbs \"" + order_name + "\" is " + str(a->order) + "; it must be at least 2";
    return false;
  }
  if (a->n < a->order) {
    *error = "nurbs \"" + n_name + "\" is " + str(a->n) + "; it must be at least \"" + order_name +
             "\" (" + str(a->order) + ")";
    return false;
  }
  if (int64_t(num_knots) != int64_t(a->n) + a->order) {
    *error = "nurbs \"" + knots_name + "\" has " + str(uint64_t(num_knots)) + " knots; it needs " +
             n_name + " + " + order_name + " = " + str(int64_t(a->n) + a->order);
    return false;
  }
  for (uint32_t i = 1; i < num_knots; ++i) {
    if (a->knots[i] < a->knots[i - 1]) {
      *error = "nurbs \"" + knots_name + "\" decreases at entry " + str(uint64_t(i)) + " (" +
               str(a->knots[i - 1]) + " then " + str(a->knots[i]) + ")";
      return false;
    }
  }
  // The range pbrt-v3 defaults to is where the whole order of basis functions is defined.
  float lo = a->knots[a->order - 1], hi = a->knots[a->n];
  std::string n0 = std::string(1, axis) + "0", n1 = std::string(1, axis) + "1";
  *t0 = e.given(n0) ? e.get_float(n0) : lo;
  *t1 = e.given(n1) ? e.get_float(n1) : hi;
  for (auto [name, t] : {std::pair{&n0, *t0}, std::pair{&n1, *t1}}) {
    if (!(t >= lo && t <= hi)) {
      *error = "nurbs \"" + *name + "\" is " + str(t) + ", outside the knot range [" + str(lo) +
               ", " + str(hi) + "] (" + knots_name + "[" + order_name + " - 1], " + knots_name +
               "[" + n_name + "])";
      return false;
    }
  }
  return true;
}

}  // namespace

bool refine_nurbs(const Entity& shape, TriangleMesh* out, std::string* error) {
  NurbsAxis ua, va;
  float u0, u1, v0, v1;
  if (!nurbs_axis(shape, 'u', &ua, &u0, &u1, error)) return false;
  if (!nurbs_axis(shape, 'v', &va, &v0, &v1, error)) return false;
  int64_t want = int64_t(ua.n) * va.n;

  // pbrt-v3 takes "P" when given, else "Pw" (x, y, z, w per point).
  std::vector<H4> cp;
  uint32_t count = 0;
  if (const float* P = shape.get_floats("P", &count)) {
    if (count != want) {
      *error = "nurbs \"point P\" has " + str(uint64_t(count)) +
               " control points; nu * nv = " + str(want);
      return false;
    }
    cp.resize(count);
    for (size_t i = 0; i < count; ++i) cp[i] = {P[3 * i], P[3 * i + 1], P[3 * i + 2], 1.f};
  } else if (const float* Pw = shape.get_floats("Pw", &count)) {
    if (count % 4 != 0) {
      *error = "nurbs \"float Pw\" has " + str(uint64_t(count)) +
               " numbers, not a multiple of 4 (x y z w per control point)";
      return false;
    }
    if (count / 4 != want) {
      *error = "nurbs \"float Pw\" has " + str(uint64_t(count / 4)) +
               " control points; nu * nv = " + str(want);
      return false;
    }
    cp.resize(count / 4);
    for (size_t i = 0; i < cp.size(); ++i)
      cp[i] = {Pw[4 * i], Pw[4 * i + 1], Pw[4 * i + 2], Pw[4 * i + 3]};
  } else {
    *error = "nurbs needs control points \"point P\" or \"float Pw\"";
    return false;
  }

  const int dice = kNurbsDice;
  std::vector<float> ueval(dice), veval(dice);
  // pbrt-v3's Lerp: (1 - t) a + t b.
  for (int i = 0; i < dice; ++i) {
    float t = float(i) / float(dice - 1);
    ueval[size_t(i)] = (1 - t) * u0 + t * u1;
    veval[size_t(i)] = (1 - t) * v0 + t * v1;
  }
  size_t nverts = size_t(dice) * size_t(dice);
  out->P.resize(3 * nverts);
  out->N.resize(3 * nverts);
  out->uv.resize(2 * nverts);
  std::vector<H4> iso, work;
  for (int v = 0; v < dice; ++v) {
    for (int u = 0; u < dice; ++u) {
      size_t i = size_t(v) * size_t(dice) + size_t(u);
      V3 dpdu, dpdv;
      V3 p =
          nurbs_surface(ua, va, cp, ueval[size_t(u)], veval[size_t(v)], &dpdu, &dpdv, &iso, &work);
      if (!finite(p)) {
        *error = "nurbs evaluates to a non-finite point at (u, v) = (" + str(ueval[size_t(u)]) +
                 ", " + str(veval[size_t(v)]) + ") (a zero weight, or repeated knots where " +
                 "the range starts?)";
        return false;
      }
      // pbrt-v3 normalizes the cross product of the partials. Where they are parallel (a
      // pole) it gets NaN, which its triangles treat as "no shading normal" for every triangle
      // touching the vertex; the archive holds no NaNs, so such a vertex gets a zero normal.
      V3 n = cross(dpdu, dpdv);
      float len = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
      float inv = 1.f / len;
      n = {n.x * inv, n.y * inv, n.z * inv};
      if (!finite(n)) n = {0, 0, 0};
      out->P[3 * i] = p.x, out->P[3 * i + 1] = p.y, out->P[3 * i + 2] = p.z;
      out->N[3 * i] = n.x, out->N[3 * i + 1] = n.y, out->N[3 * i + 2] = n.z;
      out->uv[2 * i] = ueval[size_t(u)], out->uv[2 * i + 1] = veval[size_t(v)];
    }
  }
  out->indices.clear();
  out->indices.reserve(size_t(6) * size_t(dice - 1) * size_t(dice - 1));
  auto vn = [](int u, int v) { return uint32_t(v * dice + u); };
  for (int v = 0; v < dice - 1; ++v) {
    for (int u = 0; u < dice - 1; ++u) {
      out->indices.insert(out->indices.end(), {vn(u, v), vn(u + 1, v), vn(u + 1, v + 1)});
      out->indices.insert(out->indices.end(), {vn(u, v), vn(u + 1, v + 1), vn(u, v + 1)});
    }
  }
  out->refine_level = uint32_t(dice);
  return true;
}

// ---- Heightfield -----------------------------------------------------------------------------

bool refine_heightfield(const Entity& shape, TriangleMesh* out, std::string* error) {
  int nx = shape.get_int("nu"), ny = shape.get_int("nv");
  if (nx < 2 || ny < 2) {
    // pbrt-v3 divides by nu - 1 and nv - 1.
    *error =
        "heightfield needs at least 2 x 2 points; \"nu\" is " + str(nx) + " and \"nv\" " + str(ny);
    return false;
  }
  uint64_t nverts = uint64_t(nx) * uint64_t(ny);
  uint32_t count = 0;
  const float* z = shape.get_floats("Pz", &count);
  if (count != nverts) {
    *error = "heightfield \"float Pz\" has " + str(uint64_t(count)) +
             " heights; nu * nv = " + str(nverts);
    return false;
  }
  out->P.resize(3 * nverts);
  out->uv.resize(2 * nverts);
  size_t i = 0;
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x, ++i) {
      float fx = float(x) / float(nx - 1), fy = float(y) / float(ny - 1);
      out->P[3 * i] = out->uv[2 * i] = fx;
      out->P[3 * i + 1] = out->uv[2 * i + 1] = fy;
      out->P[3 * i + 2] = z[i];
    }
  }
  out->indices.clear();
  out->indices.reserve(6 * size_t(nx - 1) * size_t(ny - 1));
  auto vert = [nx](int x, int y) { return uint32_t(x + y * nx); };
  for (int y = 0; y < ny - 1; ++y) {
    for (int x = 0; x < nx - 1; ++x) {
      out->indices.insert(out->indices.end(), {vert(x, y), vert(x + 1, y), vert(x + 1, y + 1)});
      out->indices.insert(out->indices.end(), {vert(x, y), vert(x + 1, y + 1), vert(x, y + 1)});
    }
  }
  out->refine_level = 0;
  return true;
}

// ---- Dispatch --------------------------------------------------------------------------------

bool is_refined_shape(std::string_view type) {
  return type == "loopsubdiv" || type == "nurbs" || type == "heightfield";
}

bool refine_shape(const Entity& shape, TriangleMesh* out, std::string* error) {
  std::string_view t = shape.type_name();
  if (t == "loopsubdiv") return refine_loopsubdiv(shape, out, error);
  if (t == "nurbs") return refine_nurbs(shape, out, error);
  if (t == "heightfield") return refine_heightfield(shape, out, error);
  *error = "shape type \"" + std::string(t) + "\" is not refined into triangles";
  return false;
}

}  // namespace pbrtc
