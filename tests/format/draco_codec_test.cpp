// tests/format/draco_codec_test.cpp — the Draco wrapper (format/draco_codec.h) and draco
// geometry sections in the archive container: round trips of a generated mesh with normals, uv
// and face indices at 11, 14 and 16 bits (sequential: exact order; edgebreaker: the same
// triangles up to vertex and face order), the measured position error against the bound the
// bits imply, determinism, garbage, truncated and bit-flipped streams, hostile headers, limits,
// and the reader's checks on Draco sections with their exact messages.
#include <unistd.h>

#include <gtest/gtest.h>
#include <xxhash.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "format/archive.h"
#include "format/archive_reader.h"
#include "format/archive_writer.h"
#include "format/draco_codec.h"
#include "format/draco_forgery.h"
#include "test_support.h"

namespace pbrta {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A bumpy torus (closed and manifold, so edgebreaker keeps every vertex) with analytic normals,
// uv, and one face index per quad, so every vertex is used with four face indices and the
// encoder must split it.
struct TestMesh {
  std::vector<float> P, N, uv;
  std::vector<uint32_t> indices;
  std::vector<int32_t> faces;

  MeshArrays view(bool normals = true, bool uvs = true, bool face_indices = true) const {
    MeshArrays a;
    a.positions = P.data();
    a.normals = normals ? N.data() : nullptr;
    a.uv = uvs ? uv.data() : nullptr;
    a.indices = indices.data();
    a.face_indices = face_indices ? faces.data() : nullptr;
    a.num_vertices = P.size() / 3;
    a.num_triangles = indices.size() / 3;
    return a;
  }
};

TestMesh torus(int nu, int nv) {
  TestMesh m;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * kPi * i / nu, v = 2 * kPi * j / nv;
      const double r = 0.7 * (1 + 0.1 * std::sin(3 * u) * std::cos(2 * v));
      const double x = (2 + r * std::cos(v)) * std::cos(u), y = (2 + r * std::cos(v)) * std::sin(u);
      m.P.insert(m.P.end(), {float(x + 10), float(y - 3), float(r * std::sin(v) + 1)});
      m.N.insert(m.N.end(), {float(std::cos(v) * std::cos(u)), float(std::cos(v) * std::sin(u)),
                             float(std::sin(v))});
      m.uv.insert(m.uv.end(), {float(i) / nu, float(j) / nv});
    }
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const uint32_t a = uint32_t(i * nv + j), b = uint32_t(((i + 1) % nu) * nv + j);
      const uint32_t c = uint32_t(((i + 1) % nu) * nv + (j + 1) % nv);
      const uint32_t d = uint32_t(i * nv + (j + 1) % nv);
      m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
      m.faces.insert(m.faces.end(), {i * nv + j, i * nv + j});
    }
  return m;
}

std::vector<uint8_t> encode(const MeshArrays& a, int bits, bool sequential) {
  DracoOptions o;
  o.position_bits = bits;
  o.sequential = sequential;
  std::vector<uint8_t> out;
  std::string error;
  EXPECT_TRUE(draco_encode(a, o, &out, &error)) << error;
  return out;
}

// A decoded mesh is well formed whatever the stream was.
void expect_well_formed(const DecodedMesh& d) {
  const size_t nv = d.num_vertices();
  ASSERT_EQ(d.positions.size(), 3 * nv);
  ASSERT_TRUE(d.normals.empty() || d.normals.size() == 3 * nv);
  ASSERT_TRUE(d.uv.empty() || d.uv.size() == 2 * nv);
  ASSERT_EQ(d.indices.size() % 3, 0u);
  ASSERT_TRUE(d.face_indices.empty() || d.face_indices.size() == d.num_triangles());
  for (uint32_t i : d.indices) ASSERT_LT(i, nv);
  for (float f : d.positions) ASSERT_TRUE(std::isfinite(f));
}

