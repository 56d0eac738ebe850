// tests/compiler/ply_reader_test.cpp — the PLY reader on small files built in memory (every format,
// spelling and face shape it accepts, and the malformed inputs it must refuse without crashing),
// plus every PLY file of the shared corpus.
#include "compiler/ply_reader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "test_support.h"

namespace pbrtc {
namespace {

// ---------------------------------------------------------------------------------------------
// PlyBuilder: writes a PLY header and a body in any of the three formats. Values are given with
// their PLY type name so one test body can emit ascii, little- and big-endian files alike.

class PlyBuilder {
 public:
  explicit PlyBuilder(std::string format) : format_(std::move(format)) {}

  PlyBuilder& header_line(const std::string& text) {
    header_ += text + "\n";
    return *this;
  }
  PlyBuilder& element(const std::string& name, uint64_t count) {
    return header_line("element " + name + " " + std::to_string(count));
  }
  PlyBuilder& property(const std::string& type, const std::string& name) {
    return header_line("property " + type + " " + name);
  }
  PlyBuilder& list(const std::string& count_type, const std::string& type,
                   const std::string& name) {
    return header_line("property list " + count_type + " " + type + " " + name);
  }

  // Appends one value of the named PLY type.
  PlyBuilder& value(const std::string& type, double v) {
    if (format_ == "ascii") {
      char text[64];
      if (type == "float" || type == "float32" || type == "double" || type == "float64") {
        std::snprintf(text, sizeof(text), "%.9g ", v);
      } else {
        std::snprintf(text, sizeof(text), "%lld ", static_cast<long long>(v));
      }
      body_ += text;
      return *this;
    }
    if (type == "char" || type == "int8") return put(static_cast<int8_t>(v));
    if (type == "uchar" || type == "uint8") return put(static_cast<uint8_t>(v));
    if (type == "short" || type == "int16") return put(static_cast<int16_t>(v));
    if (type == "ushort" || type == "uint16") return put(static_cast<uint16_t>(v));
    if (type == "int" || type == "int32") return put(static_cast<int32_t>(v));
    if (type == "uint" || type == "uint32") return put(static_cast<uint32_t>(v));
    if (type == "float" || type == "float32") return put(static_cast<float>(v));
    if (type == "double" || type == "float64") return put(v);
    ADD_FAILURE() << "unknown type " << type;
    return *this;
  }
  PlyBuilder& values(const std::string& type, std::initializer_list<double> vs) {
    for (double v : vs) value(type, v);
    return *this;
  }
  // A list: its count, then its values.
  PlyBuilder& list_values(const std::string& count_type, const std::string& type,
                          std::initializer_list<double> vs) {
    value(count_type, static_cast<double>(vs.size()));
    return values(type, vs);
  }
  // Ends a record (a line break in ascii; nothing in binary).
  PlyBuilder& end_record() {
    if (format_ == "ascii") body_ += "\n";
    return *this;
  }
  PlyBuilder& raw(const std::string& bytes) {
    body_ += bytes;
    return *this;
  }

  std::string str() const {
    return "ply\nformat " + format_ + " 1.0\n" + header_ + "end_header\n" + body_;
  }
  size_t body_size() const { return body_.size(); }

 private:
  template <typename T>
  PlyBuilder& put(T v) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &v, sizeof(T));
    if (format_ == "binary_big_endian") std::reverse(bytes, bytes + sizeof(T));
    body_.append(bytes, sizeof(T));
    return *this;
  }

  std::string format_;
  std::string header_;
  std::string body_;
};

const std::vector<std::string> kFormats = {"ascii", "binary_little_endian", "binary_big_endian"};

// A unit square (4 vertices) with the given face lists, in one format.
std::string square_with_faces(const std::string& format,
                              const std::vector<std::vector<double>>& faces) {
  PlyBuilder b(format);
  b.element("vertex", 4).property("float", "x").property("float", "y").property("float", "z");
  b.element("face", faces.size()).list("uchar", "int", "vertex_indices");
  b.values("float", {0, 0, 0}).end_record();
  b.values("float", {1, 0, 0}).end_record();
  b.values("float", {1, 1, 0}).end_record();
  b.values("float", {0, 1, 0}).end_record();
  for (const std::vector<double>& face : faces) {
    b.value("uchar", static_cast<double>(face.size()));
    for (double index : face) b.value("int", index);
    b.end_record();
  }
  return b.str();
}

// A richer mesh used for truncation and fuzzing: normals, uvs, face_indices, an unknown element,
// an unknown list in each element, a triangle, a quad and a pentagon.
std::string rich_mesh(const std::string& format) {
  PlyBuilder b(format);
  b.header_line("comment made by ply_reader_test");
  b.element("material", 2).property("uchar", "red").list("uchar", "float", "weights");
  b.element("vertex", 5)
      .property("float", "x")
      .property("float", "y")
      .property("float", "z")
      .list("ushort", "double", "extra")
      .property("float", "nx")
      .property("float", "ny")
      .property("float", "nz")
      .property("double", "u")
      .property("double", "v");
  b.element("face", 3)
      .property("int", "face_indices")
      .list("uchar", "uint", "vertex_indices")
      .list("int", "short", "corner_ids");
  b.value("uchar", 200).list_values("uchar", "float", {0.5, 0.25}).end_record();
  b.value("uchar", 7).list_values("uchar", "float", {}).end_record();
  for (int i = 0; i < 5; ++i) {
    b.values("float", {double(i), double(i * 2), double(i * 3)});
    b.list_values("ushort", "double", {1.5, 2.5, 3.5});
    b.values("float", {0, 0, 1}).values("double", {i * 0.25, 1 - i * 0.25}).end_record();
  }
  b.value("int", 10).list_values("uchar", "uint", {0, 1, 2}).list_values("int", "short", {9});
  b.end_record();
  b.value("int", 11).list_values("uchar", "uint", {0, 1, 2, 3});
  b.list_values("int", "short", {}).end_record();
  b.value("int", -12).list_values("uchar", "uint", {0, 1, 2, 3, 4});
  b.list_values("int", "short", {1, 2}).end_record();
  return b.str();
}

