#include "compiler/ply_writer.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

namespace pbrtc {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "PLY output assumes a little-endian host");

bool write_ply(const std::string& path, const pbrta::MeshArrays& m, std::string* error) {
  std::string tmp = path + ".tmp-" + std::to_string(::getpid());
  FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) {
    *error = "cannot write '" + path + "': " + std::strerror(errno);
    return false;
  }
  std::string h = "ply\nformat binary_little_endian 1.0\ncomment written by pbrtc\n";
  h += "element vertex " + std::to_string(m.num_vertices) + "\n";
  h += "property float x\nproperty float y\nproperty float z\n";
  if (m.normals) h += "property float nx\nproperty float ny\nproperty float nz\n";
  if (m.uv) h += "property float u\nproperty float v\n";
  h += "element face " + std::to_string(m.num_triangles) + "\n";
  h += "property list uchar int vertex_indices\n";
  if (m.face_indices) h += "property int face_indices\n";
  h += "end_header\n";
  bool ok = std::fwrite(h.data(), 1, h.size(), f) == h.size();
  // Interleave per vertex and per face, in blocks to keep writes large.
  std::vector<uint8_t> buf;
  buf.reserve(1 << 20);
  auto flush = [&]() {
    if (!buf.empty()) ok = ok && std::fwrite(buf.data(), 1, buf.size(), f) == buf.size();
    buf.clear();
  };
  auto put = [&](const void* p, size_t n) {
    const uint8_t* b = static_cast<const uint8_t*>(p);
    buf.insert(buf.end(), b, b + n);
    if (buf.size() >= (1 << 20)) flush();
  };
  for (uint64_t i = 0; i < m.num_vertices && ok; ++i) {
    put(m.positions + 3 * i, 12);
    if (m.normals) put(m.normals + 3 * i, 12);
    if (m.uv) put(m.uv + 2 * i, 8);
  }
  for (uint64_t t = 0; t < m.num_triangles && ok; ++t) {
    uint8_t three = 3;
    put(&three, 1);
    put(m.indices + 3 * t, 12);
    if (m.face_indices) put(m.face_indices + t, 4);
  }
  flush();
  ok = std::fflush(f) == 0 && ok;
  int saved = errno;
  ok = std::fclose(f) == 0 && ok;
  if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0) {
    *error = "cannot write '" + path + "': " + std::strerror(ok ? errno : saved);
    std::remove(tmp.c_str());
    return false;
  }
  return true;
}

}  // namespace pbrtc
