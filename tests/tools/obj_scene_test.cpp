// tests/tools/obj_scene_test.cpp — obj2pbrt's OBJ + MTL reading and its pbrt-v3 output.
//
// A hand-written OBJ (two groups, two materials, one with map_Kd and one with Ke, absolute and
// negative indices, quads, a pentagon, v/vt/vn and v//vn vertices, a `\` continuation) is
// converted and the output, Included by a small scene, is compiled with pbrtc's own front end:
// the shapes, triangles, uber parameters (roughness = 1/Ns as pbrt-v3's obj2pbrt computes it,
// eta from Ni, opacity from d or 1 - Tr), the textures and the one area light must be what
// pbrt-v3's obj2pbrt would make. The plymesh and complete-scene forms compile too, and the
// result survives the archive round trip. Malformed input fails with "file:line:" messages.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <string>
#include <vector>

#include "compiler/archive_builder.h"
#include "compiler/parser.h"
#include "compiler/scene_builder.h"
#include "format/scene_archive.h"
#include "test_support.h"
#include "tools/mesh/obj_scene.h"

namespace meshtools {
namespace {

using testing_support::scratch_dir;
using testing_support::write_file;

const char* kObj = R"(# two groups, two materials
mtllib materials.mtl
v 0 0 0
v 1 0 0
v 1 0 1
v 0 0 1
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 1 0
g floor
usemtl wood
f 1/1/1 2/2/1 3/3/1 4/4/1
v 2 0 0
v 3 0 0
v 3.5 0 0.5
v 3 0 1
v 2 0 1
vt 0 0
vt 1 0
vt 1 0.5
vt 1 1
vt 0 1
f -5/-5/-1 -4/-4/-1 -3/-3/-1 -2/-2/-1 -1/-1/-1
g lamp
usemtl light
v 0 2 0
v 1 2 0
v 1 2 \
  1
v 0 2 1
vn 0 -1 0
f -4//-1 -3//-1 -2//-1 -1//-1
)";

const char* kMtl = R"(# the floor's wood, and a lamp
newmtl wood
Kd 0.5 0.4 0.3
Ks 0.1 0.1 0.1
Ns 20
Ni 1.45
d 0.75
map_Kd wood.pfm

newmtl light
Kd 0 0 0
Ke 5 4 3
Tr 0.5
)";

// A 2x2 RGB PFM (little-endian: negative scale): the simplest image file to write by hand.
void write_pfm(const std::string& path) {
  std::string data = "PF\n2 2\n-1.0\n";
  const float texels[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1};
  data.append(reinterpret_cast<const char*>(texels), sizeof texels);
  write_file(path, data);
}

std::string make_inputs(const std::string& test) {
  const std::string dir = scratch_dir(test);
  write_file(dir + "/scene.obj", kObj);
  write_file(dir + "/materials.mtl", kMtl);
  write_pfm(dir + "/wood.pfm");
  return dir;
}

// Converts dir/scene.obj to dir/out.pbrt.
void convert(const std::string& dir, const ObjPbrtOptions& options, ObjPbrtStats* stats) {
  ObjScene scene;
  std::string error;
  ASSERT_TRUE(read_obj_scene(dir + "/scene.obj", &scene, &error)) << error;
  ASSERT_TRUE(write_obj_scene_pbrt(scene, dir + "/out.pbrt", options, stats, &error)) << error;
}

struct Built {
  pbrtc::SourceFiles files;
  pbrtc::SceneDesc scene;
  std::vector<std::string> messages;
  bool ok = false;
};

void build(const std::string& path, Built* b) {
  pbrtc::Diagnostics diag(&b->files, nullptr);
  b->ok = pbrtc::build_scene(path, &b->files, &diag, &b->scene);
  for (const auto& d : diag.all()) b->messages.push_back(d.text);
}

// The user's scene around obj2pbrt's fragment.
std::string write_wrapper(const std::string& dir) {
  return write_file(dir + "/main.pbrt",
                    "LookAt 0 5 5  0 0 0  0 1 0\nCamera \"perspective\"\n"
                    "Film \"image\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n"
                    "WorldBegin\nInclude \"out.pbrt\"\nWorldEnd\n");
}

const pbrtc::ShapeDesc* shape_with_material(const pbrtc::SceneDesc& s, const std::string& name) {
  for (const auto& shape : s.shapes)
    if (shape.material >= 0 && s.materials[size_t(shape.material)].name == name) return &shape;
  return nullptr;
}

const pbrtc::MaterialDesc* material_named(const pbrtc::SceneDesc& s, const std::string& name) {
  for (const auto& m : s.materials)
    if (m.name == name) return &m;
  return nullptr;
}