PlyMesh parse_ok(const std::string& bytes) {
  PlyMesh mesh;
  PlyError error;
  EXPECT_TRUE(parse_ply(bytes, &mesh, &error)) << error.message;
  return mesh;
}

std::string parse_error(const std::string& bytes) {
  PlyMesh mesh;
  PlyError error;
  EXPECT_FALSE(parse_ply(bytes, &mesh, &error)) << "parsed but should not have";
  EXPECT_TRUE(mesh.positions.empty() && mesh.indices.empty()) << "failed parse left data";
  return error.message;
}

std::vector<uint32_t> u32(std::initializer_list<uint32_t> v) {
  return v;
}

// ---------------------------------------------------------------------------------------------
// What it reads

TEST(PlyReader, ReadsAsciiTriangle) {
  const PlyMesh mesh = parse_ok(square_with_faces("ascii", {{0, 1, 2}}));
  EXPECT_EQ(mesh.num_vertices(), 4u);
  EXPECT_EQ(mesh.num_triangles(), 1u);
  EXPECT_EQ(mesh.positions, (std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}));
  EXPECT_EQ(mesh.indices, u32({0, 1, 2}));
  EXPECT_TRUE(mesh.normals.empty());
  EXPECT_TRUE(mesh.uvs.empty());
  EXPECT_TRUE(mesh.face_indices.empty());
}

TEST(PlyReader, ReadsTheSameMeshFromEveryFormat) {
  for (const std::string& format : kFormats) {
    SCOPED_TRACE(format);
    const PlyMesh mesh = parse_ok(rich_mesh(format));
    ASSERT_EQ(mesh.num_vertices(), 5u);
    EXPECT_EQ(mesh.positions[3 * 4 + 0], 4.0f);
    EXPECT_EQ(mesh.positions[3 * 4 + 1], 8.0f);
    EXPECT_EQ(mesh.positions[3 * 4 + 2], 12.0f);
    ASSERT_EQ(mesh.normals.size(), 15u);
    EXPECT_EQ(mesh.normals[3 * 2 + 2], 1.0f);
    ASSERT_EQ(mesh.uvs.size(), 10u);
    EXPECT_EQ(mesh.uvs[2 * 3 + 0], 0.75f);
    EXPECT_EQ(mesh.uvs[2 * 3 + 1], 0.25f);
    // Triangle, pbrt-v3's quad split, then the pentagon's fan.
    EXPECT_EQ(mesh.indices, u32({0, 1, 2, 0, 1, 2, 3, 0, 2, 0, 1, 2, 0, 2, 3, 0, 3, 4}));
    EXPECT_EQ(mesh.face_indices, (std::vector<int32_t>{10, 11, 11, -12, -12, -12}));
  }
}

TEST(PlyReader, ReadsBinaryBigEndianQuadsAsPbrtSplitsThem) {
  // pbrt-v3's plymesh turns quad (f0 f1 f2 f3) into (f0 f1 f2) and (f3 f0 f2).
  const PlyMesh mesh =
      parse_ok(square_with_faces("binary_big_endian", {{0, 1, 2, 3}, {3, 2, 1, 0}}));
  EXPECT_EQ(mesh.indices, u32({0, 1, 2, 3, 0, 2, 3, 2, 1, 0, 3, 1}));
  EXPECT_EQ(mesh.positions[3 * 2 + 1], 1.0f);
}

TEST(PlyReader, SplitsQuadsTheSameWayInEveryFormat) {
  for (const std::string& format : kFormats) {
    SCOPED_TRACE(format);
    const PlyMesh mesh = parse_ok(square_with_faces(format, {{0, 1, 2, 3}}));
    EXPECT_EQ(mesh.indices, u32({0, 1, 2, 3, 0, 2}));
  }
}

TEST(PlyReader, FanTriangulatesPolygonsThatPbrtWouldDrop) {
  const PlyMesh mesh =
      parse_ok(square_with_faces("binary_little_endian", {{3, 2, 1, 0, 1}, {0, 1, 2, 3, 0, 1}}));
  EXPECT_EQ(mesh.indices, u32({3, 2, 1, 3, 1, 0, 3, 0, 1,              // pentagon: 3 triangles
                               0, 1, 2, 0, 2, 3, 0, 3, 0, 0, 0, 1}));  // hexagon: 4
}

