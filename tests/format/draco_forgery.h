// tests/format/draco_forgery.h — a forged Draco stream for the tests of the budget Draco runs
// under (format/isolated_jobs.h): it passes every check made before Draco runs, yet keeps Draco
// busy for seconds. The forged field is the texture-coordinate predictor's count of orientation
// bits, an int32 read raw from the stream, one per vertex but the first two of a connected mesh
// with uv; Draco decodes that many bits whatever the stream holds (for 2^31 - 16 it works 6 s,
// then accepts the mesh). This Draco (1.5, Debian 12) writes it in the stream's last 64 bytes
// when uv is the last attribute: only the uv data's wrap transform follows it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "format/mesh_arrays.h"

namespace pbrta::test_forgery {

// A mesh whose stream carries the count: n x n quads over (n+1)^2 vertices at (x, y, (x*y) % 3)
// with uv (x/n, y/n), two triangles per quad. Connected, so the count is vertices - 2.
struct UvGrid {
  std::vector<float> P, uv;
  std::vector<uint32_t> indices;
  uint32_t num_vertices() const { return uint32_t(P.size() / 3); }
  MeshArrays view() const {
    MeshArrays a;
    a.positions = P.data();
    a.uv = uv.data();
    a.indices = indices.data();
    a.num_vertices = num_vertices();
    a.num_triangles = indices.size() / 3;
    return a;
  }
};

inline UvGrid uv_grid(uint32_t n) {
  UvGrid g;
  for (uint32_t y = 0; y <= n; ++y)
    for (uint32_t x = 0; x <= n; ++x) {
      g.P.insert(g.P.end(), {float(x), float(y), float((x * y) % 3)});
      g.uv.insert(g.uv.end(), {float(x) / float(n), float(y) / float(n)});
    }
  for (uint32_t y = 0; y < n; ++y)
    for (uint32_t x = 0; x < n; ++x) {
      const uint32_t a = y * (n + 1) + x;
      g.indices.insert(g.indices.end(), {a, a + 1, a + n + 2, a, a + n + 2, a + n + 1});
    }
  return g;
}

// Sets the count in the Draco stream at data (size bytes, of a mesh of num_vertices vertices
// with uv, no normals and no face indices) to 2^31 - 16. False, leaving the stream as it was,
// unless the count is found exactly once.
inline bool forge_orientation_count(uint8_t* data, size_t size, uint32_t num_vertices) {
  const int32_t count = int32_t(num_vertices) - 2;
  size_t found = 0, at = 0;
  for (size_t k = size < 64 ? 0 : size - 64; k + 4 <= size; ++k) {
    int32_t v;
    std::memcpy(&v, data + k, 4);
    if (v == count) {
      ++found;
      at = k;
    }
  }
  if (found != 1) return false;
  const int32_t forged = 0x7ffffff0;
  std::memcpy(data + at, &forged, 4);
  return true;
}

}  // namespace pbrta::test_forgery
