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

namespace pbrta::test_forgery {

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
