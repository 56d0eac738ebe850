#include "format/draco_codec.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <unordered_map>

// Draco's headers are not warning-free under -Wall -Wextra; CMake includes them as SYSTEM.
#include <draco/attributes/attribute_quantization_transform.h>
#include <draco/attributes/geometry_attribute.h>
#include <draco/attributes/point_attribute.h>
#include <draco/compression/config/compression_shared.h>
#include <draco/compression/decode.h>
#include <draco/compression/expert_encode.h>
#include <draco/core/decoder_buffer.h>
#include <draco/core/encoder_buffer.h>
#include <draco/mesh/mesh.h>
#include <xxhash.h>

#include "format/archive_reader.h"

namespace pbrta {

namespace {

// Draco indexes points, faces and corners with int32/uint32: stay well inside that.
constexpr uint64_t kMaxDracoElements = uint64_t{1} << 30;
// A stream is at most this long (DecoderBuffer sizes are int64, but nothing we write comes near).
constexpr uint64_t kMaxStreamBytes = uint64_t{1} << 31;

uint64_t align16(uint64_t x) {
  return (x + 15) & ~uint64_t{15};
}

bool fail(std::string* error, std::string message) {
  *error = std::move(message);
  return false;
}

// Reads the little-endian fields and LEB128 varints of a Draco stream's header, as Draco's
// DecoderBuffer and DecodeVarint do, without trusting a single byte.
class Cursor {
 public:
  Cursor(const uint8_t* p, size_t n) : p_(p), end_(p + n) {}
  bool u8(uint32_t* v) {
    if (p_ == end_) return false;
    *v = *p_++;
    return true;
  }
  bool u16(uint32_t* v) {
    if (end_ - p_ < 2) return false;
    *v = uint32_t(p_[0]) | uint32_t(p_[1]) << 8;
    p_ += 2;
    return true;
  }
  // Draco's uint32 varint: at most 5 bytes, least significant group first. Values that do not
  // fit 32 bits (which Draco would truncate) are refused.
  bool varint(uint64_t* v) {
    uint64_t value = 0;
    for (int i = 0; i < 5; ++i) {
      uint32_t byte = 0;
      if (!u8(&byte)) return false;
      value |= uint64_t(byte & 0x7f) << (7 * i);
      if (!(byte & 0x80)) {
        *v = value;
        return value <= 0xffffffffu;
      }
    }
    return false;
  }

