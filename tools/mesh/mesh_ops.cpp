// tools/mesh/mesh_ops.cpp — vertex normals, quadric simplification, measured Hausdorff distance.
//
// Geometry is computed in double from the float positions: the float inputs are exact in double,
// so face normals, areas and point-triangle distances lose nothing to the storage type.
#include "tools/mesh/mesh_ops.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <random>
#include <unordered_map>
#include <utility>

namespace meshtools {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct V3 {
  double x = 0, y = 0, z = 0;
};
V3 operator+(V3 a, V3 b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
V3 operator-(V3 a, V3 b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
V3 operator*(V3 a, double s) {
  return {a.x * s, a.y * s, a.z * s};
}
double dot(V3 a, V3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
V3 cross(V3 a, V3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
double length(V3 a) {
  return std::sqrt(dot(a, a));
}

V3 position(const Mesh& mesh, size_t v) {
  const float* p = &mesh.positions[3 * v];
  return {p[0], p[1], p[2]};
}

// Hashable key of a vertex's exact float bits, with -0 folded into +0 so the two zeros weld.
struct BitsKey {
  std::array<uint32_t, 5> bits{};
  bool operator==(const BitsKey& o) const { return bits == o.bits; }
};
struct BitsKeyHash {
  size_t operator()(const BitsKey& k) const {
    uint64_t h = 1469598103934665603ull;
    for (uint32_t b : k.bits) h = (h ^ b) * 1099511628211ull;
    return static_cast<size_t>(h ^ (h >> 29));
  }
};
uint32_t float_bits(float f) {
  if (f == 0.0f) f = 0.0f;
  uint32_t b;
  std::memcpy(&b, &f, sizeof b);
  return b;
}

// Maps every vertex to the first vertex with the same position (and the same uv when with_uv),
// so copies made for seams count as one point. Returns the number of distinct points; point ids
// are dense, in first-appearance order.
size_t weld(const Mesh& mesh, bool with_uv, std::vector<uint32_t>* point_of) {
  const size_t n = mesh.num_vertices();
  const bool use_uv = with_uv && mesh.uvs.size() == 2 * n;
  std::unordered_map<BitsKey, uint32_t, BitsKeyHash> ids;
  ids.reserve(n);
  point_of->resize(n);
  for (size_t v = 0; v < n; ++v) {
    BitsKey key;
    for (int i = 0; i < 3; ++i) key.bits[i] = float_bits(mesh.positions[3 * v + i]);
    if (use_uv) {
      key.bits[3] = float_bits(mesh.uvs[2 * v]);
      key.bits[4] = float_bits(mesh.uvs[2 * v + 1]);
    }
    auto it = ids.emplace(key, static_cast<uint32_t>(ids.size())).first;
    (*point_of)[v] = it->second;
  }
  return ids.size();
}

// Face geometry for normals. A face is degenerate when its area is negligible against its longest
// edge squared (a corner angle under about 1e-6 rad): the normal of such a sliver is rounding
// noise, and under angle weighting its near-180-degree corner would count fully.
struct FaceGeometry {
  V3 unit_normal;
  double area = 0;
  std::array<double, 3> angle{};
  bool degenerate = true;
};

FaceGeometry face_geometry(const Mesh& mesh, size_t t) {
  FaceGeometry g;
  const uint32_t* idx = &mesh.indices[3 * t];
  const V3 p[3] = {position(mesh, idx[0]), position(mesh, idx[1]), position(mesh, idx[2])};
  const V3 c = cross(p[1] - p[0], p[2] - p[0]);
  const double len = length(c);
  double max_edge2 = 0;
  for (int k = 0; k < 3; ++k) {
    const V3 e = p[(k + 1) % 3] - p[k];
    max_edge2 = std::max(max_edge2, dot(e, e));
  }
  if (!(len > 1e-6 * max_edge2) || !std::isfinite(len)) return g;
  g.degenerate = false;
  g.unit_normal = c * (1.0 / len);
  g.area = 0.5 * len;
  for (int k = 0; k < 3; ++k) {
    const V3 e1 = p[(k + 1) % 3] - p[k], e2 = p[(k + 2) % 3] - p[k];
    g.angle[k] = std::atan2(length(cross(e1, e2)), dot(e1, e2));
  }
  return g;
}

// Union-find over the corners around one point.
struct DisjointSets {
  std::vector<uint32_t> parent;
  void reset(size_t n) {
    parent.resize(n);
    std::iota(parent.begin(), parent.end(), 0u);
  }
  uint32_t find(uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void unite(uint32_t a, uint32_t b) {
    a = find(a), b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

// The normal a vertex gets when no usable face touches it: its input normal if that was usable
// (so a normals pass over a mesh with some degenerate parts does not lose information), else +z.
V3 fallback_normal(const Mesh& mesh, size_t v) {
  if (mesh.normals.size() == 3 * mesh.num_vertices()) {
    const V3 n{mesh.normals[3 * v], mesh.normals[3 * v + 1], mesh.normals[3 * v + 2]};
    const double len = length(n);
    if (len > 0 && std::isfinite(len)) return n * (1.0 / len);
  }
  return {0, 0, 1};
}

// ---- Hausdorff: exact point-triangle distance and a BVH over the triangles ----

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5): classifies
// p against the Voronoi regions of the vertices, edges and face, so the answer is exact up to
// rounding and well defined for degenerate triangles too.
V3 closest_point_on_triangle(V3 p, V3 a, V3 b, V3 c) {
  const V3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const V3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double denom = d1 - d3;
    return denom > 0 ? a + ab * (d1 / denom) : a;
  }
  const V3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double denom = d2 - d6;
    return denom > 0 ? a + ac * (d2 / denom) : a;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double denom = (d4 - d3) + (d5 - d6);
    return denom > 0 ? b + (c - b) * ((d4 - d3) / denom) : b;
  }
  const double sum = va + vb + vc;
  if (!(sum > 0)) {
    // Degenerate triangle that fell through the region tests: its closest point is on an edge.
    V3 best = a;
    double best_d = dot(p - a, p - a);
    const V3 ends[3][2] = {{a, b}, {b, c}, {c, a}};
    for (const auto& e : ends) {
      const V3 d = e[1] - e[0];
      const double dd = dot(d, d);
      const double t = dd > 0 ? std::clamp(dot(p - e[0], d) / dd, 0.0, 1.0) : 0.0;
      const V3 q = e[0] + d * t;
      const double dq = dot(p - q, p - q);
      if (dq < best_d) best_d = dq, best = q;
    }
    return best;
  }
  const double denom = 1.0 / sum;
  return a + ab * (vb * denom) + ac * (vc * denom);
}

struct Box {
  V3 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
        std::numeric_limits<double>::infinity()};
  V3 hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
        -std::numeric_limits<double>::infinity()};
  void grow(V3 p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  void grow(const Box& b) { grow(b.lo), grow(b.hi); }
  double distance2(V3 p) const {
    const double dx = std::max({lo.x - p.x, 0.0, p.x - hi.x});
    const double dy = std::max({lo.y - p.y, 0.0, p.y - hi.y});
    const double dz = std::max({lo.z - p.z, 0.0, p.z - hi.z});
    return dx * dx + dy * dy + dz * dz;
  }
};

// A binary BVH split at the median centroid of the longest axis: simple, O(n log n) to build and
// logarithmic per closest-point query on well-spread meshes, which is all the sampler needs.
class TriangleBvh {
 public:
  explicit TriangleBvh(const Mesh& mesh) : mesh_(mesh) {
    const size_t n = mesh.num_triangles();
    tris_.resize(n);
    std::iota(tris_.begin(), tris_.end(), 0u);
    centroids_.resize(n);
    boxes_.resize(n);
    for (size_t t = 0; t < n; ++t) {
      for (int k = 0; k < 3; ++k) boxes_[t].grow(corner(t, k));
      centroids_[t] = (corner(t, 0) + corner(t, 1) + corner(t, 2)) * (1.0 / 3.0);
    }
    if (n > 0) {
      nodes_.emplace_back();
      build(0, 0, n);
    }
  }

  // Squared distance from p to the nearest triangle; infinity for an empty mesh.
  double distance2(V3 p) const {
    double best = std::numeric_limits<double>::infinity();
    if (nodes_.empty()) return best;
    uint32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (node.box.distance2(p) >= best) continue;
      if (node.count > 0) {
        for (uint32_t i = node.first; i < node.first + node.count; ++i) {
          const uint32_t t = tris_[i];
          const V3 q = closest_point_on_triangle(p, corner(t, 0), corner(t, 1), corner(t, 2));
          best = std::min(best, dot(p - q, p - q));
        }
        continue;
      }
      // Visit the nearer child first (pushed last) so best shrinks early and prunes more.
      const uint32_t l = node.first, r = node.first + 1;
      const double dl = nodes_[l].box.distance2(p), dr = nodes_[r].box.distance2(p);
      if (dl < dr) {
        if (dr < best) stack[top++] = r;
        if (dl < best) stack[top++] = l;
      } else {
        if (dl < best) stack[top++] = l;
        if (dr < best) stack[top++] = r;
      }
    }
    return best;
  }

 private:
  struct Node {
    Box box;
    uint32_t first = 0;  // leaf: first index into tris_; inner: index of the left child
    uint32_t count = 0;  // leaf: number of triangles; inner: 0
  };

  V3 corner(size_t t, int k) const { return position(mesh_, mesh_.indices[3 * t + k]); }

  // Fills node `index` with the subtree over tris_[begin, end). The two children of an inner node
  // are allocated together, so the right child is left + 1. Median splits bound the depth by
  // log2(n) + 1, well inside the query stack.
  void build(uint32_t index, size_t begin, size_t end) {
    Box box, centroid_box;
    for (size_t i = begin; i < end; ++i) {
      box.grow(boxes_[tris_[i]]);
      centroid_box.grow(centroids_[tris_[i]]);
    }
    nodes_[index].box = box;
    if (end - begin <= 4) {
      nodes_[index].first = static_cast<uint32_t>(begin);
      nodes_[index].count = static_cast<uint32_t>(end - begin);
      return;
    }
    const V3 extent = centroid_box.hi - centroid_box.lo;
    const int axis =
        extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    auto key = [&](uint32_t t) {
      const V3& c = centroids_[t];
      return axis == 0 ? c.x : axis == 1 ? c.y : c.z;
    };
    const size_t mid = begin + (end - begin) / 2;
    std::nth_element(tris_.begin() + begin, tris_.begin() + mid, tris_.begin() + end,
                     [&](uint32_t a, uint32_t b) { return key(a) < key(b); });
    const uint32_t left = static_cast<uint32_t>(nodes_.size());
    nodes_.emplace_back();
    nodes_.emplace_back();
    nodes_[index].first = left;
    build(left, begin, mid);
    build(left + 1, mid, end);
  }

  const Mesh& mesh_;
  std::vector<uint32_t> tris_;
  std::vector<V3> centroids_;
  std::vector<Box> boxes_;
  std::vector<Node> nodes_;
};

// Uniform double in [0, 1) from the top 53 bits: std::uniform_real_distribution is not specified
// bit for bit across standard libraries, mt19937_64 is, so the samples are the same everywhere.
double unit_random(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

// Squared distances from the samples of `from` (used vertices plus area-weighted uniform points)
// to the surface of `to`, accumulated into max and sum.
void directed_distances(const Mesh& from, const TriangleBvh& to, const HausdorffOptions& options,
                        uint64_t seed, double* max2, double* sum2, size_t* count) {
  const size_t nt = from.num_triangles();
  std::vector<char> used(from.num_vertices(), 0);
  for (uint32_t i : from.indices) used[i] = 1;
  auto visit = [&](V3 p) {
    const double d2 = to.distance2(p);
    *max2 = std::max(*max2, d2);
    *sum2 += d2;
    ++*count;
  };
  for (size_t v = 0; v < used.size(); ++v) {
    if (used[v]) visit(position(from, v));
  }
  std::vector<double> cumulative(nt);
  double total = 0;
  for (size_t t = 0; t < nt; ++t) {
    const V3 a = position(from, from.indices[3 * t]), b = position(from, from.indices[3 * t + 1]),
             c = position(from, from.indices[3 * t + 2]);
    total += 0.5 * length(cross(b - a, c - a));
    cumulative[t] = total;
  }
  if (!(total > 0)) return;  // only degenerate faces: the vertices already cover the surface
  std::mt19937_64 rng(seed);
  for (size_t s = 0; s < options.samples; ++s) {
    const double pick = unit_random(rng) * total;
    size_t t = static_cast<size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), pick) -
                                   cumulative.begin());
    t = std::min(t, nt - 1);
    // Uniform on the triangle: the square root folds the unit square onto it without bias.
    const double r1 = std::sqrt(unit_random(rng)), r2 = unit_random(rng);
    const V3 a = position(from, from.indices[3 * t]), b = position(from, from.indices[3 * t + 1]),
             c = position(from, from.indices[3 * t + 2]);
    visit(a * (1 - r1) + b * (r1 * (1 - r2)) + c * (r1 * r2));
  }
}

// ---- OpenMesh ----

struct DecimationTraits : public OpenMesh::DefaultTraits {
  // Double points: the input floats are exact in double and quadrics are evaluated in double.
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
  VertexAttributes(OpenMesh::Attributes::Status);
  EdgeAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::Normal);
  HalfedgeAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::PrevHalfedge);
};
using DecimationMesh = OpenMesh::TriMesh_ArrayKernelT<DecimationTraits>;