void expect_rgb(const float* v, float r, float g, float b) {
  ASSERT_NE(v, nullptr);
  EXPECT_FLOAT_EQ(v[0], r);
  EXPECT_FLOAT_EQ(v[1], g);
  EXPECT_FLOAT_EQ(v[2], b);
}

TEST(ObjScene, ParsesGroupsMaterialsAndIndexForms) {
  const std::string dir = make_inputs("ObjScene.Parses");
  ObjScene scene;
  std::string error;
  ASSERT_TRUE(read_obj_scene(dir + "/scene.obj", &scene, &error)) << error;
  ASSERT_EQ(scene.materials.size(), 2u);
  ASSERT_EQ(scene.shapes.size(), 2u);
  const ObjShape& floor = scene.shapes[0];
  EXPECT_EQ(floor.name, "floor");
  EXPECT_EQ(floor.material, 0);
  // The quad is 2 triangles, the pentagon a fan of 3; 4 + 5 distinct (v, vt, vn) triples.
  EXPECT_EQ(floor.mesh.num_triangles(), 5u);
  EXPECT_EQ(floor.mesh.num_vertices(), 9u);
  EXPECT_EQ(floor.mesh.indices,
            (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7, 4, 7, 8}));
  EXPECT_EQ(floor.mesh.normals.size(), 27u);
  ASSERT_EQ(floor.mesh.uvs.size(), 18u);
  EXPECT_FLOAT_EQ(floor.mesh.uvs[2 * 6 + 1], 0.5f);  // the pentagon's third vt, by -3
  EXPECT_FLOAT_EQ(floor.mesh.positions[3 * 6], 3.5f);
  const ObjShape& lamp = scene.shapes[1];
  EXPECT_EQ(lamp.name, "lamp");
  EXPECT_EQ(lamp.material, 1);
  EXPECT_EQ(lamp.mesh.num_triangles(), 2u);
  EXPECT_EQ(lamp.mesh.num_vertices(), 4u);
  EXPECT_TRUE(lamp.mesh.uvs.empty());
  ASSERT_EQ(lamp.mesh.normals.size(), 12u);
  EXPECT_FLOAT_EQ(lamp.mesh.normals[1], -1.f);
  EXPECT_FLOAT_EQ(lamp.mesh.positions[3 * 2 + 2], 1.f);  // "v 1 2 \" continued: z = 1

  const ObjMaterial& wood = scene.materials[0];
  EXPECT_EQ(wood.name, "wood");
  EXPECT_FLOAT_EQ(wood.ns, 20.f);
  EXPECT_FLOAT_EQ(wood.ni, 1.45f);
  EXPECT_FLOAT_EQ(wood.d, 0.75f);
  EXPECT_EQ(wood.map_kd, dir + "/wood.pfm");
  const ObjMaterial& light = scene.materials[1];
  EXPECT_FLOAT_EQ(light.d, 0.5f);  // 1 - Tr
  EXPECT_FLOAT_EQ(light.ke[0], 5.f);
  EXPECT_FLOAT_EQ(light.ns, 1.f);  // tinyobjloader's default shininess
}

TEST(ObjScene, VerticesAreSharedPerTriple) {
  ObjScene scene;
  std::string error;
  ASSERT_TRUE(parse_obj_scene("t.obj",
                              "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                              "vt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\nf 1/2/1 3/3/1 4/4/1\n",
                              "", &scene, &error))
      << error;
  ASSERT_EQ(scene.shapes.size(), 1u);
  // 1/1/1 and 1/2/1 share a position but not a uv: two vertices. 3/3/1 is shared.
  EXPECT_EQ(scene.shapes[0].mesh.num_vertices(), 5u);
  EXPECT_EQ(scene.shapes[0].mesh.indices, (std::vector<uint32_t>{0, 1, 2, 3, 2, 4}));
  EXPECT_EQ(scene.shapes[0].material, -1);
}

TEST(ObjScene, RoughnessFollowsPbrtV3) {
  EXPECT_FLOAT_EQ(roughness_from_ns(20), 0.05f);
  EXPECT_EQ(roughness_from_ns(0), 0.f);
  EXPECT_EQ(roughness_from_ns(1), 1.f);
}