 private:
  const uint8_t* p_;
  const uint8_t* end_;
};

// Checks the header and the element counts of a mesh stream against limits before Draco sees
// it: Draco sizes its corner table and attribute buffers from these counts alone, so a few
// hostile bytes could otherwise ask for gigabytes. Only what this Draco version's mesh encoder
// writes is accepted: bitstream 2.2, no metadata.
bool check_header(const uint8_t* data, size_t size, const DracoLimits& limits, std::string* error) {
  auto bad = [&](const std::string& why) { return fail(error, "draco: " + why); };
  if (size < 5 || std::memcmp(data, "DRACO", 5) != 0) return bad("not a Draco stream");
  Cursor c(data + 5, size - 5);
  uint32_t major = 0, minor = 0, type = 0, method = 0, flags = 0;
  if (!c.u8(&major) || !c.u8(&minor) || !c.u8(&type) || !c.u8(&method) || !c.u16(&flags))
    return bad("truncated header");
  if (major != draco::kDracoMeshBitstreamVersionMajor ||
      minor != draco::kDracoMeshBitstreamVersionMinor)
    return bad("bitstream version " + std::to_string(major) + "." + std::to_string(minor) +
               "; this reader takes " + std::to_string(draco::kDracoMeshBitstreamVersionMajor) +
               "." + std::to_string(draco::kDracoMeshBitstreamVersionMinor));
  if (type != draco::TRIANGULAR_MESH) return bad("not a triangle mesh (a point cloud?)");
  if (flags != 0) return bad("metadata or unknown header flags (" + std::to_string(flags) + ")");
  const uint64_t max_faces = std::min(limits.max_triangles, kMaxDracoElements);
  // A point is a vertex, or a copy of one split by a seam: at most 3 per face.
  const uint64_t max_points = std::min(limits.max_vertices + 3 * max_faces, kMaxDracoElements);
  uint64_t faces = 0, points = 0;
  if (method == draco::MESH_SEQUENTIAL_ENCODING) {
    if (!c.varint(&faces) || !c.varint(&points)) return bad("truncated connectivity header");
  } else if (method == draco::MESH_EDGEBREAKER_ENCODING) {
    uint32_t traversal = 0, attribute_data = 0;
    uint64_t vertices = 0, symbols = 0, splits = 0;
    if (!c.u8(&traversal) || !c.varint(&vertices) || !c.varint(&faces) || !c.u8(&attribute_data) ||
        !c.varint(&symbols) || !c.varint(&splits))
      return bad("truncated connectivity header");
    if (splits > faces) return bad("more split symbols than faces");
    points = vertices + splits;
  } else {
    return bad("unknown mesh encoding method " + std::to_string(method));
  }
  if (faces == 0) return bad("the mesh has no triangles");
  if (faces > max_faces)
    return bad(std::to_string(faces) + " triangles, more than the limit of " +
               std::to_string(max_faces));
  if (points > max_points)
    return bad(std::to_string(points) + " points, more than the limit of " +
               std::to_string(max_points));
  return true;
}

// The mesh's arrays at r's offsets, zeros elsewhere; dst holds the layout's size.
void write_arrays(const DecodedMesh& m, const MeshRecord& r, uint8_t* dst, uint64_t size) {
  std::memset(dst, 0, size);
  auto put = [dst](uint64_t at, const void* src, size_t bytes) {
    if (bytes) std::memcpy(dst + at, src, bytes);
  };
  put(r.positions, m.positions.data(), m.positions.size() * 4);
  if (r.flags & kMeshNormals) put(r.normals, m.normals.data(), m.normals.size() * 4);
  if (r.flags & kMeshUV) put(r.uv, m.uv.data(), m.uv.size() * 4);
  put(r.indices, m.indices.data(), m.indices.size() * 4);
  if (r.flags & kMeshFaceIndices)
    put(r.face_indices, m.face_indices.data(), m.face_indices.size() * 4);
}

void fill_record(const DecodedMesh& m, MeshRecord* r) {
  *r = MeshRecord{};
  r->num_vertices = uint32_t(m.num_vertices());
  r->num_triangles = uint32_t(m.num_triangles());
  if (!m.normals.empty()) r->flags |= kMeshNormals;
  if (!m.uv.empty()) r->flags |= kMeshUV;
  if (!m.face_indices.empty()) r->flags |= kMeshFaceIndices;
}

bool finite_all(const float* v, size_t n, size_t* bad) {
  for (size_t i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) {
      *bad = i;
      return false;
    }
  return true;
}

bool validate_input(const MeshArrays& in, const DracoOptions& opt, std::string* error) {
  if (opt.position_bits < kDracoMinPositionBits || opt.position_bits > kDracoMaxPositionBits)
    return fail(error, "position quantization of " + std::to_string(opt.position_bits) +
                           " bits is outside 8..30");
  if (opt.normal_bits < 4 || opt.normal_bits > 30 || opt.uv_bits < 4 || opt.uv_bits > 30)
    return fail(error, "normal and uv quantization must be 4..30 bits");
  if (opt.compression_level < 0 || opt.compression_level > 10)
    return fail(error,
                "compression level " + std::to_string(opt.compression_level) + " is outside 0..10");
  return draco_check_mesh(in, error);
}

}  // namespace

bool draco_check_mesh(const MeshArrays& in, std::string* error) {
  if (in.num_triangles == 0 || in.num_vertices == 0) return fail(error, "the mesh is empty");
  if (in.num_vertices > kMaxDracoElements || in.num_triangles > kMaxDracoElements)
    return fail(error, "the mesh is too large for Draco (more than 2^30 vertices or triangles)");
  if (!in.positions || !in.indices) return fail(error, "the mesh has no positions or indices");
  size_t bad = 0;
  if (!finite_all(in.positions, 3 * in.num_vertices, &bad))
    return fail(error, "position of vertex " + std::to_string(bad / 3) + " is not finite");
  if (in.normals && !finite_all(in.normals, 3 * in.num_vertices, &bad))
    return fail(error, "normal of vertex " + std::to_string(bad / 3) + " is not finite");
  if (in.uv && !finite_all(in.uv, 2 * in.num_vertices, &bad))
    return fail(error, "uv of vertex " + std::to_string(bad / 2) + " is not finite");
  for (size_t i = 0; i < 3 * in.num_triangles; ++i)
    if (in.indices[i] >= in.num_vertices)
      return fail(error, "triangle " + std::to_string(i / 3) + " has vertex index " +
                             std::to_string(in.indices[i]) + " (" +
                             std::to_string(in.num_vertices) + " vertices)");
  return true;
}

namespace {

// Adds a float attribute with one value per vertex, mapped from points through point_vertex
// (identity when empty).
int add_vertex_attribute(draco::Mesh* mesh, draco::GeometryAttribute::Type type, int components,
                         const float* values, size_t num_vertices,
                         const std::vector<uint32_t>& point_vertex) {
  draco::GeometryAttribute ga;
  ga.Init(type, nullptr, uint8_t(components), draco::DT_FLOAT32, false,
          int64_t(sizeof(float)) * components, 0);
  const bool identity = point_vertex.empty();
  const int id = mesh->AddAttribute(ga, identity, uint32_t(num_vertices));
  draco::PointAttribute* att = mesh->attribute(id);
  for (size_t v = 0; v < num_vertices; ++v)
    att->SetAttributeValue(draco::AttributeValueIndex(uint32_t(v)), values + components * v);
  if (!identity)
    for (size_t p = 0; p < point_vertex.size(); ++p)
      att->SetPointMapEntry(draco::PointIndex(uint32_t(p)),
                            draco::AttributeValueIndex(point_vertex[p]));
  return id;
}

bool encode_impl(const MeshArrays& in, const DracoOptions& opt, std::vector<uint8_t>* out,
                 std::string* error) {
  const size_t nv = in.num_vertices, nt = in.num_triangles;
  draco::Mesh mesh;
  // Points: one per vertex, plus, with face indices, one more per further face index a vertex
  // is used with (Draco keeps attribute values per point). Point v is vertex v as first used;
  // the extra points follow in order of the faces that need them, so the numbering depends only
  // on the input.
  std::vector<uint32_t> point_vertex;  // empty: points are the vertices
  std::vector<int32_t> point_face_value;
  std::vector<uint32_t> corners(in.indices, in.indices + 3 * nt);
  if (in.face_indices) {
    point_vertex.resize(nv);
    point_face_value.assign(nv, 0);
    std::vector<uint8_t> used(nv, 0);
    for (size_t v = 0; v < nv; ++v) point_vertex[v] = uint32_t(v);
    std::unordered_map<uint64_t, uint32_t> extra;  // (vertex, face value) -> point
    for (size_t f = 0; f < nt; ++f) {
      const int32_t value = in.face_indices[f];
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = in.indices[3 * f + k];
        if (!used[v]) {
          used[v] = 1;
          point_face_value[v] = value;
          continue;
        }
        if (point_face_value[v] == value) continue;
        const uint64_t key = uint64_t(v) << 32 | uint32_t(value);
        auto it = extra.find(key);
        if (it == extra.end()) {
          it = extra.emplace(key, uint32_t(point_vertex.size())).first;
          point_vertex.push_back(v);
          point_face_value.push_back(value);
        }
        corners[3 * f + k] = it->second;
      }
    }
    if (point_vertex.size() > kMaxDracoElements)
      return fail(error, "the mesh is too large for Draco (face indices split its vertices)");
    if (point_vertex.size() == nv) point_vertex.clear();  // no vertex was split: identity
  }
  const size_t np = point_vertex.empty() ? nv : point_vertex.size();
  mesh.set_num_points(uint32_t(np));
  mesh.SetNumFaces(nt);
  for (size_t f = 0; f < nt; ++f) {
    draco::Mesh::Face face;
    for (int k = 0; k < 3; ++k) face[k] = draco::PointIndex(corners[3 * f + k]);
    mesh.SetFace(draco::FaceIndex(uint32_t(f)), face);
  }
  const int pos = add_vertex_attribute(&mesh, draco::GeometryAttribute::POSITION, 3, in.positions,
                                       nv, point_vertex);
  const int nrm = in.normals ? add_vertex_attribute(&mesh, draco::GeometryAttribute::NORMAL, 3,
                                                    in.normals, nv, point_vertex)
                             : -1;
  const int tex = in.uv ? add_vertex_attribute(&mesh, draco::GeometryAttribute::TEX_COORD, 2, in.uv,
                                               nv, point_vertex)
                        : -1;
  if (in.face_indices) {
    // One value per point: points of one vertex differ exactly in this value.
    draco::GeometryAttribute ga;
    ga.Init(draco::GeometryAttribute::GENERIC, nullptr, 1, draco::DT_INT32, false, sizeof(int32_t),
            0);
    const int id = mesh.AddAttribute(ga, true, uint32_t(np));
    draco::PointAttribute* att = mesh.attribute(id);
    for (size_t p = 0; p < np; ++p) {
      const int32_t value = point_face_value.empty() ? 0 : point_face_value[p];
      att->SetAttributeValue(draco::AttributeValueIndex(uint32_t(p)), &value);
    }
  }