// Triangles as (vertices rotated to start at the smallest, face index), sorted: equal lists
// mean the same triangles with the same orientation, whatever their order.
using Tri = std::array<int64_t, 4>;
std::vector<Tri> canonical(const std::vector<uint32_t>& idx, const std::vector<int32_t>& faces,
                           const std::vector<uint32_t>* map) {
  std::vector<Tri> out;
  for (size_t t = 0; t < idx.size() / 3; ++t) {
    uint32_t v[3];
    for (int k = 0; k < 3; ++k) v[k] = map ? (*map)[idx[3 * t + k]] : idx[3 * t + k];
    const int s = v[0] <= v[1] && v[0] <= v[2] ? 0 : v[1] <= v[2] ? 1 : 2;
    out.push_back({v[s], v[(s + 1) % 3], v[(s + 2) % 3], faces.empty() ? 0 : faces[t]});
  }
  std::sort(out.begin(), out.end());
  return out;
}

class DracoRoundTrip : public ::testing::TestWithParam<std::tuple<int, bool>> {};

TEST_P(DracoRoundTrip, KeepsTrianglesWithinTheBound) {
  const auto [bits, sequential] = GetParam();
  const TestMesh m = torus(40, 24);
  const MeshArrays in = m.view();
  const std::vector<uint8_t> stream = encode(in, bits, sequential);
  ASSERT_FALSE(stream.empty());
  // Smaller than the raw arrays, even sequential, where face indices split every vertex in 4.
  const size_t raw =
      4 * (m.P.size() + m.N.size() + m.uv.size() + m.indices.size() + m.faces.size());
  EXPECT_LT(stream.size(), sequential ? raw : raw / 4);

  DecodedMesh d;
  std::string error;
  ASSERT_TRUE(draco_decode(stream.data(), stream.size(), &d, &error)) << error;
  expect_well_formed(d);
  ASSERT_EQ(d.num_triangles(), in.num_triangles);
  // The face-index splits are welded back, and the torus is manifold: no vertex is lost or
  // added (its vertices are far apart compared with an 11-bit step).
  ASSERT_EQ(d.num_vertices(), in.num_vertices);
  ASSERT_EQ(d.normals.size(), m.N.size());
  ASSERT_EQ(d.uv.size(), m.uv.size());
  ASSERT_EQ(d.face_indices.size(), m.faces.size());

  const double bound = draco_position_bound(in.positions, in.num_vertices, bits);
  const double slack = draco_position_slack(in.positions, in.num_vertices);
  // The bound is half a step of the largest extent (the torus is 5.4 wide in x and y).
  EXPECT_NEAR(bound, 5.4 / ((1 << bits) - 1) / 2, 0.02 * bound);
  EXPECT_LT(slack, bound * 0.2);
  std::vector<uint32_t> nearest;
  const double moved = draco_max_displacement(in, d.view(), bound, sequential, &nearest);
  EXPECT_LE(moved, bound + slack);
  EXPECT_GT(moved, bound * 0.5) << "quantization should move some vertex by nearly the bound";

  if (sequential) {
    // Order kept: vertices, triangles and face indices are where they were.
    EXPECT_EQ(d.indices, m.indices);
    EXPECT_EQ(d.face_indices, m.faces);
    for (size_t v = 0; v < in.num_vertices; ++v) ASSERT_EQ(nearest[v], v);
  } else {
    // Matched by position, the decoded vertices are a permutation of the originals...
    std::vector<uint32_t> sorted = nearest;
    std::sort(sorted.begin(), sorted.end());
    for (size_t v = 0; v < sorted.size(); ++v) ASSERT_EQ(sorted[v], v);
    // ...and the triangles, with their orientation and face indices, are the same set.
    EXPECT_EQ(canonical(d.indices, d.face_indices, &nearest),
              canonical(m.indices, m.faces, nullptr));
  }
  // Normals to 10 bits (well under a degree), uv to 12 bits over their extent (1 - 1/40).
  const double uv_bound = (1.0 - 1.0 / 40) / 4095 / 2;
  for (size_t v = 0; v < d.num_vertices(); ++v) {
    const size_t o = nearest[v];
    double dot = 0, len = 0;
    for (int c = 0; c < 3; ++c) {
      dot += double(d.normals[3 * v + c]) * m.N[3 * o + c];
      len += double(d.normals[3 * v + c]) * d.normals[3 * v + c];
    }
    ASSERT_GT(dot / std::sqrt(len), std::cos(kPi / 180)) << "vertex " << v;
    for (int c = 0; c < 2; ++c)
      ASSERT_LE(std::fabs(d.uv[2 * v + c] - m.uv[2 * o + c]), uv_bound + 1e-6) << "vertex " << v;
  }
}