// OpenMesh's quadrics only see the faces, so along an open boundary of a flat region every
// collapse costs nothing and the border erodes (a flat grid lost 38% of its width in a test).
// This binary module lets a boundary vertex go only where the border is nearly straight: the
// boundary turns there by at most max_turn. Vertices never move in a halfedge collapse, so the
// simplified border is always a polyline through input border vertices.
template <class MeshT>
class ModBoundaryT : public OpenMesh::Decimater::ModBaseT<MeshT> {
 public:
  DECIMATING_MODULE(ModBoundaryT, MeshT, Boundary);

  explicit ModBoundaryT(MeshT& mesh) : Base(mesh, true) {}

  void set_max_turn_degrees(double degrees) { cos_max_turn_ = std::cos(degrees * kPi / 180.0); }

  float collapse_priority(const CollapseInfo& ci) override {
    const MeshT& mesh = Base::mesh();
    if (!mesh.is_boundary(ci.v0)) return Base::LEGAL_COLLAPSE;
    // The base decimater only lets a border vertex collapse along a border edge, so v1 is one of
    // v0's two border neighbours.
    const auto out = mesh.halfedge_handle(ci.v0);
    if (!mesh.is_boundary(out)) return Base::ILLEGAL_COLLAPSE;
    const auto next = mesh.to_vertex_handle(out);
    const auto prev = mesh.from_vertex_handle(mesh.prev_halfedge_handle(out));
    if (next != ci.v1 && prev != ci.v1) return Base::ILLEGAL_COLLAPSE;  // non-manifold border
    const auto a = mesh.point(ci.v0) - mesh.point(prev);
    const auto b = mesh.point(next) - mesh.point(ci.v0);
    const double la = a.norm(), lb = b.norm();
    if (!(la > 0) || !(lb > 0)) return Base::LEGAL_COLLAPSE;  // zero-length border edge
    return (a | b) >= cos_max_turn_ * la * lb ? float(Base::LEGAL_COLLAPSE)
                                              : float(Base::ILLEGAL_COLLAPSE);
  }