TEST(PlyReader, RepeatsFaceIndicesForEveryTriangleOfAFace) {
  for (const std::string& format : kFormats) {
    SCOPED_TRACE(format);
    PlyBuilder b(format);
    b.element("vertex", 4).property("float", "x").property("float", "y").property("float", "z");
    // face_indices after the list, and of a small type, to show neither matters.
    b.element("face", 2)
        .list("uint8", "uint16", "vertex_indices")
        .property("short", "face_indices");
    for (int i = 0; i < 4; ++i) b.values("float", {double(i), 0, 0}).end_record();
    b.list_values("uint8", "uint16", {0, 1, 2, 3}).value("short", 7).end_record();
    b.list_values("uint8", "uint16", {1, 2, 3}).value("short", -3).end_record();
    const PlyMesh mesh = parse_ok(b.str());
    EXPECT_EQ(mesh.face_indices, (std::vector<int32_t>{7, 7, -3}));
    EXPECT_EQ(mesh.num_triangles(), 3u);
  }
}

TEST(PlyReader, ReadsNormals) {
  for (const std::string& format : kFormats) {
    SCOPED_TRACE(format);
    PlyBuilder b(format);
    // Normals before positions: property order within a record is free.
    b.element("vertex", 3).property("float", "nx").property("float", "ny").property("float", "nz");
    b.property("float", "x").property("float", "y").property("float", "z");
    b.element("face", 1).list("uchar", "int", "vertex_indices");
    b.values("float", {0, 0, 1, 0, 0, 0}).end_record();
    b.values("float", {0, 1, 0, 1, 0, 0}).end_record();
    b.values("float", {1, 0, 0, 0, 1, 0}).end_record();
    b.list_values("uchar", "int", {0, 1, 2}).end_record();
    const PlyMesh mesh = parse_ok(b.str());
    EXPECT_EQ(mesh.normals, (std::vector<float>{0, 0, 1, 0, 1, 0, 1, 0, 0}));
    EXPECT_EQ(mesh.positions, (std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0}));
  }
}