INSTANTIATE_TEST_SUITE_P(Bits, DracoRoundTrip,
                         ::testing::Combine(::testing::Values(11, 14, 16), ::testing::Bool()),
                         [](const auto& info) {
                           return std::to_string(std::get<0>(info.param)) +
                                  (std::get<1>(info.param) ? "bits_sequential" : "bits");
                         });

TEST(DracoCodec, PositionsOnlyAndDeterministic) {
  const TestMesh m = torus(30, 20);
  const MeshArrays in = m.view(false, false, false);
  const std::vector<uint8_t> a = encode(in, 12, false), b = encode(in, 12, false);
  EXPECT_EQ(a, b);
  DecodedMesh d1, d2;
  std::string error;
  ASSERT_TRUE(draco_decode(a.data(), a.size(), &d1, &error)) << error;
  ASSERT_TRUE(draco_decode(a.data(), a.size(), &d2, &error)) << error;
  EXPECT_EQ(d1.positions, d2.positions);
  EXPECT_EQ(d1.indices, d2.indices);
  EXPECT_TRUE(d1.normals.empty() && d1.uv.empty() && d1.face_indices.empty());
  EXPECT_EQ(d1.num_vertices(), in.num_vertices);
  EXPECT_EQ(d1.num_triangles(), in.num_triangles);
  // More bits, larger stream; sequential keeps the order and costs more.
  EXPECT_LT(a.size(), encode(in, 20, false).size());
  EXPECT_LT(a.size(), encode(in, 12, true).size());
}

TEST(DracoCodec, ReportsThePositionBitsAStreamUsed) {
  const TestMesh m = torus(30, 20);
  for (int bits : {8, 11, 14, 16, 20}) {
    for (bool sequential : {false, true}) {
      const std::vector<uint8_t> s = encode(m.view(true, true, true), bits, sequential);
      int got = -1;
      std::string error;
      ASSERT_TRUE(draco_position_bits(s.data(), s.size(), &got, &error)) << error;
      EXPECT_EQ(got, bits) << (sequential ? "sequential" : "edgebreaker");
    }
  }
  const std::vector<uint8_t> junk(100, 7);
  int got = -1;
  std::string error;
  EXPECT_FALSE(draco_position_bits(junk.data(), junk.size(), &got, &error));
  EXPECT_EQ(got, 0);
  EXPECT_NE(error.find("draco"), std::string::npos) << error;
}

TEST(DracoCodec, RefusesInvalidInput) {
  TestMesh m = torus(8, 6);
  std::vector<uint8_t> out;
  std::string error;
  DracoOptions o;
  o.position_bits = 7;
  EXPECT_FALSE(draco_encode(m.view(), o, &out, &error));
  EXPECT_EQ(error, "position quantization of 7 bits is outside 8..30");
  o.position_bits = 14;
  o.compression_level = 11;
  EXPECT_FALSE(draco_encode(m.view(), o, &out, &error));
  EXPECT_EQ(error, "compression level 11 is outside 0..10");
  o.compression_level = 7;
  m.P[3 * 5 + 1] = std::nanf("");
  EXPECT_FALSE(draco_encode(m.view(), o, &out, &error));
  EXPECT_EQ(error, "position of vertex 5 is not finite");
  m = torus(8, 6);
  m.indices[7] = 48;
  EXPECT_FALSE(draco_encode(m.view(), o, &out, &error));
  EXPECT_EQ(error, "triangle 2 has vertex index 48 (48 vertices)");
  MeshArrays empty = m.view();
  empty.num_triangles = 0;
  EXPECT_FALSE(draco_encode(empty, o, &out, &error));
  EXPECT_EQ(error, "the mesh is empty");
  EXPECT_TRUE(out.empty());
}