  draco::ExpertEncoder encoder(mesh);
  encoder.SetAttributeQuantization(pos, opt.position_bits);
  if (nrm >= 0) encoder.SetAttributeQuantization(nrm, opt.normal_bits);
  if (tex >= 0) encoder.SetAttributeQuantization(tex, opt.uv_bits);
  const int speed = 10 - opt.compression_level;
  encoder.SetSpeedOptions(speed, speed);
  encoder.SetEncodingMethod(opt.sequential ? draco::MESH_SEQUENTIAL_ENCODING
                                           : draco::MESH_EDGEBREAKER_ENCODING);
  // Sequential encoding otherwise stores indices raw; entropy-coded deltas are much smaller.
  encoder.options().SetGlobalBool("compress_connectivity", true);
  draco::EncoderBuffer buffer;
  const draco::Status status = encoder.EncodeToBuffer(&buffer);
  if (!status.ok())
    return fail(error, "draco: " + (status.error_msg_string().empty()
                                        ? std::string("cannot encode the mesh")
                                        : status.error_msg_string()));
  out->assign(reinterpret_cast<const uint8_t*>(buffer.data()),
              reinterpret_cast<const uint8_t*>(buffer.data()) + buffer.size());
  return true;
}

// Checks that att holds `components` values of 4-byte type `type` per entry, that its buffer
// holds every entry, and that every point maps to an entry.
bool check_attribute(const draco::PointAttribute& att, const char* name, int components,
                     draco::DataType type, uint32_t num_points, std::string* error) {
  auto bad = [&](const std::string& why) {
    return fail(error, std::string("draco: ") + name + " attribute " + why);
  };
  if (att.data_type() != type || att.num_components() != components)
    return bad("has " + std::to_string(att.num_components()) + " components of type " +
               std::to_string(int(att.data_type())) + ", not " + std::to_string(components) +
               " of type " + std::to_string(int(type)));
  if (att.byte_stride() != int64_t(4) * components || att.byte_offset() != 0)
    return bad("is not packed");
  const draco::DataBuffer* buffer = att.buffer();
  const uint64_t entries = att.size();
  if (buffer == nullptr || buffer->data() == nullptr ||
      buffer->data_size() < entries * uint64_t(att.byte_stride()))
    return bad("buffer is shorter than its " + std::to_string(entries) + " values");
  if (!att.is_mapping_identity() && att.indices_map_size() < num_points)
    return bad("maps " + std::to_string(att.indices_map_size()) + " of " +
               std::to_string(num_points) + " points");
  for (uint32_t p = 0; p < num_points; ++p) {
    const uint32_t v = att.mapped_index(draco::PointIndex(p)).value();
    if (v >= entries)
      return bad("maps point " + std::to_string(p) + " to value " + std::to_string(v) + " of " +
                 std::to_string(entries));
  }
  return true;
}

const uint8_t* value_of(const draco::PointAttribute& att, uint32_t point) {
  const uint32_t v = att.mapped_index(draco::PointIndex(point)).value();
  return att.buffer()->data() + uint64_t(v) * uint64_t(att.byte_stride());
}

bool convert(const draco::Mesh& mesh, const DracoLimits& limits, DecodedMesh* out,
             std::string* error) {
  const uint32_t np = mesh.num_points();
  const uint32_t nf = mesh.num_faces();
  if (nf == 0) return fail(error, "draco: the mesh has no triangles");
  if (nf > limits.max_triangles)
    return fail(error, "draco: " + std::to_string(nf) + " triangles, more than the limit of " +
                           std::to_string(limits.max_triangles));
  const draco::PointAttribute *pos = nullptr, *nrm = nullptr, *tex = nullptr, *face = nullptr;
  bool welding = false;  // some attribute is not kept per vertex
  for (int i = 0; i < mesh.num_attributes(); ++i) {
    const draco::PointAttribute* att = mesh.attribute(i);
    if (att == nullptr) continue;
    const auto type = att->attribute_type();
    if (type == draco::GeometryAttribute::POSITION && !pos) {
      if (!check_attribute(*att, "position", 3, draco::DT_FLOAT32, np, error)) return false;
      pos = att;
    } else if (type == draco::GeometryAttribute::NORMAL && !nrm) {
      if (!check_attribute(*att, "normal", 3, draco::DT_FLOAT32, np, error)) return false;
      nrm = att;
    } else if (type == draco::GeometryAttribute::TEX_COORD && !tex) {
      if (!check_attribute(*att, "uv", 2, draco::DT_FLOAT32, np, error)) return false;
      tex = att;
    } else if (type == draco::GeometryAttribute::GENERIC && !face && att->num_components() == 1 &&
               att->data_type() == draco::DT_INT32) {
      if (!check_attribute(*att, "face index", 1, draco::DT_INT32, np, error)) return false;
      face = att;
      welding = true;
    } else {
      welding = true;  // ignored: colours, a second uv set, ...
    }
  }
  if (!pos) return fail(error, "draco: the mesh has no positions");

  // Points to vertices: the identity, or welding points equal in every kept attribute.
  const int stride = 3 + (nrm ? 3 : 0) + (tex ? 2 : 0);
  std::vector<float> point(stride);
  auto gather = [&](uint32_t p) {
    std::memcpy(point.data(), value_of(*pos, p), 12);
    int at = 3;
    if (nrm) std::memcpy(point.data() + at, value_of(*nrm, p), 12), at += 3;
    if (tex) std::memcpy(point.data() + at, value_of(*tex, p), 8);
  };
  std::vector<uint32_t> point_vertex(np);
  std::vector<float> vertices;  // stride floats per vertex
  if (welding) {
    // Keyed by the bits of a point's kept values (zero-padded to 8 floats).
    using Key = std::array<uint32_t, 8>;
    struct KeyHash {
      size_t operator()(const Key& k) const { return size_t(XXH3_64bits(k.data(), sizeof(Key))); }
    };
    std::unordered_map<Key, uint32_t, KeyHash> seen;
    seen.reserve(np);
    for (uint32_t p = 0; p < np; ++p) {
      gather(p);
      Key key{};
      std::memcpy(key.data(), point.data(), stride * sizeof(float));
      auto [it, fresh] = seen.emplace(key, uint32_t(vertices.size() / stride));
      if (fresh) vertices.insert(vertices.end(), point.begin(), point.end());
      point_vertex[p] = it->second;
    }
  } else {
    vertices.resize(uint64_t(np) * stride);
    for (uint32_t p = 0; p < np; ++p) {
      gather(p);
      std::copy(point.begin(), point.end(), vertices.begin() + uint64_t(p) * stride);
      point_vertex[p] = p;
    }
  }
  const uint64_t nv = vertices.size() / stride;
  if (nv > limits.max_vertices)
    return fail(error, "draco: " + std::to_string(nv) + " vertices, more than the limit of " +
                           std::to_string(limits.max_vertices));
  for (uint64_t i = 0; i < vertices.size(); ++i)
    if (!std::isfinite(vertices[i])) {
      const int c = int(i % stride);
      return fail(error, std::string("draco: ") +
                             (c < 3          ? "position"
                              : nrm && c < 6 ? "normal"
                                             : "uv") +
                             " of vertex " + std::to_string(i / stride) + " is not finite");
    }

  DecodedMesh m;
  m.positions.resize(3 * nv);
  if (nrm) m.normals.resize(3 * nv);
  if (tex) m.uv.resize(2 * nv);
  for (uint64_t v = 0; v < nv; ++v) {
    const float* src = vertices.data() + v * stride;
    std::copy(src, src + 3, m.positions.begin() + 3 * v);
    int at = 3;
    if (nrm) std::copy(src + at, src + at + 3, m.normals.begin() + 3 * v), at += 3;
    if (tex) std::copy(src + at, src + at + 2, m.uv.begin() + 2 * v);
  }
  m.indices.resize(3 * uint64_t(nf));
  if (face) m.face_indices.resize(nf);
  for (uint32_t f = 0; f < nf; ++f) {
    const draco::Mesh::Face& tri = mesh.face(draco::FaceIndex(f));
    for (int k = 0; k < 3; ++k) {
      const uint32_t p = tri[k].value();
      if (p >= np)
        return fail(error, "draco: triangle " + std::to_string(f) + " has point " +
                               std::to_string(p) + " (" + std::to_string(np) + " points)");
      m.indices[3 * uint64_t(f) + k] = point_vertex[p];
    }
    // The encoder gives all corners of a face the face's value; a stream that does not is
    // read by its first corner.
    if (face) std::memcpy(&m.face_indices[f], value_of(*face, tri[0].value()), 4);
  }
  *out = std::move(m);
  return true;
}

}  // namespace