TEST(PlyReader, AcceptsEveryUvSpellingPbrtAccepts) {
  const std::vector<std::pair<std::string, std::string>> spellings = {
      {"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}, {"texture_s", "texture_t"}};
  for (const std::string& format : kFormats) {
    for (const auto& [u, v] : spellings) {
      SCOPED_TRACE(format + " " + u + "/" + v);
      PlyBuilder b(format);
      b.element("vertex", 3).property("float", "x").property("float", "y").property("float", "z");
      b.property("float", u).property("float", v);
      b.element("face", 1).list("uchar", "int", "vertex_indices");
      for (int i = 0; i < 3; ++i) {
        b.values("float", {double(i), double(i), 0, 0.5 * i, 1 - 0.5 * i}).end_record();
      }
      b.list_values("uchar", "int", {0, 1, 2}).end_record();
      const PlyMesh mesh = parse_ok(b.str());
      EXPECT_EQ(mesh.uvs, (std::vector<float>{0, 1, 0.5f, 0.5f, 1, 0}));
    }
  }
}

TEST(PlyReader, PrefersUvSpellingsInPbrtOrder) {
  PlyBuilder b("ascii");
  b.element("vertex", 3).property("float", "x").property("float", "y").property("float", "z");
  b.property("float", "s").property("float", "t").property("float", "u").property("float", "v");
  b.element("face", 1).list("uchar", "int", "vertex_indices");
  for (int i = 0; i < 3; ++i) b.values("float", {double(i), 0, 0, 9, 9, 1, 2}).end_record();
  b.list_values("uchar", "int", {0, 1, 2}).end_record();
  const PlyMesh mesh = parse_ok(b.str());
  EXPECT_EQ(mesh.uvs, (std::vector<float>{1, 2, 1, 2, 1, 2}));  // u/v wins over s/t
}

TEST(PlyReader, AcceptsEveryScalarTypeSpelling) {
  const std::vector<std::string> all = {"char",   "int8",    "uchar",  "uint8",  "short", "int16",
                                        "ushort", "uint16",  "int",    "int32",  "uint",  "uint32",
                                        "float",  "float32", "double", "float64"};
  // The first 12 spellings are integers: those also serve as list count and index types.
  const auto is_integer_name = [&](const std::string& type) {
    return std::find(all.begin(), all.begin() + 12, type) != all.begin() + 12;
  };
  for (const std::string& format : kFormats) {
    for (const std::string& type : all) {
      SCOPED_TRACE(format + " " + type);
      const std::string count_type = is_integer_name(type) ? type : std::string("uchar");
      const std::string index_type = count_type;
      PlyBuilder b(format);
      b.element("vertex", 3).property(type, "x").property(type, "y").property(type, "z");
      b.element("face", 1).list(count_type, index_type, "vertex_indices");
      b.values(type, {0, 0, 0}).end_record();
      b.values(type, {100, 0, 0}).end_record();
      b.values(type, {0, 100, 0}).end_record();
      b.list_values(count_type, index_type, {2, 1, 0}).end_record();
      const PlyMesh mesh = parse_ok(b.str());
      EXPECT_EQ(mesh.positions, (std::vector<float>{0, 0, 0, 100, 0, 0, 0, 100, 0}));
      EXPECT_EQ(mesh.indices, u32({2, 1, 0}));
    }
  }
}

TEST(PlyReader, AcceptsVertexIndexAsTheFaceListName) {
  PlyBuilder b("binary_little_endian");
  b.element("vertex", 3).property("float", "x").property("float", "y").property("float", "z");
  b.element("face", 1).list("uchar", "uint", "vertex_index");
  for (int i = 0; i < 3; ++i) b.values("float", {double(i), 0, 0});
  b.list_values("uchar", "uint", {0, 2, 1});
  EXPECT_EQ(parse_ok(b.str()).indices, u32({0, 2, 1}));
}

TEST(PlyReader, SkipsUnknownElementsAndListPropertiesInEveryFormat) {
  for (const std::string& format : kFormats) {
    SCOPED_TRACE(format);
    PlyBuilder b(format);
    b.element("camera", 1).property("double", "fov").list("int", "uchar", "name");
    b.element("vertex", 3)
        .list("uint", "int", "neighbours")
        .property("float", "x")
        .property("uchar", "red")
        .property("float", "y")
        .property("float", "z")
        .list("uchar", "double", "weights");
    b.element("edge", 2).property("int", "a").property("int", "b");
    b.element("face", 1)
        .list("short", "float", "corner_uvs")
        .list("uchar", "int", "vertex_indices")
        .property("float", "area");
    b.element("empty", 0).property("float", "w");
    b.element("nothing", 5);  // no properties: occupies no bytes
    b.element("trailer", 1).list("uchar", "uchar", "bytes");
    b.value("double", 45).list_values("int", "uchar", {104, 105}).end_record();
    for (int i = 0; i < 3; ++i) {
      b.list_values("uint", "int", {1, 2}).value("float", i).value("uchar", 255);
      b.values("float", {double(-i), 0.5}).list_values("uchar", "double", {}).end_record();
    }
    b.values("int", {0, 1}).end_record().values("int", {1, 2}).end_record();
    b.list_values("short", "float", {0, 0, 1, 0, 1, 1}).list_values("uchar", "int", {0, 1, 2});
    b.value("float", 0.5).end_record();
    b.list_values("uchar", "uchar", {1, 2, 3}).end_record();
    const PlyMesh mesh = parse_ok(b.str());
    EXPECT_EQ(mesh.positions, (std::vector<float>{0, 0, 0.5f, 1, -1, 0.5f, 2, -2, 0.5f}));
    EXPECT_EQ(mesh.indices, u32({0, 1, 2}));
  }
}

TEST(PlyReader, ReadsFacesThatComeBeforeVertices) {
  for (const std::string& format : kFormats) {
    SCOPED_TRACE(format);
    PlyBuilder b(format);
    b.element("face", 1).list("uchar", "int", "vertex_indices");
    b.element("vertex", 3).property("float", "x").property("float", "y").property("float", "z");
    b.list_values("uchar", "int", {2, 0, 1}).end_record();
    for (int i = 0; i < 3; ++i) b.values("float", {double(i), 1, 2}).end_record();
    const PlyMesh mesh = parse_ok(b.str());
    EXPECT_EQ(mesh.indices, u32({2, 0, 1}));
    EXPECT_EQ(mesh.positions[6], 2.0f);
  }
}

TEST(PlyReader, AcceptsCommentsObjInfoAndCrlfHeaderLines) {
  const std::string text =
      "ply\r\nformat binary_little_endian 1.0\r\ncomment exported\r\nobj_info 42 things\r\n"
      "element vertex 3\r\nproperty float x\r\nproperty float y\r\nproperty float z\r\n"
      "comment between\r\nelement face 1\r\nproperty list uchar int vertex_indices\r\n"
      "end_header\r\n";
  PlyBuilder body("binary_little_endian");
  for (int i = 0; i < 3; ++i) body.values("float", {double(i), 0, 0});
  body.list_values("uchar", "int", {0, 1, 2});
  // The body alone: str() minus the header it writes.
  const std::string full = body.str();
  const std::string bytes = text + full.substr(full.size() - body.body_size());
  const PlyMesh mesh = parse_ok(bytes);
  EXPECT_EQ(mesh.positions[3], 1.0f);
  EXPECT_EQ(mesh.indices, u32({0, 1, 2}));
}

// Blender 2.4's exporter wrote "Created by Blender3D 247 - www.blender.org, source file: ..."
// without the comment keyword. A line that is not format, element, property or end_header cannot
// change the layout: it is skipped, with a warning naming its line (quoted up to 40 bytes).
TEST(PlyReader, SkipsHeaderLinesThatAreNoKeywordWithAWarningEach) {
  const std::string long_line = "Exported " + std::string(80, 'x');
  const std::string text =
      "ply\nformat ascii 1.0\nCreated by Blender3D 247 - www.blender.org\n"
      "element vertex 3\nproperty float x\nproperty float y\n"
      "property float z\n" +
      long_line +
      "\nelement face 1\nproperty list uchar int vertex_indices\n"
      "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  PlyMesh mesh;
  PlyError error;
  std::vector<std::string> warnings{"kept"};
  ASSERT_TRUE(parse_ply(text, &mesh, &error, &warnings)) << error.message;
  EXPECT_EQ(mesh.indices, u32({0, 1, 2}));
  EXPECT_EQ(warnings,
            (std::vector<std::string>{
                "kept",
                "header line 3: skipped 'Created by Blender3D 247 - www.blender.o...' (not a PLY "
                "header keyword)",
                "header line 8: skipped '" + long_line.substr(0, 40) +
                    "...' (not a PLY header keyword)"}));
  // Without a list to append to, the same file reads the same.
  EXPECT_EQ(parse_ok(text).indices, u32({0, 1, 2}));
  // A failed parse says nothing but its error.
  warnings.clear();
  EXPECT_FALSE(parse_ply(text.substr(0, text.size() - 4), &mesh, &error, &warnings));
  EXPECT_TRUE(warnings.empty());
  // Lines that do shape the layout are still checked: a skipped line never hides a bad one.
  EXPECT_EQ(parse_error("ply\nformat ascii 1.0\nelephant 3\nelement vertex 1\nproperty flot x\n"
                        "end_header\n"),
            "header line 5: unknown type 'flot'");
}

TEST(PlyReader, AcceptsAsciiNumbersInAnyLayoutAndSpelling) {
  // Records split and joined across lines, tabs, CRLF, a leading '+', exponents.
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty double y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "+1.5 -2e1\t.25\r\n0 0\n0 1E0 1. 0 3 0 1 +2";
  const PlyMesh mesh = parse_ok(text);
  EXPECT_EQ(mesh.positions, (std::vector<float>{1.5f, -20, 0.25f, 0, 0, 0, 1, 1, 0}));
  EXPECT_EQ(mesh.indices, u32({0, 1, 2}));
}

TEST(PlyReader, NarrowsAsciiDoublesToFloatLikePbrt) {
  // pbrt-v3 reads ascii values as double and narrows to float; check a value whose double
  // rounding is observable: it must equal (float)(double)text.
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0.1 1.00000005960464477539062499 3.4028234663852886e38 0 0 0 0 0 0 3 0 1 2\n";
  const PlyMesh mesh = parse_ok(text);
  EXPECT_EQ(mesh.positions[0], static_cast<float>(0.1));
  EXPECT_EQ(mesh.positions[1], static_cast<float>(1.00000005960464477539062499));
  EXPECT_EQ(mesh.positions[2], std::numeric_limits<float>::max());
}

TEST(PlyReader, ReadsAFileFromDisk) {
  const std::string dir = testing_support::scratch_dir("PlyReader.ReadsAFileFromDisk");
  const std::string path = testing_support::write_file(
      dir + "/quad.ply", square_with_faces("binary_little_endian", {{0, 1, 2, 3}}));
  PlyMesh mesh;
  PlyError error;
  ASSERT_TRUE(read_ply(path, &mesh, &error)) << error.message;
  EXPECT_EQ(mesh.num_triangles(), 2u);
}

TEST(PlyReader, ReportsAMissingFile) {
  PlyMesh mesh;
  PlyError error;
  EXPECT_FALSE(read_ply("/nonexistent/dir/mesh.ply", &mesh, &error));
  EXPECT_NE(error.message.find("cannot open file"), std::string::npos) << error.message;
  EXPECT_FALSE(read_ply(testing_support::shared_dir(), &mesh, &error));
  EXPECT_NE(error.message.find("not a regular file"), std::string::npos) << error.message;
}

// ---------------------------------------------------------------------------------------------
// What it refuses

TEST(PlyReader, RejectsEmptyInput) {
  EXPECT_EQ(parse_error(""), "empty input");
}

TEST(PlyReader, RejectsMissingMagic) {
  EXPECT_EQ(parse_error("format ascii 1.0\n"), "missing \"ply\" magic at start of file");
  EXPECT_EQ(parse_error("pl"), "missing \"ply\" magic at start of file");
  EXPECT_EQ(parse_error("plyx\nformat ascii 1.0\n"), "header line 1: expected \"ply\", got 'plyx'");
}

TEST(PlyReader, RejectsUnknownFormatAndVersion) {
  EXPECT_EQ(parse_error("ply\nformat binary_middle_endian 1.0\nend_header\n"),
            "header line 2: unknown format 'binary_middle_endian'");
  EXPECT_EQ(parse_error("ply\nformat ascii 2.0\nend_header\n"),
            "header line 2: unsupported PLY version '2.0'");
  EXPECT_EQ(parse_error("ply\nelement vertex 0\nend_header\n"), "header: no format line");
}

TEST(PlyReader, RejectsMissingEndHeader) {
  const std::string text = square_with_faces("ascii", {{0, 1, 2}});
  const std::string no_end = text.substr(0, text.find("end_header"));
  EXPECT_EQ(parse_error(no_end), "header: missing end_header (input ends after line 8)");
}

TEST(PlyReader, RejectsTheHeaderCutAnywhere) {
  const std::string text = square_with_faces("binary_little_endian", {{0, 1, 2}});
  const size_t header_end = text.find("end_header");
  for (size_t cut = 0; cut < header_end; ++cut) {
    SCOPED_TRACE(cut);
    const std::string message = parse_error(text.substr(0, cut));
    EXPECT_FALSE(message.empty());
  }
}

TEST(PlyReader, RejectsMalformedHeaderLines) {
  const std::string start = "ply\nformat ascii 1.0\n";
  EXPECT_EQ(parse_error(start + "property float x\nend_header\n"),
            "header line 3: property before any element");
  EXPECT_EQ(parse_error(start + "element vertex -3\nend_header\n"),
            "header line 3: element count '-3' is not a non-negative integer");
  EXPECT_EQ(parse_error(start + "element vertex 99999999999999999999999\nend_header\n"),
            "header line 3: element count '99999999999999999999999' is too large");
  EXPECT_EQ(parse_error(start + "element vertex 3\nproperty quad x\nend_header\n"),
            "header line 4: unknown type 'quad'");
  EXPECT_EQ(parse_error(start + "element face 3\nproperty list float int v\nend_header\n"),
            "header line 4: list count type 'float' is not an integer type");
  EXPECT_EQ(parse_error(start + "element vertex 1\nelement vertex 1\nend_header\n"),
            "header line 4: second vertex element");
}

TEST(PlyReader, RejectsAHeaderLineLongerThan64KiB) {
  const std::string text = "ply\nformat ascii 1.0\ncomment " + std::string(70000, 'a') + "\n";
  EXPECT_EQ(parse_error(text), "header line 3: longer than 65536 bytes");
  // Also when the line never ends (a binary blob where a header should be).
  EXPECT_EQ(parse_error("ply\n" + std::string(200000, 'b')),
            "header line 2: longer than 65536 bytes");
}

TEST(PlyReader, RejectsMissingVertexOrFaceData) {
  const std::string start = "ply\nformat binary_little_endian 1.0\n";
  EXPECT_EQ(parse_error(start + "element face 0\nend_header\n"), "header: no vertex element");
  EXPECT_EQ(parse_error(start + "element vertex 1\nproperty float x\nproperty float y\n"
                                "property float z\nend_header\n0000"),
            "header: no face element");
  EXPECT_EQ(parse_error(start + "element vertex 1\nproperty float x\nproperty float z\n"
                                "element face 1\nproperty list uchar int vertex_indices\n"
                                "end_header\n"),
            "header: vertex element has no 'y' property");
  EXPECT_EQ(parse_error(start + "element vertex 0\nproperty float x\nproperty float y\n"
                                "property float z\nelement face 1\n"
                                "property list uchar int vertex_indices\nend_header\n"),
            "header: vertex count is 0");
  EXPECT_EQ(parse_error(start + "element vertex 1\nproperty float x\nproperty float y\n"
                                "property float z\nelement face 1\nproperty int vertex_indices\n"
                                "end_header\n"),
            "header: face property 'vertex_indices' is not a list of integers");
}

TEST(PlyReader, RejectsPartialNormalsAndUvs) {
  PlyBuilder normals("ascii");
  normals.element("vertex", 3).property("float", "x").property("float", "y");
  normals.property("float", "z").property("float", "nx").property("float", "nz");
  normals.element("face", 1).list("uchar", "int", "vertex_indices");
  EXPECT_EQ(parse_error(normals.str()), "header: vertex has 'nz' but no 'ny'");

  PlyBuilder uvs("ascii");
  uvs.element("vertex", 3).property("float", "x").property("float", "y");
  uvs.property("float", "z").property("float", "texture_u");
  uvs.element("face", 1).list("uchar", "int", "vertex_indices");
  EXPECT_EQ(parse_error(uvs.str()), "header: vertex has 'texture_u' but no 'texture_v'");
}

TEST(PlyReader, RejectsTruncatedBinaryDataAtEveryCutPoint) {
  for (const std::string format : {"binary_little_endian", "binary_big_endian"}) {
    SCOPED_TRACE(format);
    const std::string text = rich_mesh(format);
    const size_t data_begin = text.find("end_header\n") + 11;
    ASSERT_TRUE(parse_ok(text).num_triangles() == 6);
    for (size_t cut = data_begin; cut < text.size(); ++cut) {
      SCOPED_TRACE(cut);
      const std::string message = parse_error(text.substr(0, cut));
      EXPECT_TRUE(message.find("unexpected end of data") != std::string::npos ||
                  message.find("exceeds what the file can hold") != std::string::npos)
          << message;
    }
  }
}

TEST(PlyReader, RejectsTruncatedAsciiData) {
  const std::string text = rich_mesh("ascii");
  const size_t data_begin = text.find("end_header\n") + 11;
  // Any cut that removes a whole value fails; a cut inside the last value may still parse.
  const size_t last_value = text.find_last_of(" \n", text.size() - 3);
  for (size_t cut = data_begin; cut <= last_value; cut += 3) {
    SCOPED_TRACE(cut);
    EXPECT_FALSE(parse_error(text.substr(0, cut)).empty());
  }
  const std::string small = square_with_faces("ascii", {{0, 1, 2}});
  const size_t cut = small.size() - 3;  // inside the face, after "3 0 1"
  EXPECT_EQ(parse_error(small.substr(0, cut)),
            "face 0: unexpected end of data at byte " + std::to_string(cut));
}

TEST(PlyReader, FailsFastWhenAVertexCountLies) {
  PlyBuilder b("binary_little_endian");
  b.element("vertex", 1000000000).property("float", "x").property("float", "y");
  b.property("float", "z").element("face", 1).list("uchar", "int", "vertex_indices");
  for (int i = 0; i < 3; ++i) b.values("float", {0, 0, 0});
  b.list_values("uchar", "int", {0, 1, 2});
  const std::string text = b.str();
  ASSERT_LT(text.size(), 250u);
  const auto start = std::chrono::steady_clock::now();
  const std::string message = parse_error(text);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(message,
            "header: vertex count 1000000000 exceeds what the file can hold (49 bytes "
            "left)");
  EXPECT_LT(seconds, 0.5);  // no allocation or loop sized by the lie
}

TEST(PlyReader, FailsFastWhenCountsLieInAscii) {
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 4000000000\nproperty list uchar int vertex_indices\n"
      "end_header\n0 0 0 1 0 0 0 1 0 3 0 1 2\n";
  EXPECT_EQ(parse_error(text),
            "header: face count 4000000000 exceeds what the file can hold (8 bytes left)");
  const std::string max_count =
      "ply\nformat binary_little_endian 1.0\nelement junk 18446744073709551615\n"
      "property double d\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  EXPECT_EQ(parse_error(max_count),
            "header: junk count 18446744073709551615 exceeds what the file can hold (0 bytes "
            "left)");
}

TEST(PlyReader, RejectsListCountsThatLie) {
  for (const std::string& format : kFormats) {
    SCOPED_TRACE(format);
    PlyBuilder b(format);
    b.element("vertex", 3).property("float", "x").property("float", "y").property("float", "z");
    b.list("uint", "uchar", "junk");
    b.element("face", 1).list("uint", "int", "vertex_indices");
    for (int i = 0; i < 3; ++i) b.values("float", {0, 0, 0}).list_values("uint", "uchar", {});
    b.value("uint", 4000000000.0).values("int", {0, 1, 2}).end_record();
    EXPECT_NE(parse_error(b.str()).find("face 0: list 'vertex_indices' count 4000000000 exceeds"
                                        " what the file can hold"),
              std::string::npos);
  }
  PlyBuilder junk("binary_little_endian");
  junk.element("vertex", 3).property("float", "x").property("float", "y").property("float", "z");
  junk.list("int", "double", "junk");
  junk.element("face", 1).list("uchar", "int", "vertex_indices");
  junk.values("float", {0, 0, 0}).value("int", 100000);
  for (int i = 0; i < 12; ++i) junk.value("int", 0);  // enough for the header's check
  EXPECT_EQ(parse_error(junk.str()),
            "vertex 0: list 'junk' count 100000 exceeds what the file can hold (48 bytes left)");
  PlyBuilder negative("binary_big_endian");
  negative.element("vertex", 3).property("float", "x").property("float", "y");
  negative.property("float", "z").list("int", "double", "junk");
  negative.element("face", 1).list("uchar", "int", "vertex_indices");
  negative.values("float", {0, 0, 0}).value("int", -5);
  for (int i = 0; i < 12; ++i) negative.value("int", 0);
  EXPECT_EQ(parse_error(negative.str()), "vertex 0: list 'junk' has negative count -5");
}

TEST(PlyReader, RejectsNanAndInfiniteValues) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  struct Case {
    int property;  // 0..7: x y z nx ny nz u v
    double value;
    std::string message;
  };
  const std::vector<Case> cases = {
      {1, nan, "vertex 1: coordinate is NaN"},
      {2, -inf, "vertex 1: coordinate is infinite"},
      {4, inf, "vertex 1: normal is infinite"},
      {6, nan, "vertex 1: texture coordinate is NaN"},
      {0, 1e300, "vertex 1: coordinate is out of float range"},
  };
  for (const std::string& format : kFormats) {
    for (const Case& c : cases) {
      SCOPED_TRACE(format + " " + c.message);
      PlyBuilder b(format);
      b.element("vertex", 3);
      for (const char* name : {"x", "y", "z", "nx", "ny", "nz", "u", "v"}) {
        b.property("double", name);
      }
      b.element("face", 1).list("uchar", "int", "vertex_indices");
      for (int v = 0; v < 3; ++v) {
        for (int p = 0; p < 8; ++p) b.value("double", v == 1 && p == c.property ? c.value : 0.5);
        b.end_record();
      }
      b.list_values("uchar", "int", {0, 1, 2}).end_record();
      EXPECT_EQ(parse_error(b.str()), c.message);
    }
  }
}