TEST(ObjScene, IncludedOutputCompiles) {
  const std::string dir = make_inputs("ObjScene.IncludedOutputCompiles");
  ObjPbrtStats stats;
  ASSERT_NO_FATAL_FAILURE(convert(dir, ObjPbrtOptions(), &stats));
  EXPECT_EQ(stats.shapes, 2u);
  EXPECT_EQ(stats.triangles, 7u);
  EXPECT_EQ(stats.area_lights, 1u);
  const std::string text = testing_support::read_file(dir + "/out.pbrt");
  EXPECT_EQ(text.find("\nWorldBegin"), std::string::npos);  // comments may name it
  EXPECT_EQ(text.find("\nCamera"), std::string::npos);

  Built b;
  build(write_wrapper(dir), &b);
  ASSERT_TRUE(b.ok) << (b.messages.empty() ? "" : b.messages[0]);
  const pbrtc::SceneDesc& s = b.scene;
  ASSERT_EQ(s.shapes.size(), 2u);
  const pbrtc::ShapeDesc* floor = shape_with_material(s, "wood");
  const pbrtc::ShapeDesc* lamp = shape_with_material(s, "light");
  ASSERT_TRUE(floor && lamp);
  ASSERT_GE(floor->mesh, 0);
  ASSERT_GE(lamp->mesh, 0);
  const pbrtc::TriangleMesh& fm = s.meshes[size_t(floor->mesh)];
  EXPECT_EQ(fm.num_triangles(), 5u);
  EXPECT_EQ(fm.num_vertices(), 9u);
  EXPECT_EQ(fm.N.size(), 27u);
  EXPECT_EQ(fm.uv.size(), 18u);
  const pbrtc::TriangleMesh& lm = s.meshes[size_t(lamp->mesh)];
  EXPECT_EQ(lm.num_triangles(), 2u);
  EXPECT_TRUE(lm.uv.empty());

  // One area light, on the lamp only.
  ASSERT_EQ(s.area_lights.size(), 1u);
  EXPECT_EQ(floor->area_light, pbrtc::kNone);
  ASSERT_EQ(lamp->area_light, 0);
  EXPECT_EQ(s.area_lights[0].type_name(), "diffuse");
  expect_rgb(s.area_lights[0].get_floats("L"), 5, 4, 3);

  const pbrtc::MaterialDesc* wood = material_named(s, "wood");
  const pbrtc::MaterialDesc* light = material_named(s, "light");
  ASSERT_TRUE(wood && light);
  EXPECT_EQ(wood->params.type_name(), "uber");
  EXPECT_EQ(light->params.type_name(), "uber");
  EXPECT_FLOAT_EQ(wood->params.get_float("roughness"), 1.f / 20.f);
  EXPECT_FLOAT_EQ(light->params.get_float("roughness"), 1.f);  // Ns absent: 1, so 1/1
  EXPECT_FLOAT_EQ(wood->params.get_float("eta"), 1.45f);       // "index" is eta's alias
  EXPECT_FLOAT_EQ(light->params.get_float("eta"), 1.f);
  expect_rgb(wood->params.get_floats("opacity"), 0.75f, 0.75f, 0.75f);
  expect_rgb(light->params.get_floats("opacity"), 0.5f, 0.5f, 0.5f);
  expect_rgb(wood->params.get_floats("Ks"), 0.1f, 0.1f, 0.1f);
  expect_rgb(wood->params.get_floats("Kt"), 0, 0, 0);
  expect_rgb(light->params.get_floats("Kd"), 0, 0, 0);

  // The wood's Kd: its map scaled by its non-black Kd, as pbrt-v3's obj2pbrt writes it.
  const int32_t kd = wood->params.get_texture("Kd");
  ASSERT_GE(kd, 0);
  const pbrtc::TextureDesc& scale = s.textures[size_t(kd)];
  EXPECT_EQ(scale.name, "wood-kd");
  EXPECT_EQ(scale.params.type_name(), "scale");
  expect_rgb(scale.params.get_floats("tex2"), 0.5f, 0.4f, 0.3f);
  const int32_t img = scale.params.get_texture("tex1");
  ASSERT_GE(img, 0);
  EXPECT_EQ(s.textures[size_t(img)].params.type_name(), "imagemap");
  EXPECT_NE(s.textures[size_t(img)].image, pbrtc::kNone);
  EXPECT_EQ(light->params.get_texture("Kd"), pbrtc::kNone);
}

TEST(ObjScene, PlymeshOutputCompiles) {
  const std::string dir = make_inputs("ObjScene.PlymeshOutputCompiles");
  ObjPbrtOptions options;
  options.style = PbrtStyle::kPlymesh;
  ASSERT_NO_FATAL_FAILURE(convert(dir, options, nullptr));
  EXPECT_FALSE(testing_support::read_file(dir + "/out-0.ply").empty());
  EXPECT_FALSE(testing_support::read_file(dir + "/out-1.ply").empty());
  Built b;
  build(write_wrapper(dir), &b);
  ASSERT_TRUE(b.ok) << (b.messages.empty() ? "" : b.messages[0]);
  ASSERT_EQ(b.scene.shapes.size(), 2u);
  EXPECT_EQ(b.scene.shapes[0].params.type_name(), "plymesh");
  size_t triangles = 0;
  for (const auto& m : b.scene.meshes) triangles += m.num_triangles();
  EXPECT_EQ(triangles, 7u);
  EXPECT_EQ(b.scene.area_lights.size(), 1u);
}