 private:
  double cos_max_turn_ = std::cos(15.0 * kPi / 180.0);
};

// Builds the OpenMesh mesh, with vertices welded by (position, uv) when weld is set. Returns the
// number of faces OpenMesh refused; counts faces with a repeated vertex in *degenerate.
size_t build_openmesh(const Mesh& mesh, bool weld_vertices, DecimationMesh* om,
                      OpenMesh::FPropHandleT<int32_t> face_index, size_t* degenerate) {
  const bool has_uv = mesh.uvs.size() == 2 * mesh.num_vertices();
  std::vector<uint32_t> id_of(mesh.num_vertices());
  size_t num_ids = mesh.num_vertices();
  if (weld_vertices) {
    num_ids = weld(mesh, /*with_uv=*/true, &id_of);
  } else {
    std::iota(id_of.begin(), id_of.end(), 0u);
  }
  if (has_uv) om->request_vertex_texcoords2D();
  std::vector<DecimationMesh::VertexHandle> handles(num_ids);
  std::vector<char> made(num_ids, 0);
  for (size_t v = 0; v < mesh.num_vertices(); ++v) {
    const uint32_t id = id_of[v];
    if (made[id]) continue;
    made[id] = 1;
    handles[id] = om->add_vertex(DecimationMesh::Point(
        mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]));
    if (has_uv) {
      om->set_texcoord2D(handles[id],
                         DecimationMesh::TexCoord2D(mesh.uvs[2 * v], mesh.uvs[2 * v + 1]));
    }
  }
  size_t rejected = 0;
  *degenerate = 0;
  const bool has_face_indices = mesh.face_indices.size() == mesh.num_triangles();
  for (size_t t = 0; t < mesh.num_triangles(); ++t) {
    const uint32_t a = id_of[mesh.indices[3 * t]], b = id_of[mesh.indices[3 * t + 1]],
                   c = id_of[mesh.indices[3 * t + 2]];
    if (a == b || b == c || c == a) {
      ++*degenerate;
      continue;
    }
    const auto f = om->add_face(handles[a], handles[b], handles[c]);
    if (!f.is_valid()) {
      ++rejected;
      continue;
    }
    om->property(face_index, f) = has_face_indices ? mesh.face_indices[t] : 0;
  }
  return rejected;
}

}  // namespace