TEST(PlyReader, RejectsOutOfRangeAndNegativeIndices) {
  for (const std::string& format : kFormats) {
    SCOPED_TRACE(format);
    EXPECT_EQ(parse_error(square_with_faces(format, {{0, 1, 2}, {0, 1, 2}, {0, 4, 2}})),
              "face 2: index 4 out of range (4 vertices)");
    EXPECT_EQ(parse_error(square_with_faces(format, {{0, 1, 2, -1}})),
              "face 0: index -1 out of range (4 vertices)");
  }
  // An unsigned index too large for int32 is still just out of range.
  PlyBuilder b("binary_little_endian");
  b.element("vertex", 3).property("float", "x").property("float", "y").property("float", "z");
  b.element("face", 1).list("uchar", "uint", "vertex_indices");
  for (int i = 0; i < 3; ++i) b.values("float", {0, 0, 0});
  b.list_values("uchar", "uint", {0, 1, 4294967295.0});
  EXPECT_EQ(parse_error(b.str()), "face 0: index 4294967295 out of range (3 vertices)");
}

TEST(PlyReader, RejectsFacesWithFewerThanThreeVertices) {
  for (const std::string& format : kFormats) {
    SCOPED_TRACE(format);
    EXPECT_EQ(parse_error(square_with_faces(format, {{0, 1, 2}, {0, 1}})), "face 1 has 2 vertices");
    EXPECT_EQ(parse_error(square_with_faces(format, {{}})), "face 0 has 0 vertices");
  }
}