TEST(ObjScene, CompleteSceneCompilesDirectly) {
  const std::string dir = make_inputs("ObjScene.CompleteSceneCompilesDirectly");
  ObjPbrtOptions options;
  options.complete_scene = true;
  ASSERT_NO_FATAL_FAILURE(convert(dir, options, nullptr));
  Built b;
  build(dir + "/out.pbrt", &b);
  ASSERT_TRUE(b.ok) << (b.messages.empty() ? "" : b.messages[0]);
  EXPECT_TRUE(b.scene.camera.given);
  EXPECT_EQ(b.scene.shapes.size(), 2u);
  EXPECT_EQ(b.scene.lights.size(), 1u);  // the infinite light
}

TEST(ObjScene, ArchiveRoundTrip) {
  const std::string dir = make_inputs("ObjScene.ArchiveRoundTrip");
  ASSERT_NO_FATAL_FAILURE(convert(dir, ObjPbrtOptions(), nullptr));
  Built b;
  const std::string main = write_wrapper(dir);
  build(main, &b);
  ASSERT_TRUE(b.ok) << (b.messages.empty() ? "" : b.messages[0]);
  pbrtc::ArchiveOptions opt;
  opt.threads = 1;
  std::string error;
  const std::string archive = dir + "/main.pbrta";
  ASSERT_TRUE(pbrtc::write_archive(b.scene, b.files, pbrtc::directory_of(main), archive, opt,
                                   nullptr, &error))
      << error;
  pbrta::SceneArchive a;
  ASSERT_TRUE(a.load(archive, 1, &error)) << error;
  EXPECT_EQ(a.shapes.size, 2u);
  EXPECT_EQ(a.meshes.size, 2u);
  EXPECT_EQ(a.area_lights.size, 1u);
  size_t triangles = 0;
  for (const pbrta::MeshRecord& m : a.meshes) triangles += m.num_triangles;
  EXPECT_EQ(triangles, 7u);
}

// parse_obj_scene on text, expecting failure with a message that holds every piece.
void expect_error(const std::string& text, const std::string& base_dir,
                  const std::vector<std::string>& pieces) {
  ObjScene scene;
  std::string error;
  EXPECT_FALSE(parse_obj_scene("bad.obj", text, base_dir, &scene, &error)) << text;
  for (const std::string& p : pieces)
    EXPECT_NE(error.find(p), std::string::npos) << "\"" << error << "\" lacks \"" << p << "\"";
  EXPECT_TRUE(scene.shapes.empty());
}

TEST(ObjScene, MalformedInputGivesFileAndLine) {
  const std::string dir = scratch_dir("ObjScene.Malformed");
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  expect_error(tri + "f 1 2 99\n", dir, {"bad.obj:4:", "vertex index 99 out of range"});
  expect_error(tri + "f 1 2 0\n", dir, {"bad.obj:4:", "index 0"});
  expect_error(tri + "f -4 -2 -1\n", dir, {"bad.obj:4:", "vertex index -4 out of range"});
  expect_error(tri + "vt 0 0\nf 1/2 2/1 3/1\n", dir,
               {"bad.obj:5:", "texture coordinate index 2 out of range"});
  expect_error("v 0 nan 0\n", dir, {"bad.obj:1:", "NaN"});
  expect_error("v 0 0 1e40\n", dir, {"bad.obj:1:", "out of range"});
  expect_error("v 0 0 zero\n", dir, {"bad.obj:1:", "expected a number"});
  expect_error(tri + "f 1 2\n", dir, {"bad.obj:4:", "at least 3 vertices"});
  // A continued line counts its physical lines: the face is on line 5.
  expect_error("v 0 0 \\\n 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", dir,
               {"bad.obj:5:", "vertex index 4 out of range"});
  expect_error("# nothing yet\nmtllib missing.mtl\n", dir,
               {"bad.obj:2:", "material library \"missing.mtl\" not found"});
  write_file(dir + "/badnum.mtl", "newmtl m\nNs inf\n");
  expect_error("mtllib badnum.mtl\n", dir, {"badnum.mtl:2:", "out of range"});
}