MeshArrays DecodedMesh::view() const {
  MeshArrays a;
  a.positions = positions.data();
  a.normals = normals.empty() ? nullptr : normals.data();
  a.uv = uv.empty() ? nullptr : uv.data();
  a.indices = indices.data();
  a.face_indices = face_indices.empty() ? nullptr : face_indices.data();
  a.num_vertices = num_vertices();
  a.num_triangles = num_triangles();
  return a;
}

bool draco_encode(const MeshArrays& in, const DracoOptions& opt, std::vector<uint8_t>* out,
                  std::string* error) {
  out->clear();
  if (!validate_input(in, opt, error)) return false;
  try {
    if (encode_impl(in, opt, out, error)) return true;
  } catch (const std::exception& e) {
    *error = std::string("draco: ") + e.what();
  }
  out->clear();
  return false;
}

bool draco_decode(const uint8_t* data, size_t size, DecodedMesh* out, std::string* error) {
  return draco_decode(data, size, draco_limits_for(size), out, error);
}

DracoLimits draco_limits_for(uint64_t stream_bytes) {
  // The archive's bound on any compressed section, over 12 bytes (a vertex's position, a
  // triangle's indices).
  uint64_t raw = stream_bytes > (uint64_t{1} << 40) / kMaxZstdRatio
                     ? uint64_t{1} << 40
                     : stream_bytes * kMaxZstdRatio + kZstdRatioSlack;
  DracoLimits limits;
  limits.max_vertices = std::min(limits.max_vertices, raw / 12);
  limits.max_triangles = std::min(limits.max_triangles, raw / 12);
  return limits;
}