TEST(PlyReader, RejectsAsciiTokensThatAreNotNumbers) {
  const std::string start =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  EXPECT_EQ(parse_error(start + "0 0 0 1 zero 0 0 1 0 3 0 1 2\n"),
            "vertex 1: 'zero' is not a number");
  EXPECT_EQ(parse_error(start + "0 0 0 1 0 0 0 1 0.5e 3 0 1 2\n"),
            "vertex 2: '0.5e' is not a number");
  EXPECT_EQ(parse_error(start + "0 0 0 1 0 0 0 1 0 3 0 1 2.0\n"),
            "face 0: '2.0' is not a valid int");
  EXPECT_EQ(parse_error(start + "0 0 0 1 0 0 0 1 0 300 0 1 2\n"),
            "face 0: value 300 out of range for uchar");
  EXPECT_EQ(parse_error(start + "0 0 0 1 0 0 0 1 0 3 0 1 \x01\xff\n"),
            "face 0: '\?\?' is not a valid int");
  EXPECT_EQ(parse_error(start + "0 0 0 1 0 0 0 1 nan 3 0 1 2\n"), "vertex 2: coordinate is NaN");
}

TEST(PlyReader, RejectsFaceIndicesThatDoNotFitInt32) {
  PlyBuilder b("binary_little_endian");
  b.element("vertex", 3).property("float", "x").property("float", "y").property("float", "z");
  b.element("face", 1).list("uchar", "int", "vertex_indices").property("uint", "face_indices");
  for (int i = 0; i < 3; ++i) b.values("float", {0, 0, 0});
  b.list_values("uchar", "int", {0, 1, 2}).value("uint", 3000000000.0);
  EXPECT_EQ(parse_error(b.str()), "face 0: face_indices value 3000000000 does not fit in int32");
}