double bbox_diagonal(const Mesh& mesh) {
  if (mesh.num_vertices() == 0) return 0;
  Box box;
  for (size_t v = 0; v < mesh.num_vertices(); ++v) box.grow(position(mesh, v));
  return length(box.hi - box.lo);
}

void compute_normals(Mesh* mesh, const NormalsOptions& options,
                     std::vector<uint32_t>* source_vertex) {
  const size_t nv = mesh->num_vertices(), nt = mesh->num_triangles();
  std::vector<uint32_t> point_of;
  const size_t np = weld(*mesh, /*with_uv=*/false, &point_of);

  std::vector<FaceGeometry> faces(nt);
  for (size_t t = 0; t < nt; ++t) faces[t] = face_geometry(*mesh, t);

  // Corners grouped by point (CSR), so each point's fan is processed on its own.
  std::vector<uint32_t> start(np + 1, 0), corners(3 * nt);
  for (size_t c = 0; c < 3 * nt; ++c) ++start[point_of[mesh->indices[c]] + 1];
  for (size_t p = 0; p < np; ++p) start[p + 1] += start[p];
  {
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (size_t c = 0; c < 3 * nt; ++c) corners[fill[point_of[mesh->indices[c]]]++] = c;
  }

  const bool split = options.crease_angle_degrees < 180.0;
  const double cos_crease = std::cos(std::max(0.0, options.crease_angle_degrees) * kPi / 180.0);
  auto weight = [&](uint32_t c) {
    const FaceGeometry& f = faces[c / 3];
    return options.weighting == NormalWeighting::kArea ? f.area : f.angle[c % 3];
  };

  // Output: vertex v keeps its slot for the first group it appears in; further groups of the same
  // vertex become copies appended at the end.
  std::vector<float> normals(3 * nv, 0.0f);
  std::vector<char> assigned(nv, 0);
  std::vector<uint32_t> source(nv);
  std::iota(source.begin(), source.end(), 0u);
  std::vector<uint32_t> new_indices = mesh->indices;
  size_t next_vertex = nv;

  DisjointSets sets;
  std::vector<std::pair<uint32_t, uint32_t>> edge_ends;  // (other point, local corner)
  std::vector<V3> group_sum;
  std::vector<double> group_best_weight;
  std::vector<V3> group_best_normal;
  std::vector<std::pair<uint64_t, uint32_t>> vertex_of_group;  // (vertex << 32 | group, output)
  for (size_t p = 0; p < np; ++p) {
    const uint32_t* fan = &corners[start[p]];
    const size_t k = start[p + 1] - start[p];
    if (k == 0) continue;
    sets.reset(k);
    // Corners meeting across an edge (the same other point) are one group unless the crease
    // separates them; without a crease the whole fan is one group.
    edge_ends.clear();
    for (uint32_t i = 0; i < k; ++i) {
      const uint32_t t = fan[i] / 3, j = fan[i] % 3;
      edge_ends.push_back({point_of[mesh->indices[3 * t + (j + 1) % 3]], i});
      edge_ends.push_back({point_of[mesh->indices[3 * t + (j + 2) % 3]], i});
    }
    std::sort(edge_ends.begin(), edge_ends.end());
    uint32_t first_solid = UINT32_MAX;
    for (uint32_t i = 0; i < k; ++i) {
      if (!faces[fan[i] / 3].degenerate) {
        if (first_solid == UINT32_MAX) first_solid = i;
        if (!split) sets.unite(first_solid, i);
      }
    }
    for (size_t b = 0, e; b < edge_ends.size(); b = e) {
      for (e = b + 1; e < edge_ends.size() && edge_ends[e].first == edge_ends[b].first;) ++e;
      for (size_t x = b; x < e; ++x) {
        const uint32_t i = edge_ends[x].second;
        const FaceGeometry& fi = faces[fan[i] / 3];
        if (fi.degenerate || !split) continue;
        for (size_t y = x + 1; y < e; ++y) {
          const uint32_t j = edge_ends[y].second;
          const FaceGeometry& fj = faces[fan[j] / 3];
          if (!fj.degenerate && dot(fi.unit_normal, fj.unit_normal) >= cos_crease - 1e-12) {
            sets.unite(i, j);
          }
        }
      }
    }
    // A degenerate face has no normal of its own: its corner joins a solid neighbour across an
    // edge, or the first solid group, so it never creates a vertex with a made-up normal.
    std::vector<uint32_t> group(k);
    for (uint32_t i = 0; i < k; ++i) group[i] = sets.find(i);
    for (size_t b = 0, e; b < edge_ends.size(); b = e) {
      for (e = b + 1; e < edge_ends.size() && edge_ends[e].first == edge_ends[b].first;) ++e;
      uint32_t solid = UINT32_MAX;
      for (size_t x = b; x < e; ++x) {
        if (!faces[fan[edge_ends[x].second] / 3].degenerate) solid = edge_ends[x].second;
      }
      if (solid == UINT32_MAX) continue;
      for (size_t x = b; x < e; ++x) {
        const uint32_t i = edge_ends[x].second;
        if (faces[fan[i] / 3].degenerate && group[i] == i) group[i] = sets.find(solid);
      }
    }
    for (uint32_t i = 0; i < k; ++i) {
      if (faces[fan[i] / 3].degenerate && group[i] == i && first_solid != UINT32_MAX) {
        group[i] = sets.find(first_solid);
      }
    }
    group_sum.assign(k, V3{});
    group_best_weight.assign(k, -1.0);
    group_best_normal.assign(k, V3{});
    for (uint32_t i = 0; i < k; ++i) {
      const FaceGeometry& f = faces[fan[i] / 3];
      if (f.degenerate) continue;
      const double w = weight(fan[i]);
      group_sum[group[i]] = group_sum[group[i]] + f.unit_normal * w;
      if (w > group_best_weight[group[i]]) {
        group_best_weight[group[i]] = w;
        group_best_normal[group[i]] = f.unit_normal;
      }
    }
    vertex_of_group.clear();
    for (uint32_t i = 0; i < k; ++i) {
      const uint32_t c = fan[i], v = mesh->indices[c], g = group[i];
      const uint64_t key = (static_cast<uint64_t>(v) << 32) | g;
      auto it = std::find_if(vertex_of_group.begin(), vertex_of_group.end(),
                             [&](const auto& e) { return e.first == key; });
      uint32_t out;
      if (it != vertex_of_group.end()) {
        out = it->second;
      } else {
        if (!assigned[v]) {
          assigned[v] = 1;
          out = v;
        } else {
          out = static_cast<uint32_t>(next_vertex++);
          source.push_back(v);
          normals.resize(3 * next_vertex);
        }
        vertex_of_group.push_back({key, out});
        // The sum can cancel (faces folded back onto each other); then the heaviest face's
        // normal, and with no solid face at all, the fallback.
        V3 n = group_sum[g];
        double len = length(n);
        if (!(len > 1e-12 * std::max(1e-300, group_best_weight[g]))) {
          n = group_best_weight[g] > 0 ? group_best_normal[g] : fallback_normal(*mesh, v);
          len = length(n);
        }
        n = n * (1.0 / len);
        normals[3 * out] = static_cast<float>(n.x);
        normals[3 * out + 1] = static_cast<float>(n.y);
        normals[3 * out + 2] = static_cast<float>(n.z);
      }
      new_indices[c] = out;
    }
  }
  // Vertices no triangle uses.
  for (size_t v = 0; v < nv; ++v) {
    if (assigned[v]) continue;
    const V3 n = fallback_normal(*mesh, v);
    normals[3 * v] = static_cast<float>(n.x);
    normals[3 * v + 1] = static_cast<float>(n.y);
    normals[3 * v + 2] = static_cast<float>(n.z);
  }
  if (next_vertex > nv) {
    mesh->positions.resize(3 * next_vertex);
    const bool has_uv = mesh->uvs.size() == 2 * nv;
    if (has_uv) mesh->uvs.resize(2 * next_vertex);
    for (size_t v = nv; v < next_vertex; ++v) {
      for (int i = 0; i < 3; ++i) mesh->positions[3 * v + i] = mesh->positions[3 * source[v] + i];
      if (has_uv) {
        for (int i = 0; i < 2; ++i) mesh->uvs[2 * v + i] = mesh->uvs[2 * source[v] + i];
      }
    }
  }
  mesh->normals = std::move(normals);
  mesh->indices = std::move(new_indices);
  if (source_vertex) *source_vertex = std::move(source);
}