bool draco_decode(const uint8_t* data, size_t size, const DracoLimits& limits, DecodedMesh* out,
                  std::string* error) {
  *out = DecodedMesh{};
  if (size > kMaxStreamBytes) return fail(error, "draco: the stream is longer than 2^31 bytes");
  if (!check_header(data, size, limits, error)) return false;
  try {
    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(data), size);
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
    if (!decoded.ok())
      return fail(error, "draco: " + (decoded.status().error_msg_string().empty()
                                          ? std::string("cannot decode the mesh")
                                          : decoded.status().error_msg_string()));
    const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
    if (!mesh) return fail(error, "draco: cannot decode the mesh");
    return convert(*mesh, limits, out, error);
  } catch (const std::exception& e) {
    *out = DecodedMesh{};
    return fail(error, std::string("draco: ") + e.what());
  }
}

bool draco_position_bits(const uint8_t* data, size_t size, int* bits, std::string* error) {
  *bits = 0;
  if (size > kMaxStreamBytes) return fail(error, "draco: the stream is longer than 2^31 bytes");
  if (!check_header(data, size, draco_limits_for(size), error)) return false;
  try {
    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(data), size);
    draco::Decoder decoder;
    // Left quantized, the position attribute keeps its transform parameters: the bits.
    decoder.SetSkipAttributeTransform(draco::GeometryAttribute::POSITION);
    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
    if (!decoded.ok() || !decoded.value()) return fail(error, "draco: cannot decode the mesh");
    const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
    const draco::PointAttribute* pos = mesh->GetNamedAttribute(draco::GeometryAttribute::POSITION);
    if (pos == nullptr) return fail(error, "draco: the mesh has no positions");
    draco::AttributeQuantizationTransform q;
    if (pos->GetAttributeTransformData() != nullptr && q.InitFromAttribute(*pos))
      *bits = q.quantization_bits();
    return true;
  } catch (const std::exception& e) {
    return fail(error, std::string("draco: ") + e.what());
  }
}