// Mutated and random inputs: whatever the result, no crash, hang or inconsistent mesh.
TEST(PlyReader, SurvivesGarbageAndMutatedFiles) {
  std::mt19937 rng(12345);
  std::vector<std::string> seeds;
  for (const std::string& format : kFormats) seeds.push_back(rich_mesh(format));
  seeds.push_back(square_with_faces("binary_big_endian", {{0, 1, 2, 3}, {3, 2, 1}}));
  int parsed = 0, rejected = 0;
  for (int iteration = 0; iteration < 20000; ++iteration) {
    std::string bytes = seeds[iteration % seeds.size()];
    const int edits = 1 + static_cast<int>(rng() % 4);
    for (int e = 0; e < edits; ++e) {
      const size_t at = rng() % bytes.size();
      switch (rng() % 5) {
        case 0:
          bytes[at] = static_cast<char>(rng());
          break;
        case 1:
          bytes[at] ^= static_cast<char>(1u << (rng() % 8));
          break;
        case 2:
          bytes.insert(at, 1, static_cast<char>(rng()));
          break;
        case 3:
          bytes.erase(at, 1 + rng() % 8);
          break;
        case 4:
          bytes.resize(std::max<size_t>(at, 1));
          break;
      }
      if (bytes.empty()) bytes = "p";
    }
    if (iteration % 10 == 0) {  // pure garbage, sometimes behind a valid magic
      bytes.resize(rng() % 300);
      for (char& c : bytes) c = static_cast<char>(rng());
      if (iteration % 20 == 0) bytes = "ply\n" + bytes;
    }
    PlyMesh mesh;
    PlyError error;
    if (!parse_ply(bytes, &mesh, &error)) {
      ++rejected;
      EXPECT_FALSE(error.message.empty());
      EXPECT_TRUE(mesh.positions.empty());
      continue;
    }
    ++parsed;
    ASSERT_EQ(mesh.positions.size() % 3, 0u);
    ASSERT_TRUE(mesh.normals.empty() || mesh.normals.size() == mesh.positions.size());
    ASSERT_TRUE(mesh.uvs.empty() || mesh.uvs.size() / 2 == mesh.num_vertices());
    ASSERT_TRUE(mesh.face_indices.empty() || mesh.face_indices.size() == mesh.num_triangles());
    ASSERT_GT(mesh.num_triangles(), 0u);
    for (uint32_t index : mesh.indices) ASSERT_LT(index, mesh.num_vertices());
    for (float v : mesh.positions) ASSERT_TRUE(std::isfinite(v));
  }
  EXPECT_GT(parsed, 0);
  EXPECT_GT(rejected, 0);
}