TEST(DracoCodec, GarbageFailsCleanly) {
  DecodedMesh d;
  std::string error;
  EXPECT_FALSE(draco_decode(nullptr, 0, &d, &error));
  EXPECT_EQ(error, "draco: not a Draco stream");
  const std::string junk = "this is not a mesh at all, just text";
  EXPECT_FALSE(
      draco_decode(reinterpret_cast<const uint8_t*>(junk.data()), junk.size(), &d, &error));
  EXPECT_EQ(error, "draco: not a Draco stream");
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<uint8_t> bytes(1 + rng() % 600);
    for (uint8_t& b : bytes) b = uint8_t(rng());
    // Half of them get a valid-looking header so Draco itself sees the rest.
    if (trial % 2 == 0 && bytes.size() > 12) {
      const uint8_t header[11] = {'D', 'R', 'A', 'C', 'O', 2, 2, 1, uint8_t(trial % 4 / 2), 0, 0};
      std::memcpy(bytes.data(), header, sizeof header);
    }
    if (draco_decode(bytes.data(), bytes.size(), &d, &error)) {
      expect_well_formed(d);
    } else {
      EXPECT_EQ(error.compare(0, 7, "draco: "), 0) << error;
      EXPECT_EQ(d.num_vertices(), 0u);
    }
  }
}

TEST(DracoCodec, TruncatedAndFlippedStreamsFailCleanly) {
  const TestMesh m = torus(12, 8);
  // The limits the archive reader would derive from the section's raw size.
  DracoLimits limits;
  limits.max_vertices = limits.max_triangles = 96 * 32 + 192 * 16;
  for (bool sequential : {false, true}) {
    const std::vector<uint8_t> good = encode(m.view(), 11, sequential);
    DecodedMesh d;
    std::string error;
    for (size_t n = 0; n < good.size(); ++n) {
      std::vector<uint8_t> cut(good.begin(), good.begin() + n);  // own buffer: ASan sees overreads
      if (draco_decode(cut.data(), cut.size(), limits, &d, &error))
        expect_well_formed(d);
      else
        EXPECT_EQ(error.compare(0, 7, "draco: "), 0) << error;
    }
    // Some flips in the edgebreaker stream's attribute parameters cost Draco seconds before it
    // fails (format/draco_codec.h): one flip per byte there keeps the test quick.
    std::mt19937 rng(sequential ? 3 : 4);
    for (size_t i = 0; i < good.size(); ++i)
      for (int trial = 0; trial < (sequential ? 3 : 1); ++trial) {
        std::vector<uint8_t> bad = good;
        bad[i] ^= uint8_t(1u << (rng() % 8));
        if (draco_decode(bad.data(), bad.size(), limits, &d, &error))
          expect_well_formed(d);
        else
          EXPECT_EQ(error.compare(0, 7, "draco: "), 0) << error;
      }
  }
}

TEST(DracoCodec, HostileHeadersAreRefusedBeforeDracoAllocates) {
  DecodedMesh d;
  std::string error;
  auto decode = [&](std::vector<uint8_t> bytes) {
    bytes.resize(bytes.size() + 8, 0);
    EXPECT_FALSE(draco_decode(bytes.data(), bytes.size(), DracoLimits{}, &d, &error));
    return error;
  };
  // Sequential: 2^29 faces, 3 points, in a few bytes.
  EXPECT_EQ(decode({'D', 'R', 'A', 'C', 'O', 2, 2, 1, 0, 0, 0, 0x80, 0x80, 0x80, 0x80, 0x02, 3}),
            "draco: 536870912 triangles, more than the limit of 268435456");
  // Edgebreaker: a few faces but 2^31 vertices.
  EXPECT_EQ(decode({'D', 'R',  'A',  'C',  'O',  2,    2, 1, 1, 0, 0,
                    0,   0x80, 0x80, 0x80, 0x80, 0x08, 4, 0, 4, 0}),
            "draco: 2147483648 points, more than the limit of 1073741824");
  EXPECT_EQ(decode({'D', 'R', 'A', 'C', 'O', 2, 2, 1, 1, 0, 0, 0, 4, 0}),
            "draco: the mesh has no triangles");
  EXPECT_EQ(decode({'D', 'R', 'A', 'C', 'O', 2, 2, 1, 0, 0, 0, 0x80, 0x80, 0x80, 0x80, 0x80, 1}),
            "draco: truncated connectivity header");
  EXPECT_EQ(decode({'D', 'R', 'A', 'C', 'O', 1, 3, 1, 0, 0, 0}),
            "draco: bitstream version 1.3; this reader takes 2.2");
  EXPECT_EQ(decode({'D', 'R', 'A', 'C', 'O', 2, 2, 0, 0, 0, 0}),
            "draco: not a triangle mesh (a point cloud?)");
  EXPECT_EQ(decode({'D', 'R', 'A', 'C', 'O', 2, 2, 1, 0, 0, 0x80}),
            "draco: metadata or unknown header flags (32768)");
  EXPECT_EQ(decode({'D', 'R', 'A', 'C', 'O', 2, 2, 1, 2, 0, 0}),
            "draco: unknown mesh encoding method 2");
}