HausdorffResult hausdorff_distance(const Mesh& a, const Mesh& b, const HausdorffOptions& options) {
  HausdorffResult result;
  const bool a_empty = a.num_triangles() == 0, b_empty = b.num_triangles() == 0;
  if (a_empty || b_empty) {
    const double d = a_empty && b_empty ? 0.0 : std::numeric_limits<double>::infinity();
    result.max = result.rms = result.max_a_to_b = result.max_b_to_a = d;
    return result;
  }
  const TriangleBvh bvh_a(a), bvh_b(b);
  double max_ab = 0, max_ba = 0, sum = 0;
  size_t count = 0;
  // Different seeds per direction so the two sample sets are independent even for equal meshes.
  directed_distances(a, bvh_b, options, options.seed, &max_ab, &sum, &count);
  directed_distances(b, bvh_a, options, options.seed ^ 0x9e3779b97f4a7c15ull, &max_ba, &sum,
                     &count);
  result.max_a_to_b = std::sqrt(max_ab);
  result.max_b_to_a = std::sqrt(max_ba);
  result.max = std::max(result.max_a_to_b, result.max_b_to_a);
  result.rms = count > 0 ? std::sqrt(sum / static_cast<double>(count)) : 0.0;
  result.samples = count;
  return result;
}

bool simplify(const Mesh& mesh, const SimplifyOptions& options, Mesh* out, SimplifyReport* report,
              std::string* error) {
  if (!(options.ratio > 0.0 && options.ratio <= 1.0)) {
    *error = "ratio must be in (0, 1], got " + std::to_string(options.ratio);
    return false;
  }
  if (options.max_quadric_error && !(*options.max_quadric_error >= 0.0)) {
    *error = "max quadric error must be >= 0";
    return false;
  }
  SimplifyReport r;
  r.faces_before = mesh.num_triangles();
  r.vertices_before = mesh.num_vertices();
  r.bbox_diagonal = bbox_diagonal(mesh);

  // Vertices are welded by position (and uv) first: exporters split vertices along normal and uv
  // seams, and an unwelded mesh would fall apart into patches whose borders the decimater cannot
  // move. If welding itself makes the mesh non-manifold (two parts touching at a point), build it
  // again as given before giving up.
  DecimationMesh om;
  OpenMesh::FPropHandleT<int32_t> face_index;
  om.add_property(face_index);
  size_t rejected =
      build_openmesh(mesh, /*weld_vertices=*/true, &om, face_index, &r.degenerate_faces_dropped);
  if (rejected > 0) {
    const size_t welded_rejected = rejected;
    om = DecimationMesh();
    om.add_property(face_index);
    rejected =
        build_openmesh(mesh, /*weld_vertices=*/false, &om, face_index, &r.degenerate_faces_dropped);
    if (rejected > 0) {
      *error = std::to_string(std::min(rejected, welded_rejected)) + " of " +
               std::to_string(mesh.num_triangles()) +
               " faces could not be added to the halfedge mesh (non-manifold edge or vertex, "
               "or inconsistent orientation); simplification needs a manifold mesh";
      return false;
    }
  }

  // Vertices that still share a position with another vertex sit on a uv seam (or where parts
  // touch). Collapsing them would move one side of the seam and not the other and open a crack,
  // so they stay where they are.
  {
    std::unordered_map<BitsKey, uint32_t, BitsKeyHash> count;
    auto key_of = [&](DecimationMesh::VertexHandle v) {
      BitsKey k;
      const auto& p = om.point(v);
      for (int i = 0; i < 3; ++i) k.bits[i] = float_bits(static_cast<float>(p[i]));
      return k;
    };
    for (auto v : om.vertices()) ++count[key_of(v)];
    for (auto v : om.vertices()) {
      if (count[key_of(v)] > 1) {
        om.status(v).set_locked(true);
        ++r.locked_vertices;
      }
    }
  }

  om.update_face_normals();  // ModNormalFlippingT compares against the current face normals
  using Decimater = OpenMesh::Decimater::DecimaterT<DecimationMesh>;
  Decimater decimater(om);
  OpenMesh::Decimater::ModQuadricT<DecimationMesh>::Handle quadric;
  decimater.add(quadric);
  if (options.max_quadric_error) {
    // Non-binary: the quadric stays the priority and the bound only refuses collapses.
    decimater.module(quadric).set_max_err(*options.max_quadric_error, false);
  }
  OpenMesh::Decimater::ModNormalFlippingT<DecimationMesh>::Handle flipping;
  if (options.prevent_normal_flips) decimater.add(flipping);
  ModBoundaryT<DecimationMesh>::Handle boundary;
  decimater.add(boundary);
  decimater.module(boundary).set_max_turn_degrees(options.boundary_max_turn_degrees);
  if (!decimater.initialize()) {
    *error = "OpenMesh decimater failed to initialize";
    return false;
  }
  const size_t target = std::max<size_t>(
      1, static_cast<size_t>(std::llround(options.ratio * static_cast<double>(om.n_faces()))));
  if (target < om.n_faces()) decimater.decimate_to_faces(0, target);
  om.garbage_collection();

  Mesh result;
  const bool has_uv = mesh.uvs.size() == 2 * mesh.num_vertices();
  result.positions.reserve(3 * om.n_vertices());
  for (auto v : om.vertices()) {
    const auto& p = om.point(v);
    for (int i = 0; i < 3; ++i) result.positions.push_back(static_cast<float>(p[i]));
    if (has_uv) {
      // A halfedge collapse removes one vertex and keeps the other untouched, so this uv is an
      // input uv of an input vertex at its input position.
      const auto& uv = om.texcoord2D(v);
      result.uvs.push_back(uv[0]);
      result.uvs.push_back(uv[1]);
    }
  }
  const bool has_face_indices = mesh.face_indices.size() == mesh.num_triangles();
  for (auto f : om.faces()) {
    for (auto v : om.fv_range(f)) result.indices.push_back(static_cast<uint32_t>(v.idx()));
    if (has_face_indices) result.face_indices.push_back(om.property(face_index, f));
  }
  // Input normals belonged to the input's surface, and welding merged vertices whose normals
  // differed, so there is nothing faithful to carry over: normals are recomputed instead.
  if (!mesh.normals.empty()) {
    compute_normals(&result, options.normals);
    r.normals_recomputed = true;
  }
  r.faces_after = result.num_triangles();
  r.vertices_after = result.num_vertices();
  if (options.measure) {
    r.hausdorff = hausdorff_distance(mesh, result, options.hausdorff);
    r.measured = true;
  }
  *out = std::move(result);
  if (report) *report = r;
  return true;
}

}  // namespace meshtools