// ---------------------------------------------------------------------------------------------
// The shared corpus: every PLY file the scenes use must load.

TEST(PlyReader, ReadsEveryPlyFileOfTheSharedCorpus) {
  namespace fs = std::filesystem;
  const fs::path scenes = fs::path(testing_support::shared_dir()) / "scenes";
  std::vector<fs::path> files;
  for (const fs::directory_entry& entry : fs::recursive_directory_iterator(scenes)) {
    if (entry.is_regular_file() && entry.path().extension() == ".ply") {
      files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  ASSERT_FALSE(files.empty()) << "no .ply files under " << scenes;
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.string());
    PlyMesh mesh;
    PlyError error;
    ASSERT_TRUE(read_ply(file.string(), &mesh, &error)) << error.message;
    EXPECT_GT(mesh.num_triangles(), 0u);
    const size_t vertices = mesh.num_vertices();
    EXPECT_TRUE(std::all_of(mesh.indices.begin(), mesh.indices.end(),
                            [vertices](uint32_t i) { return i < vertices; }));
    std::printf("  %-70s %8zu vertices %8zu triangles%s%s%s\n",
                fs::relative(file, scenes).string().c_str(), vertices, mesh.num_triangles(),
                mesh.normals.empty() ? "" : " +normals", mesh.uvs.empty() ? "" : " +uvs",
                mesh.face_indices.empty() ? "" : " +face_indices");
  }
}

}  // namespace
}  // namespace pbrtc