double draco_position_bound(const float* positions, size_t num_vertices, int bits) {
  if (num_vertices == 0) return 0;
  // As Draco's AttributeQuantizationTransform computes it: per-axis extents in float, the
  // largest of them (1 if all are 0), split into 2^bits - 1 steps.
  float lo[3], hi[3];
  for (int c = 0; c < 3; ++c) lo[c] = hi[c] = positions[c];
  for (size_t v = 1; v < num_vertices; ++v)
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min(lo[c], positions[3 * v + c]);
      hi[c] = std::max(hi[c], positions[3 * v + c]);
    }
  float range = 0;
  for (int c = 0; c < 3; ++c) range = std::max(range, hi[c] - lo[c]);
  if (range == 0) range = 1;
  return double(range) / double((uint64_t{1} << bits) - 1) / 2;
}

double draco_max_displacement(const MeshArrays& original, const MeshArrays& decoded, double bound,
                              bool same_order, std::vector<uint32_t>* nearest) {
  const size_t no = original.num_vertices, nd = decoded.num_vertices;
  const float* po = original.positions;
  const float* pd = decoded.positions;
  if (nearest) nearest->assign(nd, 0);
  if (no == 0 || nd == 0) return 0;
  auto dist = [&](size_t d, size_t o) {
    double m = 0;
    for (int c = 0; c < 3; ++c) m = std::max(m, std::fabs(double(pd[3 * d + c]) - po[3 * o + c]));
    return m;
  };
  double worst = 0;
  if (same_order && no == nd) {
    for (size_t v = 0; v < nd; ++v) {
      worst = std::max(worst, dist(v, v));
      if (nearest) (*nearest)[v] = uint32_t(v);
    }
    return worst;
  }
  // Cells a little over twice the bound: a vertex's source lies in its cell or a neighbour.
  double lo[3] = {po[0], po[1], po[2]};
  for (size_t v = 1; v < no; ++v)
    for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], double(po[3 * v + c]));
  double extent = 0;
  for (size_t v = 0; v < no; ++v)
    for (int c = 0; c < 3; ++c) extent = std::max(extent, po[3 * v + c] - lo[c]);
  const double cell = std::max(2 * bound * (1 + 1e-6), std::max(extent, 1.0) * 1e-12);
  auto cell_of = [&](const float* p, int c) {
    return int64_t(std::floor((double(p[c]) - lo[c]) / cell));
  };
  auto hash = [](int64_t x, int64_t y, int64_t z) {
    const int64_t k[3] = {x, y, z};
    return XXH3_64bits(k, sizeof(k));
  };
  std::vector<std::pair<uint64_t, uint32_t>> grid(no);  // (cell hash, vertex), sorted
  for (size_t v = 0; v < no; ++v)
    grid[v] = {hash(cell_of(po + 3 * v, 0), cell_of(po + 3 * v, 1), cell_of(po + 3 * v, 2)),
               uint32_t(v)};
  std::sort(grid.begin(), grid.end());
  for (size_t d = 0; d < nd; ++d) {
    const float* p = pd + 3 * d;
    const int64_t x = cell_of(p, 0), y = cell_of(p, 1), z = cell_of(p, 2);
    double best = std::numeric_limits<double>::infinity();
    uint32_t best_v = 0;
    auto consider = [&](uint32_t o) {
      const double m = dist(d, o);
      if (m < best || (m == best && o < best_v)) best = m, best_v = o;
    };
    for (int64_t dx = -1; dx <= 1; ++dx)
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dz = -1; dz <= 1; ++dz) {
          const uint64_t h = hash(x + dx, y + dy, z + dz);
          auto it = std::lower_bound(grid.begin(), grid.end(), std::make_pair(h, uint32_t(0)));
          for (; it != grid.end() && it->first == h; ++it) consider(it->second);
        }
    if (best > cell)  // nothing that close (or only hash neighbours): the nearest of all
      for (size_t o = 0; o < no; ++o) consider(uint32_t(o));
    worst = std::max(worst, best);
    if (nearest) (*nearest)[d] = best_v;
  }
  return worst;
}