TEST(DracoCodec, LimitsBoundTheDecodedMesh) {
  // Without limits given, a stream's size sets them as for an archive section.
  EXPECT_EQ(draco_limits_for(1000).max_triangles, (1000 * 32768 + (1 << 20)) / 12);
  EXPECT_EQ(draco_limits_for(uint64_t{1} << 30).max_vertices, uint64_t{1} << 28);
  const TestMesh m = torus(10, 8);
  const std::vector<uint8_t> s = encode(m.view(), 14, false);
  DecodedMesh d;
  std::string error;
  DracoLimits limits;
  limits.max_triangles = 159;
  EXPECT_FALSE(draco_decode(s.data(), s.size(), limits, &d, &error));
  EXPECT_EQ(error, "draco: 160 triangles, more than the limit of 159");
  limits.max_triangles = 160;
  limits.max_vertices = 79;
  EXPECT_FALSE(draco_decode(s.data(), s.size(), limits, &d, &error));
  EXPECT_EQ(error, "draco: 80 vertices, more than the limit of 79");
  limits.max_vertices = 80;
  EXPECT_TRUE(draco_decode(s.data(), s.size(), limits, &d, &error)) << error;
}

TEST(DracoCodec, SingleMeshLayout) {
  MeshRecord r{};
  r.num_vertices = 5;
  r.num_triangles = 3;
  r.flags = kMeshNormals | kMeshUV | kMeshFaceIndices;
  EXPECT_EQ(single_mesh_layout(&r), 236u);
  EXPECT_EQ(r.positions, 0u);       // 60 bytes
  EXPECT_EQ(r.normals, 64u);        // 60
  EXPECT_EQ(r.tangents, 0u);        // absent
  EXPECT_EQ(r.uv, 128u);            // 40
  EXPECT_EQ(r.indices, 176u);       // 36
  EXPECT_EQ(r.face_indices, 224u);  // 12
}

// ---------------------------------------------------------------------------------------------
// Codec 3 in the archive container.

std::string archive_with(const std::vector<uint8_t>& raw, const std::vector<uint8_t>& stream,
                         const std::string& name) {
  ArchiveWriter w;
  w.add_encoded_section(SectionKind::kGeometry, raw, stream, 1, Codec::kDraco);
  w.add_section(SectionKind::kStrings, std::vector<uint8_t>(100, 'x'), 1, Codec::kZstd);
  const std::string path = testing_support::scratch_dir(name) + "/a.pbrta";
  std::string error;
  EXPECT_TRUE(w.write(path, 0, 3, 1, &error)) << error;
  EXPECT_EQ(w.table()[0].codec, uint32_t(Codec::kDraco));
  return testing_support::read_file(path);
}

SectionEntry entry_of(const std::string& b, uint32_t i) {
  SectionEntry e;
  std::memcpy(&e, b.data() + sizeof(Header) + i * sizeof(SectionEntry), sizeof e);
  return e;
}

void put_entry(std::string* b, uint32_t i, const SectionEntry& e) {
  std::memcpy(&(*b)[sizeof(Header) + i * sizeof(SectionEntry)], &e, sizeof e);
  Header h;
  std::memcpy(&h, b->data(), sizeof h);
  h.table_checksum = XXH3_64bits(b->data() + sizeof(Header), h.section_count * sizeof e);
  h.header_checksum = XXH3_64bits(&h, offsetof(Header, header_checksum));
  std::memcpy(&(*b)[0], &h, sizeof h);
}

