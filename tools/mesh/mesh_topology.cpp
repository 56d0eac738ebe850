// tools/mesh/mesh_topology.cpp — edge, fan, loop, degenerate and duplicate counts.
//
// One pass builds an edge table (undirected key -> face count and how many faces traverse it
// from its lower to its higher vertex); boundary loops are components of the boundary edges
// (union-find over their vertices); fans are components of each vertex's faces, linked when
// two of them share an edge through that vertex.
#include "tools/mesh/mesh_topology.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace meshtools {
namespace {

struct EdgeUse {
  uint32_t faces = 0;
  uint32_t forward = 0;  // faces that go from the lower index to the higher
};

uint64_t edge_key(uint32_t a, uint32_t b) {
  return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a;
}

class UnionFind {
 public:
  explicit UnionFind(size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  size_t find(size_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  bool unite(size_t a, size_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    parent_[a] = b;
    return true;
  }

 private:
  std::vector<size_t> parent_;
};

bool repeats_index(const uint32_t* f) {
  return f[0] == f[1] || f[1] == f[2] || f[0] == f[2];
}

bool zero_area(const Mesh& m, const uint32_t* f) {
  const float* p[3];
  for (int k = 0; k < 3; ++k) p[k] = &m.positions[3 * size_t(f[k])];
  const double e1[3] = {double(p[1][0]) - p[0][0], double(p[1][1]) - p[0][1],
                        double(p[1][2]) - p[0][2]};
  const double e2[3] = {double(p[2][0]) - p[0][0], double(p[2][1]) - p[0][1],
                        double(p[2][2]) - p[0][2]};
  const double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                       e1[0] * e2[1] - e1[1] * e2[0]};
  return c[0] == 0 && c[1] == 0 && c[2] == 0;
}

struct TripleHash {
  size_t operator()(const std::array<uint32_t, 3>& t) const {
    return (uint64_t(t[0]) * 0x9E3779B97F4A7C15ull) ^ (uint64_t(t[1]) * 0xC2B2AE3D27D4EB4Full) ^
           t[2];
  }
};

}  // namespace

TopologyCounts count_topology(const Mesh& m) {
  TopologyCounts c;
  const size_t nv = m.num_vertices(), nf = m.num_triangles();
  std::vector<bool> proper(nf);  // three distinct indices
  std::unordered_map<uint64_t, EdgeUse> edges;
  edges.reserve(nf * 3 / 2 + 1);
  std::unordered_set<std::array<uint32_t, 3>, TripleHash> seen;
  seen.reserve(nf);
  std::vector<bool> referenced(nv);
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t* t = &m.indices[3 * f];
    for (int k = 0; k < 3; ++k) referenced[t[k]] = true;
    std::array<uint32_t, 3> sorted = {t[0], t[1], t[2]};
    std::sort(sorted.begin(), sorted.end());
    if (!seen.insert(sorted).second) ++c.duplicate_faces;
    proper[f] = !repeats_index(t);
    if (!proper[f] || zero_area(m, t)) ++c.degenerate_faces;
    if (!proper[f]) continue;
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = t[k], b = t[(k + 1) % 3];
      EdgeUse& e = edges[edge_key(a, b)];
      ++e.faces;
      if (a < b) ++e.forward;
    }
  }
  for (size_t v = 0; v < nv; ++v)
    if (!referenced[v]) ++c.unreferenced_vertices;

  c.edges = edges.size();
  UnionFind loops(nv);
  std::vector<bool> on_boundary(nv);
  for (const auto& [key, e] : edges) {
    if (e.faces == 1) {
      ++c.boundary_edges;
      const uint32_t a = uint32_t(key >> 32), b = uint32_t(key);
      on_boundary[a] = on_boundary[b] = true;
      loops.unite(a, b);
    } else if (e.faces > 2 || e.forward != 1) {
      // Two faces on an edge must traverse it in opposite directions; forward is then 1.
      ++c.non_manifold_edges;
    }
  }
  for (size_t v = 0; v < nv; ++v)
    if (on_boundary[v] && loops.find(v) == v) ++c.boundary_loops;

  // Fans: per vertex, its faces (CSR), linked when they share the vertex's other endpoint.
  std::vector<uint32_t> start(nv + 1, 0);
  for (size_t f = 0; f < nf; ++f)
    if (proper[f])
      for (int k = 0; k < 3; ++k) ++start[m.indices[3 * f + size_t(k)] + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<uint32_t> incident(start[nv]);
  std::vector<uint32_t> fill(start.begin(), start.end() - 1);
  for (size_t f = 0; f < nf; ++f)
    if (proper[f])
      for (int k = 0; k < 3; ++k) incident[fill[m.indices[3 * f + size_t(k)]]++] = uint32_t(f);
  std::vector<std::pair<uint32_t, uint32_t>> spokes;  // (other vertex, local face number)
  for (size_t v = 0; v < nv; ++v) {
    const uint32_t n = start[v + 1] - start[v];
    if (n < 2) continue;
    spokes.clear();
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t* t = &m.indices[3 * size_t(incident[start[v] + i])];
      for (int k = 0; k < 3; ++k)
        if (t[k] != v) spokes.push_back({t[k], i});
    }
    std::sort(spokes.begin(), spokes.end());
    UnionFind fans(n);
    size_t components = n;
    for (size_t i = 1; i < spokes.size(); ++i)
      if (spokes[i].first == spokes[i - 1].first &&
          fans.unite(spokes[i].second, spokes[i - 1].second))
        --components;
    if (components > 1) ++c.non_manifold_vertices;
  }
  return c;
}

}  // namespace meshtools