double draco_position_slack(const float* positions, size_t num_vertices) {
  if (num_vertices == 0) return 0;
  float lo = positions[0], hi = positions[0], magnitude = 0, extent = 0;
  for (int c = 0; c < 3; ++c) {
    lo = hi = positions[c];
    for (size_t v = 0; v < num_vertices; ++v) {
      lo = std::min(lo, positions[3 * v + c]);
      hi = std::max(hi, positions[3 * v + c]);
    }
    magnitude = std::max({magnitude, std::fabs(lo), std::fabs(hi)});
    extent = std::max(extent, hi - lo);
  }
  return 4.0 * std::max(magnitude, extent) * std::numeric_limits<float>::epsilon();
}

uint64_t single_mesh_layout(MeshRecord* r) {
  const uint64_t nv = r->num_vertices, nt = r->num_triangles;
  uint64_t at = 0;
  auto place = [&at](bool present, uint64_t bytes) -> uint64_t {
    if (!present) return 0;
    const uint64_t offset = align16(at);
    at = offset + bytes;
    return offset;
  };
  r->positions = place(true, 12 * nv);
  r->normals = place(r->flags & kMeshNormals, 12 * nv);
  r->tangents = place(r->flags & kMeshTangents, 12 * nv);
  r->uv = place(r->flags & kMeshUV, 8 * nv);
  r->indices = place(true, 12 * nt);
  r->face_indices = place(r->flags & kMeshFaceIndices, 4 * nt);
  return at;
}