std::string load_error(const std::string& bytes) {
  ArchiveReader r;
  std::string error;
  if (!r.open_memory(bytes, "d.pbrta", &error)) return error;
  if (!r.load_sections(2, &error)) return error;
  return "";
}

TEST(DracoSection, ReaderDecodesToTheWritersLayout) {
  const TestMesh m = torus(20, 12);
  const std::vector<uint8_t> stream = encode(m.view(), 14, false);
  DecodedMesh d;
  std::string error;
  ASSERT_TRUE(draco_decode(stream.data(), stream.size(), &d, &error)) << error;
  MeshRecord rec;
  std::vector<uint8_t> raw;
  draco_geometry_section(d, &rec, &raw);
  EXPECT_EQ(rec.num_vertices, 240u);
  EXPECT_EQ(rec.num_triangles, 480u);
  EXPECT_EQ(rec.flags, uint32_t(kMeshNormals | kMeshUV | kMeshFaceIndices));
  EXPECT_EQ(std::memcmp(raw.data() + rec.indices, d.indices.data(), d.indices.size() * 4), 0);

  const std::string bytes = archive_with(raw, stream, "DracoSectionLayout");
  ArchiveReader r;
  ASSERT_TRUE(r.open_memory(bytes, "d.pbrta", &error)) << error;
  ASSERT_TRUE(r.load_sections(2, &error)) << error;
  EXPECT_EQ(r.entry(0).stored_size, stream.size());
  EXPECT_EQ(r.section_size(0), raw.size());
  EXPECT_FALSE(r.in_place(0));
  EXPECT_EQ(std::memcmp(r.section_data(0), raw.data(), raw.size()), 0);
  for (int k = 0; k < 16; ++k) EXPECT_EQ(r.section_data(0)[raw.size() + k], 0);
}

// The geometry section a Draco stream decodes to: what the writer stores as its raw bytes.
std::vector<uint8_t> geometry_of(const std::vector<uint8_t>& stream) {
  DecodedMesh d;
  std::string error;
  EXPECT_TRUE(draco_decode(stream.data(), stream.size(), &d, &error)) << error;
  MeshRecord rec;
  std::vector<uint8_t> bytes;
  draco_geometry_section(d, &rec, &bytes);
  return bytes;
}

// An archive whose section 0 is this Draco stream, laid out as the reader will decode it (its
// raw bytes in *raw when asked).
std::string archive_of_stream(const std::vector<uint8_t>& stream, const std::string& name,
                              std::vector<uint8_t>* raw = nullptr) {
  const std::vector<uint8_t> bytes = geometry_of(stream);
  if (raw != nullptr) *raw = bytes;
  return archive_with(bytes, stream, name);
}

TEST(DracoSection, ReaderRejectsWithMessages) {
  const TestMesh m = torus(20, 12);
  const std::vector<uint8_t> stream = encode(m.view(), 11, true);
  std::vector<uint8_t> raw;
  const std::string good = archive_of_stream(stream, "DracoSectionRejects", &raw);
  EXPECT_EQ(load_error(good), "");

  std::string b = good;
  SectionEntry e = entry_of(b, 0);
  e.count = 2;
  put_entry(&b, 0, e);
  EXPECT_EQ(load_error(b),
            "d.pbrta: section 'geometry' (#0): codec 'draco' is only for a "
            "geometry section of one mesh (this one is kind 17 with count 2)");
  b = good;
  e = entry_of(b, 0);
  e.raw_size += 16;
  put_entry(&b, 0, e);
  EXPECT_EQ(load_error(b),
            "d.pbrta: section 'geometry' (#0): draco: the mesh (240 vertices, "
            "480 triangles) lays out to " +
                std::to_string(raw.size()) + " bytes but the table says " +
                std::to_string(raw.size() + 16));
  // Bytes whose checksum matches but which are no Draco stream (a hostile file).
  b = good;
  e = entry_of(b, 0);
  for (uint64_t k = 0; k < e.stored_size; ++k) b[e.offset + k] = char(k * 7);
  e.checksum = XXH3_64bits(b.data() + e.offset, e.stored_size);
  put_entry(&b, 0, e);
  EXPECT_EQ(load_error(b), "d.pbrta: section 'geometry' (#0): draco: not a Draco stream");
  // The same stream claiming more triangles than raw_size can hold.
  b = good;
  e = entry_of(b, 0);
  e.raw_size = 4000;  // room for 333 triangles, the mesh has 480
  put_entry(&b, 0, e);
  EXPECT_EQ(load_error(b),
            "d.pbrta: section 'geometry' (#0): draco: 480 triangles, more than the limit of 333");
  // Flipped bits in the checksummed stream.
  std::mt19937 rng(11);
  for (int trial = 0; trial < 100; ++trial) {
    b = good;
    e = entry_of(b, 0);
    b[e.offset + rng() % e.stored_size] ^= char(1 << (rng() % 8));
    e.checksum = XXH3_64bits(b.data() + e.offset, e.stored_size);
    put_entry(&b, 0, e);
    const std::string why = load_error(b);
    const std::string prefix = "d.pbrta: section 'geometry' (#0): draco: ";
    if (!why.empty()) {
      EXPECT_EQ(why.compare(0, prefix.size(), prefix), 0) << why;
    }
  }
}

