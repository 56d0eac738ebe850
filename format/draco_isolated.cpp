// format/draco_isolated.cpp — draco_decode_isolated (format/draco_codec.h): a .drc file from a
// user decoded in a budgeted child process (format/isolated_jobs.h), its mesh passed back as
// bytes and checked here as untrusted input.
#include <cstring>
#include <string>
#include <vector>

#include "format/draco_codec.h"
#include "format/isolated_jobs.h"

namespace pbrta {
namespace {

// The mesh as bytes: five uint64 element counts (positions, normals and uv as floats, indices,
// face indices), then the five arrays back to back.
constexpr size_t kCounts = 5;

template <typename T>
void append(std::vector<uint8_t>* out, const std::vector<T>& v) {
  const size_t at = out->size();
  out->resize(at + v.size() * sizeof(T));
  if (!v.empty()) std::memcpy(out->data() + at, v.data(), v.size() * sizeof(T));
}

void to_bytes(const DecodedMesh& m, std::vector<uint8_t>* out) {
  const uint64_t counts[kCounts] = {m.positions.size(), m.normals.size(), m.uv.size(),
                                    m.indices.size(), m.face_indices.size()};
  out->resize(sizeof counts);
  std::memcpy(out->data(), counts, sizeof counts);
  append(out, m.positions);
  append(out, m.normals);
  append(out, m.uv);
  append(out, m.indices);
  append(out, m.face_indices);
}

template <typename T>
void take(const uint8_t** at, uint64_t n, std::vector<T>* v) {
  v->resize(n);
  if (n > 0) std::memcpy(v->data(), *at, n * sizeof(T));
  *at += n * sizeof(T);
}

// What draco_decode guarantees of its result, checked again on bytes from the child.
bool from_bytes(const std::vector<uint8_t>& b, const DracoLimits& limits, DecodedMesh* m) {
  uint64_t c[kCounts];
  if (b.size() < sizeof c) return false;
  std::memcpy(c, b.data(), sizeof c);
  uint64_t words = 0;
  for (uint64_t n : c) {
    if (n > b.size() / 4) return false;  // so the sum cannot overflow
    words += n;
  }
  if (sizeof c + 4 * words != b.size()) return false;
  const uint64_t nv = c[0] / 3, nt = c[3] / 3;
  if (c[0] % 3 != 0 || (c[1] != 0 && c[1] != c[0]) || (c[2] != 0 && c[2] != 2 * nv) ||
      c[3] % 3 != 0 || (c[4] != 0 && c[4] != nt) || nv > limits.max_vertices ||
      nt > limits.max_triangles)
    return false;
  const uint8_t* at = b.data() + sizeof c;
  take(&at, c[0], &m->positions);
  take(&at, c[1], &m->normals);
  take(&at, c[2], &m->uv);
  take(&at, c[3], &m->indices);
  take(&at, c[4], &m->face_indices);
  std::string unused;  // the caller has one message for any malformed mesh
  return draco_check_mesh(m->view(), &unused);
}

}  // namespace

bool draco_decode_isolated(const uint8_t* data, size_t size, DecodedMesh* out, std::string* error) {
  *out = DecodedMesh{};
  std::vector<std::vector<uint8_t>> outputs;
  std::vector<std::string> errors;
  std::vector<char> by_job;
  run_isolated_blobs(
      {uint64_t(size)}, 1, IsolationBudget{},
      [&](size_t, std::vector<uint8_t>* bytes, std::string* why) {
        DecodedMesh m;
        if (!draco_decode(data, size, &m, why)) return false;
        to_bytes(m, bytes);
        return true;
      },
      &outputs, &errors, &by_job);
  if (!errors[0].empty()) {
    // draco_decode's messages say "draco:" already; the budget's do not.
    *error = by_job[0] ? errors[0] : "draco: " + errors[0];
    return false;
  }
  if (!from_bytes(outputs[0], draco_limits_for(size), out)) {
    *out = DecodedMesh{};
    *error = "draco: the decoder passed back a malformed mesh";
    return false;
  }
  return true;
}

}  // namespace pbrta