void draco_geometry_section(const DecodedMesh& mesh, MeshRecord* r, std::vector<uint8_t>* raw) {
  fill_record(mesh, r);
  const uint64_t size = single_mesh_layout(r);
  raw->resize(size);
  write_arrays(mesh, *r, raw->data(), size);
}

bool draco_decode_section(const uint8_t* data, size_t size, uint64_t raw_size, uint8_t* dst,
                          uint32_t counts[2], std::string* error) {
  // Positions take 12 bytes a vertex and indices 12 a triangle: raw_size bounds both.
  DracoLimits limits;
  limits.max_vertices = raw_size / 12;
  limits.max_triangles = raw_size / 12;
  DecodedMesh mesh;
  if (!draco_decode(data, size, limits, &mesh, error)) return false;
  MeshRecord r;
  fill_record(mesh, &r);
  const uint64_t layout = single_mesh_layout(&r);
  if (layout != raw_size)
    return fail(error, "draco: the mesh (" + std::to_string(r.num_vertices) + " vertices, " +
                           std::to_string(r.num_triangles) + " triangles) lays out to " +
                           std::to_string(layout) + " bytes but the table says " +
                           std::to_string(raw_size));
  write_arrays(mesh, r, dst, layout);
  counts[0] = r.num_vertices;
  counts[1] = r.num_triangles;
  return true;
}

}  // namespace pbrta