// The uv-only torus's stream; *forged gets a copy with the orientation count forged
// (format/draco_forgery.h).
std::vector<uint8_t> forged_orientation_count(std::vector<uint8_t>* forged) {
  const TestMesh m = torus(8, 8);
  const std::vector<uint8_t> stream = encode(m.view(false, true, false), 14, false);
  *forged = stream;
  EXPECT_TRUE(test_forgery::forge_orientation_count(forged->data(), forged->size(),
                                                    uint32_t(m.P.size() / 3)))
      << "the orientation count is not where this Draco version writes it";
  return stream;
}

// The reader runs Draco in a child process with a budget (format/isolated_jobs.h), so the load
// fails within it, with a message, and this process never runs the loop.
TEST(DracoSection, AForgedStreamIsStoppedByItsBudget) {
  std::vector<uint8_t> forged;
  const std::string good =
      archive_of_stream(forged_orientation_count(&forged), "DracoSectionForged");
  EXPECT_EQ(load_error(good), "");
  std::string b = good;
  SectionEntry e = entry_of(b, 0);
  std::memcpy(&b[e.offset], forged.data(), forged.size());
  e.checksum = XXH3_64bits(b.data() + e.offset, e.stored_size);
  put_entry(&b, 0, e);
  EXPECT_EQ(load_error(b),
            "d.pbrta: section 'geometry' (#0): draco: decoding ran past its budget "
            "of 1 s of CPU time (a forged or damaged stream)");
}

// The section that stops a child is the one reported, though the child would have decoded a
// larger section first were the jobs in schedule order (largest first): there the small sound
// section 0 would be left "not decoded" and reported as the lowest-numbered failure.
TEST(DracoSection, TheSectionThatStopsTheDecoderIsTheOneReported) {
  std::vector<uint8_t> forged;
  const std::vector<uint8_t> stream = forged_orientation_count(&forged);
  const TestMesh small = torus(4, 4);
  const std::vector<uint8_t> sound = encode(small.view(false, false, false), 11, false);
  ASSERT_LT(sound.size(), forged.size());
  ArchiveWriter w;
  for (const std::vector<uint8_t>* s : {&sound, &stream})
    w.add_encoded_section(SectionKind::kGeometry, geometry_of(*s), s == &stream ? forged : *s, 1,
                          Codec::kDraco);
  w.add_section(SectionKind::kStrings, std::vector<uint8_t>(100, 'x'), 1, Codec::kZstd);
  const std::string path = testing_support::scratch_dir("DracoSectionOrder") + "/a.pbrta";
  std::string error;
  ASSERT_TRUE(w.write(path, 0, 3, 1, &error)) << error;
  ArchiveReader r;
  ASSERT_TRUE(r.open(path, &error)) << error;
  EXPECT_FALSE(r.load_sections(1, &error));  // one thread: one child decodes both
  EXPECT_EQ(error, path +
                       ": section 'geometry' (#1): draco: decoding ran past its budget of 1 s "
                       "of CPU time (a forged or damaged stream)");
}