// Maps named as their authors' machines named them: Windows separators, absolute paths from
// elsewhere, another letter case. The file that came along with the model is found.
TEST(ObjScene, TextureNamesFromOtherMachinesAreFound) {
  const std::string dir = scratch_dir("ObjScene.TextureNames");
  write_file(dir + "/wall.jpg", "x");  // beside the OBJ (never decoded here)
  write_file(dir + "/mtl/sub/floor.png", "x");
  write_file(dir + "/mtl/Roof.PNG", "x");
  write_file(dir + "/mtl/lib.mtl",
             "newmtl a\nmap_Kd .\\sub\\floor.png\n"  // `\` as a separator, beside the MTL
             "newmtl b\nmap_Kd C:\\Users\\me\\Tex\\Wall.JPG\n"  // its file name, beside the OBJ
             "newmtl c\nmap_Kd /home/me/roof.png\n");           // beside the MTL, letter case aside
  ObjScene scene;
  std::string error;
  ASSERT_TRUE(parse_obj_scene("m.obj", "mtllib mtl/lib.mtl\n", dir, &scene, &error)) << error;
  ASSERT_EQ(scene.materials.size(), 3u);
  EXPECT_EQ(scene.materials[0].map_kd, dir + "/mtl/sub/floor.png");
  EXPECT_EQ(scene.materials[1].map_kd, dir + "/wall.jpg");
  EXPECT_EQ(scene.materials[2].map_kd, dir + "/mtl/Roof.PNG");
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings[0];
}

// A converter converts what it can and says what it could not: a map that cannot be found is a
// warning, and its material keeps its constant colour; --strict makes it the error it was.
TEST(ObjScene, MissingTextureIsAWarningUnlessStrict) {
  const std::string dir = scratch_dir("ObjScene.MissingTexture");
  write_file(dir + "/notex.mtl", "newmtl m\nKd 1 0.5 1\nmap_Kd gone.png\n");
  const std::string obj = "mtllib notex.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n";
  ObjScene scene;
  std::string error;
  ASSERT_TRUE(parse_obj_scene("m.obj", obj, dir, &scene, &error)) << error;
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_TRUE(scene.materials[0].map_kd.empty());
  EXPECT_EQ(scene.materials[0].kd, (std::array<float, 3>{1, 0.5f, 1}));
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_EQ(scene.warnings[0],
            dir + "/notex.mtl:3: map_Kd file \"gone.png\" not found (looked in \"" + dir +
                "\"); the material keeps its constant value");
  ObjPbrtStats stats;
  ASSERT_TRUE(write_obj_scene_pbrt(scene, dir + "/out.pbrt", ObjPbrtOptions(), &stats, &error))
      << error;
  EXPECT_EQ(stats.textures, 0u);
  EXPECT_NE(testing_support::read_file(dir + "/out.pbrt").find("\"rgb Kd\" [ 1 0.5 1 ]"),
            std::string::npos);

  EXPECT_FALSE(parse_obj_scene("bad.obj", obj, dir, &scene, &error, /*strict=*/true));
  for (const char* piece : {"bad.obj:1:", "notex.mtl:3:", "gone.png", "not found"})
    EXPECT_NE(error.find(piece), std::string::npos) << error;
  EXPECT_TRUE(scene.shapes.empty());
}

TEST(ObjScene, MultipleLibrariesAndWarnings) {
  const std::string dir = scratch_dir("ObjScene.MultipleLibraries");
  write_file(dir + "/a.mtl", "newmtl a\nKd 1 0 0\n");
  write_file(dir + "/b.mtl", "newmtl b\nKd 0 1 0\nmap_Ka amb.png\n");
  ObjScene scene;
  std::string error;
  ASSERT_TRUE(parse_obj_scene("m.obj",
                              "mtllib a.mtl b.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl b\n"
                              "f 1 2 3\nusemtl nothing\nf 1 2 3\ncstype bezier\n",
                              dir, &scene, &error))
      << error;
  ASSERT_EQ(scene.materials.size(), 2u);
  ASSERT_EQ(scene.shapes.size(), 2u);
  EXPECT_EQ(scene.shapes[0].material, 1);
  EXPECT_EQ(scene.shapes[1].material, -1);  // pbrt-v3: an undefined usemtl means none
  std::string all;
  for (const std::string& w : scene.warnings) all += w + "\n";
  EXPECT_NE(all.find("m.obj:7:"), std::string::npos) << all;    // usemtl nothing
  EXPECT_NE(all.find("map_Ka"), std::string::npos) << all;      // not converted
  EXPECT_NE(all.find("\"cstype\""), std::string::npos) << all;  // unsupported
}

}  // namespace
}  // namespace meshtools