// A mapped file that shrank since it was opened is an error naming the section, found when the
// load starts, before the Draco streams' checksums read the mapping or any child is forked (a
// child reading the cut pages once raised SIGBUS there: "the decoder crashed (signal 7)"). The
// file is over 64 KiB and mostly compressed, so the reader maps it; the cut lies in the stream,
// after the big zstd section.
TEST(DracoSection, AFileThatShrinksAfterOpenIsAnErrorBeforeAnyDecode) {
  const TestMesh m = torus(20, 12);
  const std::vector<uint8_t> stream = encode(m.view(), 14, false);
  std::mt19937 rng(5);
  std::vector<uint8_t> noise(200000);
  for (uint8_t& b : noise) b = uint8_t(rng());
  ArchiveWriter w;
  w.add_section(SectionKind::kStrings, std::vector<uint8_t>(100, 'x'), 1, Codec::kZstd);
  w.add_section(SectionKind::kTexels, noise, 1, Codec::kZstd);
  w.add_encoded_section(SectionKind::kGeometry, geometry_of(stream), stream, 1, Codec::kDraco);
  const std::string path = testing_support::scratch_dir("DracoSectionShrinks") + "/a.pbrta";
  std::string error;
  ASSERT_TRUE(w.write(path, 0, 3, 1, &error)) << error;
  ASSERT_EQ(w.table()[2].codec, uint32_t(Codec::kDraco));
  ArchiveReader r;
  ASSERT_TRUE(r.open(path, &error)) << error;
  ASSERT_EQ(::truncate(path.c_str(), off_t(w.table()[2].offset + 10)), 0);
  EXPECT_FALSE(r.load_sections(2, &error));
  EXPECT_EQ(error, path +
                       ": section 'geometry' (#2): truncated while loading: the file shrank after "
                       "it was opened");
}

// A .drc file a user names goes through the same budget (plymesh, pbrt-mesh): the isolated
// decode gives what draco_decode gives, its messages, and stops the forged stream.
TEST(DracoCodec, IsolatedDecodeMatchesAndIsBounded) {
  const TestMesh m = torus(20, 12);
  for (bool sequential : {false, true}) {
    const std::vector<uint8_t> stream = encode(m.view(), 14, sequential);
    DecodedMesh here, there;
    std::string error;
    ASSERT_TRUE(draco_decode(stream.data(), stream.size(), &here, &error)) << error;
    ASSERT_TRUE(draco_decode_isolated(stream.data(), stream.size(), &there, &error)) << error;
    EXPECT_EQ(there.positions, here.positions);
    EXPECT_EQ(there.normals, here.normals);
    EXPECT_EQ(there.uv, here.uv);
    EXPECT_EQ(there.indices, here.indices);
    EXPECT_EQ(there.face_indices, here.face_indices);
  }
  const std::vector<uint8_t> garbage(300, 7);
  DecodedMesh d;
  std::string here_error, there_error;
  EXPECT_FALSE(draco_decode(garbage.data(), garbage.size(), &d, &here_error));
  EXPECT_FALSE(draco_decode_isolated(garbage.data(), garbage.size(), &d, &there_error));
  EXPECT_EQ(there_error, here_error);
  EXPECT_EQ(d.num_vertices(), 0u);

  std::vector<uint8_t> forged;
  forged_orientation_count(&forged);
  std::string error;
  EXPECT_FALSE(draco_decode_isolated(forged.data(), forged.size(), &d, &error));
  EXPECT_EQ(error,
            "draco: decoding ran past its budget of 1 s of CPU time (a forged or damaged stream)");
}

TEST(DracoSection, WriterNeedsAnEncodedGeometrySectionOfOneMesh) {
  ArchiveWriter w;
  w.add_section(SectionKind::kGeometry, std::vector<uint8_t>(64, 0), 1, Codec::kDraco);
  std::string error;
  const std::string path = testing_support::scratch_dir("DracoSectionWriter") + "/w.pbrta";
  EXPECT_FALSE(w.write(path, 0, 3, 1, &error));
  EXPECT_EQ(error, "cannot write '" + path +
                       "': section 'geometry' (#0): codec 'draco' needs a "
                       "geometry section of one mesh, encoded by the caller");
}

}  // namespace
}  // namespace pbrta
