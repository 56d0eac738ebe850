// tests/compiler/pbrt_semantics_test.cpp — pbrt-v3's meaning of the directives, as the front end
// records it in the SceneDesc.
//
// One test per behaviour of /work/shared/PBRT-V3-NOTES.md that the front end decides: scoping
// of named things, texture namespaces, when materials capture textures, per-shape material
// overrides, pbrt-v2 spellings, the transform stack (column-major matrices, the camera
// transform, ActiveTransform/TransformTimes, object instances), path resolution, orientation,
// media, defaults and the effects summary.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "compiler/diagnostics.h"
#include "compiler/scene_builder.h"
#include "compiler/transform.h"
#include "test_support.h"

namespace pbrtc {
namespace {

using pbrta::Category;
using testing_support::scratch_dir;
using testing_support::write_file;

struct Build {
  SourceFiles files;
  Diagnostics diag{&files};
  SceneDesc scene;
  bool ok = false;

  explicit Build(const std::string& text, const std::string& base_dir = "/nonexistent-pbrtc") {
    ok = build_scene_from_string("scene.pbrt", text, base_dir, &files, &diag, &scene);
  }
  struct FromFile {};
  Build(FromFile, const std::string& path) { ok = build_scene(path, &files, &diag, &scene); }

  std::vector<std::string> texts(Severity s) const {
    std::vector<std::string> out;
    for (const Diagnostic& d : diag.all())
      if (d.severity == s) out.push_back(d.text);
    return out;
  }
  std::vector<std::string> errors() const { return texts(Severity::kError); }
  std::vector<std::string> warnings() const { return texts(Severity::kWarning); }
  // Everything reported, one message a line, for failure output.
  std::string report() const {
    std::string r;
    for (const Diagnostic& d : diag.all()) r += d.text + "\n";
    return r;
  }

  const ShapeDesc& shape(size_t i) const { return scene.shapes.at(i); }
  const MaterialDesc& material_of(size_t shape_index) const {
    return scene.materials.at(size_t(shape(shape_index).material));
  }
  const AnimatedTransform& transform_of(size_t shape_index) const {
    return scene.transforms.at(size_t(shape(shape_index).transform));
  }
};

// Builds and requires no diagnostics at all.
#define EXPECT_CLEAN(b)                                  \
  do {                                                   \
    EXPECT_TRUE((b).ok) << (b).report();                 \
    EXPECT_TRUE((b).diag.all().empty()) << (b).report(); \
  } while (0)

std::string in_world(const std::string& world) {
  return "WorldBegin\n" + world + "WorldEnd\n";
}

void expect_matrix_near(const Matrix4& a, const Matrix4& b) {
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(a.at(r, c), b.at(r, c), 1e-9) << "at " << r << "," << c;
}

void expect_rgb(const Entity& e, const char* param, float r, float g, float b) {
  uint32_t n = 0;
  const float* f = e.get_floats(param, &n);
  ASSERT_NE(f, nullptr) << param;
  ASSERT_EQ(n, 1u) << param;
  EXPECT_FLOAT_EQ(f[0], r) << param;
  EXPECT_FLOAT_EQ(f[1], g) << param;
  EXPECT_FLOAT_EQ(f[2], b) << param;
}

// ---- Scoping and names ----

TEST(PbrtSemantics, NamedTexturesAndMaterialsVanishAtAttributeEnd) {
  Build b(
      in_world("AttributeBegin\n"
               "  Texture \"t\" \"float\" \"constant\" \"float value\" 0.5\n"
               "  MakeNamedMaterial \"m\" \"string type\" \"matte\"\n"
               "  Material \"matte\" \"texture sigma\" \"t\"\n"
               "  NamedMaterial \"m\"\n"
               "AttributeEnd\n"
               "Material \"matte\" \"texture sigma\" \"t\"\n"
               "NamedMaterial \"m\"\n"));
  EXPECT_EQ(b.errors(),
            (std::vector<std::string>{"scene.pbrt:8:34: error: undefined float texture \"t\" for "
                                      "parameter \"texture sigma\"",
                                      "scene.pbrt:9:1: error: undefined named material \"m\""}));
}

TEST(PbrtSemantics, NamedTexturesAreVisibleInNestedBlocks) {
  Build b(
      in_world("Texture \"t\" \"float\" \"constant\"\n"
               "AttributeBegin\n"
               "  AttributeBegin\n"
               "    Material \"matte\" \"texture sigma\" \"t\"\n"
               "    Shape \"sphere\"\n"
               "  AttributeEnd\n"
               "AttributeEnd\n"));
  EXPECT_CLEAN(b);
  EXPECT_EQ(b.material_of(0).params.get_texture("sigma"), 0);
}

TEST(PbrtSemantics, NamedMediaCoordinateSystemsAndObjectsAreGlobal) {
  Build b(
      "Integrator \"volpath\"\n"
      "WorldBegin\n"
      "AttributeBegin\n"
      "  MakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\n"
      "  Translate 1 2 3\n"
      "  CoordinateSystem \"here\"\n"
      "  ObjectBegin \"o\"\n"
      "    Shape \"sphere\"\n"
      "  ObjectEnd\n"
      "AttributeEnd\n"
      "MediumInterface \"fog\"\n"
      "CoordSysTransform \"here\"\n"
      "ObjectInstance \"o\"\n"
      "Shape \"sphere\"\n"
      "WorldEnd\n");
  EXPECT_CLEAN(b);
  ASSERT_EQ(b.scene.shapes.size(), 2u);
  EXPECT_EQ(b.shape(1).inside_medium, 0);
  EXPECT_EQ(b.shape(1).outside_medium, 0);
  expect_matrix_near(b.transform_of(1).start, translate(1, 2, 3));
  ASSERT_EQ(b.scene.instances.size(), 1u);
  EXPECT_EQ(b.scene.instances[0].object, 0);
}

TEST(PbrtSemantics, FloatAndSpectrumTexturesAreSeparateNamespaces) {
  Build b(
      in_world("Texture \"n\" \"float\" \"constant\" \"float value\" 0.25\n"
               "Texture \"n\" \"spectrum\" \"constant\" \"rgb value\" [0.1 0.2 0.3]\n"
               "Material \"matte\" \"texture Kd\" \"n\" \"texture sigma\" \"n\"\n"
               "Shape \"sphere\"\n"));
  EXPECT_CLEAN(b);  // in particular, no "redefined" warning
  ASSERT_EQ(b.scene.textures.size(), 2u);
  EXPECT_EQ(b.scene.textures[0].params.category, Category::kFloatTexture);
  EXPECT_EQ(b.scene.textures[1].params.category, Category::kSpectrumTexture);
  const Entity& m = b.material_of(0).params;
  EXPECT_EQ(m.get_texture("sigma"), 0);
  EXPECT_EQ(m.get_texture("Kd"), 1);
}

TEST(PbrtSemantics, ColorTextureClassIsSpectrum) {
  Build b(
      in_world("Texture \"c\" \"color\" \"checkerboard\"\n"
               "Material \"matte\" \"texture Kd\" \"c\"\n"
               "Shape \"sphere\"\n"));
  EXPECT_CLEAN(b);
  ASSERT_EQ(b.scene.textures.size(), 1u);
  EXPECT_EQ(b.scene.textures[0].params.category, Category::kSpectrumTexture);
  EXPECT_EQ(b.scene.textures[0].params.type_name(), "checkerboard");
  EXPECT_EQ(b.material_of(0).params.get_texture("Kd"), 0);
}

TEST(PbrtSemantics, TextureRedefinitionWarnsAndTheNewOneWins) {
  Build b(
      in_world("Texture \"t\" \"float\" \"constant\" \"float value\" 0.1\n"
               "Texture \"t\" \"float\" \"constant\" \"float value\" 0.2\n"
               "Material \"matte\" \"texture sigma\" \"t\"\n"
               "Shape \"sphere\"\n"));
  EXPECT_TRUE(b.ok);
  EXPECT_EQ(b.warnings(),
            std::vector<std::string>{"scene.pbrt:3:1: warning: float texture \"t\" redefined"});
  EXPECT_EQ(b.material_of(0).params.get_texture("sigma"), 1);
  EXPECT_FLOAT_EQ(b.scene.textures[1].params.get_float("value"), 0.2f);
}

TEST(PbrtSemantics, NamedMaterialRedefinitionWarnsAndTheNewOneWins) {
  Build b(
      in_world("MakeNamedMaterial \"m\" \"string type\" \"matte\"\n"
               "MakeNamedMaterial \"m\" \"string type\" \"mirror\"\n"
               "NamedMaterial \"m\"\n"
               "Shape \"sphere\"\n"));
  EXPECT_TRUE(b.ok);
  EXPECT_EQ(b.warnings(),
            std::vector<std::string>{"scene.pbrt:3:1: warning: named material \"m\" redefined"});
  EXPECT_EQ(b.material_of(0).params.type_name(), "mirror");
  EXPECT_EQ(b.material_of(0).name, "m");
}

TEST(PbrtSemantics, MaterialsKeepTheTexturesTheyNamedWhenCreated) {
  Build b(
      in_world("Texture \"t\" \"float\" \"constant\" \"float value\" 0.1\n"
               "MakeNamedMaterial \"named\" \"string type\" \"matte\" \"texture sigma\" \"t\"\n"
               "Material \"matte\" \"texture sigma\" \"t\"\n"
               "Texture \"t\" \"float\" \"constant\" \"float value\" 0.2\n"
               "Shape \"sphere\"\n"
               "NamedMaterial \"named\"\n"
               "Shape \"sphere\"\n"
               "Material \"matte\" \"texture sigma\" \"t\"\n"
               "Shape \"sphere\"\n"));
  EXPECT_TRUE(b.ok);
  EXPECT_EQ(b.warnings().size(), 1u);  // the redefinition
  EXPECT_EQ(b.material_of(0).params.get_texture("sigma"), 0);
  EXPECT_EQ(b.material_of(1).params.get_texture("sigma"), 0);
  EXPECT_EQ(b.material_of(2).params.get_texture("sigma"), 1);
}

// ---- Per-shape material overrides ----

TEST(PbrtSemantics, ShapeParametersTheMaterialKnowsMakeANewMaterial) {
  Build b(
      in_world("Material \"plastic\" \"rgb Kd\" [0.1 0.2 0.3] \"float roughness\" 0.5\n"
               "Shape \"sphere\" \"rgb Kd\" [0.9 0.8 0.7] \"float radius\" 2\n"
               "Shape \"sphere\"\n"));
  EXPECT_CLEAN(b);  // "rgb Kd" counts as used
  ASSERT_EQ(b.scene.shapes.size(), 2u);
  EXPECT_NE(b.shape(0).material, b.shape(1).material);
  const Entity& over = b.material_of(0).params;
  const Entity& original = b.material_of(1).params;
  EXPECT_EQ(over.type_name(), "plastic");
  expect_rgb(over, "Kd", 0.9f, 0.8f, 0.7f);
  EXPECT_FLOAT_EQ(over.get_float("roughness"), 0.5f);  // the rest comes from the material
  expect_rgb(original, "Kd", 0.1f, 0.2f, 0.3f);
  EXPECT_FLOAT_EQ(b.shape(0).params.get_float("radius"), 2.0f);
}

TEST(PbrtSemantics, ShapeParametersNeitherKnowsAreUnused) {
  Build b(
      in_world("Material \"matte\"\n"
               "Shape \"sphere\" \"rgb Ks\" [0.9 0.8 0.7]\n"));
  EXPECT_TRUE(b.ok);
  EXPECT_EQ(b.warnings(), std::vector<std::string>{"scene.pbrt:3:16: warning: parameter \"rgb "
                                                   "Ks\" is not used by sphere shape"});
  EXPECT_EQ(b.shape(0).material, 0);
  EXPECT_EQ(b.scene.materials.size(), 1u);
}

TEST(PbrtSemantics, MixMaterialRecordsItsTwoMaterials) {
  Build b(
      in_world("MakeNamedMaterial \"a\" \"string type\" \"matte\"\n"
               "MakeNamedMaterial \"b\" \"string type\" \"mirror\"\n"
               "Material \"mix\" \"string namedmaterial1\" \"a\" \"string namedmaterial2\" \"b\" "
               "\"rgb amount\" [0.3 0.3 0.3]\n"
               "Shape \"sphere\"\n"));
  EXPECT_CLEAN(b);
  const MaterialDesc& mix = b.material_of(0);
  EXPECT_EQ(mix.params.type_name(), "mix");
  ASSERT_NE(mix.mix[0], kNone);
  ASSERT_NE(mix.mix[1], kNone);
  EXPECT_EQ(b.scene.materials.at(size_t(mix.mix[0])).name, "a");
  EXPECT_EQ(b.scene.materials.at(size_t(mix.mix[0])).params.type_name(), "matte");
  EXPECT_EQ(b.scene.materials.at(size_t(mix.mix[1])).name, "b");
  EXPECT_EQ(b.scene.materials.at(size_t(mix.mix[1])).params.type_name(), "mirror");
  expect_rgb(mix.params, "amount", 0.3f, 0.3f, 0.3f);
}

TEST(PbrtSemantics, IndexOnGlassAndUberIsEta) {
  Build b(
      in_world("Material \"glass\" \"float index\" 1.33\n"
               "Shape \"sphere\"\n"
               "Material \"uber\" \"float index\" 1.7\n"
               "Shape \"sphere\"\n"
               "Material \"glass\"\n"
               "Shape \"sphere\"\n"));
  EXPECT_CLEAN(b);
  EXPECT_TRUE(b.material_of(0).params.given("eta"));
  EXPECT_FLOAT_EQ(b.material_of(0).params.get_float("eta"), 1.33f);
  EXPECT_FLOAT_EQ(b.material_of(1).params.get_float("eta"), 1.7f);
  EXPECT_FALSE(b.material_of(2).params.given("eta"));
  EXPECT_FLOAT_EQ(b.material_of(2).params.get_float("eta"), 1.5f);
}

TEST(PbrtSemantics, InterfaceMaterialIsNone) {
  Build b(in_world("Material \"\"\nShape \"sphere\"\n"));
  EXPECT_CLEAN(b);
  EXPECT_EQ(b.material_of(0).params.type_name(), "none");
}

// ---- Meshes ----

constexpr const char* kTriangle = "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] ";

TEST(PbrtSemantics, TriangleMeshAcceptsFloatUvAndFloatSt) {
  Build b(in_world(std::string(kTriangle) +
                   "\"integer indices\" [0 1 2] \"float uv\" [0 0 1 0 0 1]\n" + kTriangle +
                   "\"integer indices\" [0 1 2] \"float st\" [0 0 .5 0 0 .5]\n" + kTriangle +
                   "\"integer indices\" [0 1 2] \"point2 uv\" [0 0 1 0 1 1]\n"));
  EXPECT_CLEAN(b);
  ASSERT_EQ(b.scene.meshes.size(), 3u);
  EXPECT_EQ(b.scene.meshes[0].uv, (std::vector<float>{0, 0, 1, 0, 0, 1}));
  EXPECT_EQ(b.scene.meshes[1].uv, (std::vector<float>{0, 0, .5f, 0, 0, .5f}));
  EXPECT_EQ(b.scene.meshes[2].uv, (std::vector<float>{0, 0, 1, 0, 1, 1}));
}

TEST(PbrtSemantics, TriangleMeshAcceptsIntegerFaceIndices) {
  Build b(
      in_world("Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0] "
               "\"integer indices\" [0 1 2 2 1 3] \"integer faceIndices\" [7 9]\n"));
  EXPECT_CLEAN(b);
  ASSERT_EQ(b.scene.meshes.size(), 1u);
  EXPECT_EQ(b.scene.meshes[0].num_triangles(), 2u);
  EXPECT_EQ(b.scene.meshes[0].face_indices, (std::vector<int32_t>{7, 9}));
  EXPECT_EQ(b.shape(0).mesh, 0);
}

TEST(PbrtSemantics, PlyQuadsAreSplitAndStCoordinatesAreUv) {
  std::string dir = scratch_dir("PbrtSemantics.PlyQuads");
  write_file(dir + "/quad.ply",
             "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
             "property float z\nproperty float s\nproperty float t\nelement face 1\n"
             "property list uchar int vertex_indices\nend_header\n"
             "0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n4 0 1 2 3\n");
  Build b(in_world("Shape \"plymesh\" \"string filename\" \"quad.ply\"\n"), dir);
  EXPECT_CLEAN(b);
  ASSERT_EQ(b.scene.meshes.size(), 1u);
  const TriangleMesh& m = b.scene.meshes[0];
  EXPECT_EQ(m.num_vertices(), 4u);
  EXPECT_EQ(m.num_triangles(), 2u);
  EXPECT_EQ(m.uv, (std::vector<float>{0, 0, 1, 0, 1, 1, 0, 1}));
}

TEST(PbrtSemantics, AlphaIsAMeshParameterOnly) {
  Build b(in_world("Shape \"sphere\" \"float alpha\" 0\n"));
  EXPECT_TRUE(b.ok);
  EXPECT_EQ(b.warnings(), std::vector<std::string>{"scene.pbrt:2:16: warning: parameter \"float "
                                                   "alpha\" is not used by sphere shape"});
  EXPECT_FALSE(b.scene.effects.alpha);
}

TEST(PbrtSemantics, ThreeVertexTriangleMeshMayLeaveOutIndices) {
  Build b(in_world(std::string(kTriangle) + "\n"));
  EXPECT_CLEAN(b);
  ASSERT_EQ(b.scene.meshes.size(), 1u);
  EXPECT_EQ(b.scene.meshes[0].indices, (std::vector<uint32_t>{0, 1, 2}));
}

// ---- pbrt-v2 spellings ----

TEST(PbrtSemantics, PbrtV2SpellingsPbrtV3StillAccepts) {
  Build b(
      "Sampler \"lowdiscrepancy\" \"integer pixelsamples\" 8\n"
      "WorldBegin\n"
      "LightSource \"exinfinite\"\n"
      "AttributeBegin\n"
      "  AreaLightSource \"area\" \"rgb L\" [1 1 1]\n"
      "  Shape \"sphere\"\n"
      "AttributeEnd\n"
      "WorldEnd\n");
  EXPECT_CLEAN(b);
  EXPECT_EQ(b.scene.sampler.type_name(), "02sequence");
  EXPECT_EQ(b.scene.sampler.get_int("pixelsamples"), 8);
  ASSERT_EQ(b.scene.lights.size(), 1u);
  EXPECT_EQ(b.scene.lights[0].params.type_name(), "infinite");
  ASSERT_EQ(b.scene.area_lights.size(), 1u);
  EXPECT_EQ(b.scene.area_lights[0].type_name(), "diffuse");
  EXPECT_EQ(b.shape(0).area_light, 0);
}

TEST(PbrtSemantics, CameraHalfFovIsHalfTheFov) {
  Build b("Camera \"perspective\" \"float halffov\" 30\nWorldBegin\nWorldEnd\n");
  EXPECT_CLEAN(b);
  EXPECT_TRUE(b.scene.camera.params.given("fov"));
  EXPECT_FLOAT_EQ(b.scene.camera.params.get_float("fov"), 60.0f);
}

TEST(PbrtSemantics, PositiveHalfFovReplacesAGivenFov) {
  // pbrt-v3: fov = FindOneFloat("fov", 90); if (halffov > 0) fov = 2 * halffov.
  Build b("Camera \"perspective\" \"float fov\" 90 \"float halffov\" 20\nWorldBegin\nWorldEnd\n");
  EXPECT_CLEAN(b);
  EXPECT_FLOAT_EQ(b.scene.camera.params.get_float("fov"), 40.0f);
}

TEST(PbrtSemantics, NonPositiveHalfFovIsIgnored) {
  Build b("Camera \"perspective\" \"float fov\" 45 \"float halffov\" 0\nWorldBegin\nWorldEnd\n");
  EXPECT_CLEAN(b);
  EXPECT_FLOAT_EQ(b.scene.camera.params.get_float("fov"), 45.0f);
  Build d("Camera \"perspective\" \"float halffov\" -1\nWorldBegin\nWorldEnd\n");
  EXPECT_CLEAN(d);
  EXPECT_FLOAT_EQ(d.scene.camera.params.get_float("fov"), 90.0f);
}

// ---- Transforms ----

TEST(PbrtSemantics, TransformNumbersAreColumnMajor) {
  Build b(in_world("Transform [1 0 0 0  0 1 0 0  0 0 1 0  5 6 7 1]\nShape \"sphere\"\n"));
  EXPECT_CLEAN(b);
  const Matrix4& m = b.transform_of(0).start;
  EXPECT_EQ(m.at(0, 3), 5);
  EXPECT_EQ(m.at(1, 3), 6);
  EXPECT_EQ(m.at(2, 3), 7);
  EXPECT_EQ(m.at(3, 0), 0);
  EXPECT_EQ(m.at(3, 3), 1);
  expect_matrix_near(m, translate(5, 6, 7));
}

TEST(PbrtSemantics, ConcatTransformIsColumnMajorAndPostMultiplies) {
  Build b(
      in_world("Translate 1 2 3\n"
               "ConcatTransform [2 0 0 0  0 2 0 0  0 0 2 0  1 0 0 1]\n"
               "Shape \"sphere\"\n"));
  EXPECT_CLEAN(b);
  // T(1,2,3) * (T(1,0,0) * S(2)): a point at the origin lands at (2, 2, 3).
  expect_matrix_near(b.transform_of(0).start,
                     mul(translate(1, 2, 3), mul(translate(1, 0, 0), scale(2, 2, 2))));
}

TEST(PbrtSemantics, TransformBeginEndRestoresOnlyTheTransform) {
  Build b(
      in_world("TransformBegin\n"
               "  Translate 1 0 0\n"
               "  Material \"mirror\"\n"
               "TransformEnd\n"
               "Shape \"sphere\"\n"));
  EXPECT_CLEAN(b);
  expect_matrix_near(b.transform_of(0).start, Matrix4());
  EXPECT_EQ(b.material_of(0).params.type_name(), "mirror");
}

TEST(PbrtSemantics, CameraRecordsCameraFromWorldAndCoordSysCameraRestoresItsInverse) {
  Build b(
      "Translate 1 2 3\n"
      "Camera \"perspective\"\n"
      "WorldBegin\n"
      "Shape \"sphere\"\n"
      "CoordSysTransform \"camera\"\n"
      "Shape \"sphere\"\n"
      "WorldEnd\n");
  EXPECT_CLEAN(b);
  EXPECT_TRUE(b.scene.camera.given);
  expect_matrix_near(b.scene.camera.camera_from_world.start, translate(1, 2, 3));
  expect_matrix_near(b.scene.camera.camera_from_world.end, translate(1, 2, 3));
  EXPECT_FALSE(b.scene.camera.camera_from_world.animated());
  // WorldBegin resets the transform.
  expect_matrix_near(b.transform_of(0).start, Matrix4());
  expect_matrix_near(b.transform_of(1).start, translate(-1, -2, -3));
}

TEST(PbrtSemantics, LookAtBuildsCameraFromWorld) {
  Build b("LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\nWorldEnd\n");
  EXPECT_CLEAN(b);
  const double eye[3] = {0, 0, -5}, look[3] = {0, 0, 0}, up[3] = {0, 1, 0};
  Matrix4 expected;
  ASSERT_TRUE(look_at(eye, look, up, &expected));
  expect_matrix_near(b.scene.camera.camera_from_world.start, expected);
  // The eye maps to the camera-space origin: camera_from_world * (0 0 -5 1) = 0.
  const Matrix4& m = b.scene.camera.camera_from_world.start;
  EXPECT_NEAR(m.at(2, 2) * -5 + m.at(2, 3), 0, 1e-9);
}

TEST(PbrtSemantics, ActiveTransformSelectsWhichTransformChanges) {
  Build b(
      "TransformTimes 0.25 0.75\n"
      "WorldBegin\n"
      "ActiveTransform EndTime\n"
      "Translate 1 0 0\n"
      "ActiveTransform All\n"
      "Shape \"sphere\"\n"
      "ActiveTransform StartTime\n"
      "Translate 0 2 0\n"
      "ActiveTransform All\n"
      "Shape \"sphere\"\n"
      "WorldEnd\n");
  EXPECT_CLEAN(b);
  const AnimatedTransform& t0 = b.transform_of(0);
  EXPECT_TRUE(t0.animated());
  expect_matrix_near(t0.start, Matrix4());
  expect_matrix_near(t0.end, translate(1, 0, 0));
  EXPECT_DOUBLE_EQ(t0.start_time, 0.25);
  EXPECT_DOUBLE_EQ(t0.end_time, 0.75);
  const AnimatedTransform& t1 = b.transform_of(1);
  expect_matrix_near(t1.start, translate(0, 2, 0));
  expect_matrix_near(t1.end, translate(1, 0, 0));
  EXPECT_TRUE(b.scene.effects.motion_blur);
}

TEST(PbrtSemantics, TransformTimesDefaultToZeroAndOne) {
  Build b(
      in_world("ActiveTransform EndTime\nTranslate 0 0 1\nActiveTransform All\n"
               "Shape \"sphere\"\n"));
  EXPECT_CLEAN(b);
  EXPECT_DOUBLE_EQ(b.transform_of(0).start_time, 0);
  EXPECT_DOUBLE_EQ(b.transform_of(0).end_time, 1);
}

TEST(PbrtSemantics, CameraMayBeAnimated) {
  Build b(
      "ActiveTransform StartTime\n"
      "Translate 0 0 1\n"
      "ActiveTransform All\n"
      "Camera \"perspective\"\n"
      "WorldBegin\nWorldEnd\n");
  EXPECT_CLEAN(b);
  const AnimatedTransform& c = b.scene.camera.camera_from_world;
  EXPECT_TRUE(c.animated());
  expect_matrix_near(c.start, translate(0, 0, 1));
  expect_matrix_near(c.end, Matrix4());
  EXPECT_TRUE(b.scene.effects.motion_blur);
}

TEST(PbrtSemantics, ObjectDefinitionKeepsItsTransformAndInstancesRecordTheirOwn) {
  Build b(
      in_world("Translate 1 0 0\n"
               "ObjectBegin \"o\"\n"
               "  Translate 0 2 0\n"
               "  Shape \"sphere\"\n"
               "ObjectEnd\n"
               "Translate 0 0 3\n"
               "ObjectInstance \"o\"\n"
               "Shape \"sphere\"\n"));
  EXPECT_CLEAN(b);
  ASSERT_EQ(b.scene.objects.size(), 1u);
  EXPECT_EQ(b.scene.objects[0].name, "o");
  EXPECT_EQ(b.scene.objects[0].shapes, std::vector<int32_t>{0});
  EXPECT_EQ(b.shape(0).object, 0);
  EXPECT_EQ(b.shape(1).object, kNone);
  // The object's shape: the transform at ObjectBegin and inside the definition.
  expect_matrix_near(b.transform_of(0).start, translate(1, 2, 0));
  // ObjectEnd restores the transform; the instance records the current one.
  ASSERT_EQ(b.scene.instances.size(), 1u);
  const InstanceDesc& inst = b.scene.instances[0];
  EXPECT_EQ(inst.object, 0);
  expect_matrix_near(b.scene.transforms.at(size_t(inst.transform)).start, translate(1, 0, 3));
  expect_matrix_near(b.transform_of(1).start, translate(1, 0, 3));
  EXPECT_TRUE(b.scene.effects.instancing);
}

TEST(PbrtSemantics, AreaLightInsideAnObjectDefinitionIsIgnoredWithAWarning) {
  Build b(
      in_world("AttributeBegin\n"
               "  AreaLightSource \"diffuse\"\n"
               "  ObjectBegin \"o\"\n"
               "    Shape \"sphere\"\n"
               "  ObjectEnd\n"
               "AttributeEnd\n"
               "ObjectInstance \"o\"\n"));
  EXPECT_TRUE(b.ok);
  EXPECT_EQ(b.warnings(), std::vector<std::string>{
                              "scene.pbrt:5:5: warning: area lights are not supported inside "
                              "object instances (ignored, as pbrt-v3 does)"});
  EXPECT_EQ(b.shape(0).area_light, kNone);
  EXPECT_FALSE(b.scene.effects.area_lights);
}

TEST(PbrtSemantics, AreaLightOnAnAnimatedShapeIsIgnoredWithAWarning) {
  Build b(
      in_world("AreaLightSource \"diffuse\"\n"
               "ActiveTransform EndTime\n"
               "Translate 1 0 0\n"
               "ActiveTransform All\n"
               "Shape \"sphere\"\n"));
  EXPECT_TRUE(b.ok);
  EXPECT_EQ(b.warnings(), std::vector<std::string>{
                              "scene.pbrt:6:1: warning: area lights are not supported on shapes "
                              "with animated transforms (ignored, as pbrt-v3 does)"});
  EXPECT_EQ(b.shape(0).area_light, kNone);
}

// pbrt-v3 reads "iterations" and falls back to "numiterations" (sppm), "levels" and falls
// back to "nlevels" (loopsubdiv): the alias never overrides its parameter, in either order.
TEST(PbrtSemantics, AnAliasBesideItsParameterIsIgnored) {
  for (const char* order : {"\"integer numiterations\" 5 \"integer iterations\" 9",
                            "\"integer iterations\" 9 \"integer numiterations\" 5"}) {
    Build b(std::string("Integrator \"sppm\" ") + order + "\nWorldBegin\nWorldEnd\n");
    EXPECT_TRUE(b.ok);
    EXPECT_EQ(b.scene.integrator.get_int("iterations"), 9) << order;
  }
  Build alone("Integrator \"sppm\" \"integer numiterations\" 5\nWorldBegin\nWorldEnd\n");
  EXPECT_EQ(alone.scene.integrator.get_int("iterations"), 5);
}

TEST(PbrtSemantics, AnimatedLightUsesItsStartTransformWithAWarning) {
  Build b(
      in_world("Translate 0 2 0\n"
               "ActiveTransform EndTime\n"
               "Translate 1 0 0\n"
               "ActiveTransform All\n"
               "LightSource \"point\"\n"));
  EXPECT_TRUE(b.ok);
  EXPECT_EQ(b.warnings(), std::vector<std::string>{
                              "scene.pbrt:6:1: warning: lights do not move: the light uses its "
                              "start transform (as pbrt-v3 does)"});
  ASSERT_EQ(b.scene.lights.size(), 1u);
  EXPECT_EQ(b.scene.lights[0].world_from_light.at(1, 3), 2);
}

TEST(PbrtSemantics, AreaLightAppliesToTheShapesOfItsBlock) {
  Build b(
      in_world("AttributeBegin\n"
               "  AreaLightSource \"diffuse\" \"rgb L\" [2 2 2] \"bool twosided\" \"true\"\n"
               "  Shape \"sphere\"\n"
               "AttributeEnd\n"
               "Shape \"sphere\"\n"));
  EXPECT_CLEAN(b);
  EXPECT_EQ(b.shape(0).area_light, 0);
  EXPECT_EQ(b.shape(1).area_light, kNone);
  EXPECT_TRUE(b.scene.area_lights.at(0).get_bool("twosided"));
  EXPECT_TRUE(b.scene.effects.area_lights);
}

// ---- Orientation ----

TEST(PbrtSemantics, ReverseOrientationAndHandedness) {
  Build b(
      in_world("AttributeBegin\n"
               "  ReverseOrientation\n"
               "  Shape \"sphere\"\n"
               "  ReverseOrientation\n"
               "  Shape \"sphere\"\n"
               "  ReverseOrientation\n"
               "AttributeEnd\n"
               "Shape \"sphere\"\n"
               "Scale -1 1 1\n"
               "Shape \"sphere\"\n"));
  EXPECT_CLEAN(b);
  ASSERT_EQ(b.scene.shapes.size(), 4u);
  EXPECT_TRUE(b.shape(0).reverse_orientation);
  EXPECT_FALSE(b.shape(1).reverse_orientation);  // a second ReverseOrientation toggles back
  EXPECT_FALSE(b.shape(2).reverse_orientation);  // restored by AttributeEnd
  EXPECT_FALSE(b.shape(3).reverse_orientation);
  EXPECT_FALSE(b.shape(0).transform_swaps_handedness);
  EXPECT_FALSE(b.shape(2).transform_swaps_handedness);
  EXPECT_TRUE(b.shape(3).transform_swaps_handedness);
}

// ---- Media ----

TEST(PbrtSemantics, MediumInterfaceWithOneOrTwoNames) {
  Build b(
      "Integrator \"volpath\"\n"
      "MakeNamedMedium \"a\" \"string type\" \"homogeneous\"\n"
      "MakeNamedMedium \"b\" \"string type\" \"homogeneous\" \"float g\" 0.5\n"
      "MediumInterface \"\" \"b\"\n"
      "Camera \"perspective\"\n"
      "WorldBegin\n"
      "MediumInterface \"a\"\n"
      "Shape \"sphere\"\n"
      "MediumInterface \"a\" \"b\"\n"
      "Shape \"sphere\"\n"
      "LightSource \"point\"\n"
      "MediumInterface \"\" \"b\"\n"
      "Shape \"sphere\"\n"
      "WorldEnd\n");
  EXPECT_CLEAN(b);
  ASSERT_EQ(b.scene.media.size(), 2u);
  EXPECT_FLOAT_EQ(b.scene.media[1].params.get_float("g"), 0.5f);
  EXPECT_EQ(b.scene.camera.medium, 1);
  EXPECT_EQ(b.shape(0).inside_medium, 0);  // one name: both sides
  EXPECT_EQ(b.shape(0).outside_medium, 0);
  EXPECT_EQ(b.shape(1).inside_medium, 0);  // two names: inside, then outside
  EXPECT_EQ(b.shape(1).outside_medium, 1);
  EXPECT_EQ(b.shape(2).inside_medium, kNone);
  EXPECT_EQ(b.shape(2).outside_medium, 1);
  // A light records the outside medium, which pbrt-v3 emits its rays into.
  EXPECT_EQ(b.scene.lights.at(0).medium, 1);
  EXPECT_TRUE(b.scene.effects.media);
}

TEST(PbrtSemantics, MediumMayBeDefinedAfterTheMediumInterfaceThatNamesIt) {
  // pbrt-v3 looks media up when it creates a shape, not at MediumInterface.
  Build b("Integrator \"bdpt\"\n" +
          in_world("MediumInterface \"late\" \"\"\n"
                   "MakeNamedMedium \"late\" \"string type\" \"homogeneous\"\n"
                   "Shape \"sphere\"\n"));
  EXPECT_CLEAN(b);
  EXPECT_EQ(b.shape(0).inside_medium, 0);
  EXPECT_EQ(b.shape(0).outside_medium, kNone);
}

TEST(PbrtSemantics, MediaWithAnIntegratorThatIgnoresThemWarn) {
  const std::string world = in_world(
      "MakeNamedMedium \"m\" \"string type\" \"homogeneous\"\n"
      "MediumInterface \"m\" \"\"\nShape \"sphere\"\n");
  Build path_default(world);
  EXPECT_TRUE(path_default.ok);
  EXPECT_EQ(path_default.warnings(),
            std::vector<std::string>{"scene.pbrt:3:1: warning: the scene has participating media, "
                                     "but the path integrator ignores them (pbrt-v3 simulates "
                                     "media only with volpath, bdpt and mlt)"});
  Build whitted("Integrator \"whitted\"\n" + world);
  EXPECT_EQ(whitted.warnings(),
            std::vector<std::string>{"scene.pbrt:1:1: warning: the scene has participating media, "
                                     "but the whitted integrator ignores them (pbrt-v3 simulates "
                                     "media only with volpath, bdpt and mlt)"});
  for (const char* integrator : {"volpath", "bdpt", "mlt"}) {
    Build b("Integrator \"" + std::string(integrator) + "\"\n" + world);
    EXPECT_CLEAN(b);
  }
  Build empty_names(in_world("MediumInterface \"\" \"\"\nShape \"sphere\"\n"));
  EXPECT_CLEAN(empty_names);
}

// ---- Defaults ----

TEST(PbrtSemantics, DefaultMaterialIsMatte) {
  Build b(in_world("Shape \"sphere\"\n"));
  EXPECT_CLEAN(b);
  const Entity& m = b.material_of(0).params;
  EXPECT_EQ(m.type_name(), "matte");
  expect_rgb(m, "Kd", 0.5f, 0.5f, 0.5f);
  EXPECT_FLOAT_EQ(m.get_float("sigma"), 0.0f);
}

TEST(PbrtSemantics, DefaultsAreFilledIn) {
  Build b(in_world("Shape \"sphere\"\n"));
  EXPECT_CLEAN(b);
  const Entity& sphere = b.shape(0).params;
  EXPECT_FALSE(sphere.given("radius"));
  EXPECT_FLOAT_EQ(sphere.get_float("radius"), 1.0f);
  EXPECT_FLOAT_EQ(sphere.get_float("phimax"), 360.0f);
  EXPECT_EQ(b.scene.integrator.type_name(), "path");
  EXPECT_EQ(b.scene.integrator.get_int("maxdepth"), 5);
  EXPECT_FALSE(b.scene.camera.given);
  EXPECT_EQ(b.scene.camera.params.type_name(), "perspective");
  EXPECT_FLOAT_EQ(b.scene.camera.params.get_float("fov"), 90.0f);
  EXPECT_EQ(b.scene.film.type_name(), "image");
  EXPECT_EQ(b.scene.film.get_int("xresolution"), 1280);
  EXPECT_EQ(b.scene.film.get_int("yresolution"), 720);
  EXPECT_EQ(b.scene.sampler.type_name(), "halton");
  EXPECT_EQ(b.scene.sampler.get_int("pixelsamples"), 16);
  EXPECT_EQ(b.scene.filter.type_name(), "box");
  EXPECT_FLOAT_EQ(b.scene.filter.get_float("xwidth"), 0.5f);
  EXPECT_EQ(b.scene.accelerator.type_name(), "bvh");
  EXPECT_EQ(b.scene.camera.medium, kNone);
}

TEST(PbrtSemantics, GivenValuesReplaceDefaults) {
  Build b(
      "Integrator \"path\" \"integer maxdepth\" 12\n"
      "Film \"image\" \"integer xresolution\" 64 \"integer yresolution\" 32\n"
      "WorldBegin\nShape \"sphere\" \"float radius\" 3\nWorldEnd\n");
  EXPECT_CLEAN(b);
  EXPECT_EQ(b.scene.integrator.get_int("maxdepth"), 12);
  EXPECT_EQ(b.scene.film.get_int("xresolution"), 64);
  EXPECT_EQ(b.scene.film.get_int("yresolution"), 32);
  EXPECT_TRUE(b.shape(0).params.given("radius"));
  EXPECT_FLOAT_EQ(b.shape(0).params.get_float("radius"), 3.0f);
}

TEST(PbrtSemantics, WholeNumbersSpelledAsFloatsAreIntegers) {
  // pbrt-v3 reads every number as a double and converts it for "integer" parameters.
  Build b(
      "Sampler \"halton\" \"integer pixelsamples\" 2.0\n"
      "Film \"image\" \"integer xresolution\" [ 1e3 ]\nWorldBegin\nWorldEnd\n");
  EXPECT_CLEAN(b);
  EXPECT_EQ(b.scene.sampler.get_int("pixelsamples"), 2);
  EXPECT_EQ(b.scene.film.get_int("xresolution"), 1000);
}

TEST(PbrtSemantics, LastOfARepeatedParameterWins) {
  // pbrt-v3's ParamSet replaces an earlier parameter of the same name and type.
  Build b(in_world("Shape \"sphere\" \"float radius\" 2 \"float radius\" 3\n"));
  EXPECT_CLEAN(b);
  EXPECT_FLOAT_EQ(b.shape(0).params.get_float("radius"), 3.0f);
}

// ---- Relative paths ----

TEST(PbrtSemantics, RelativePathsResolveAgainstTheTopLevelFilesDirectory) {
  std::string dir = scratch_dir("PbrtSemantics.RelativePaths");
  write_file(dir + "/meshes/tri.ply",
             "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
             "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
             "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  std::string top = write_file(dir + "/top.pbrt", "WorldBegin\nInclude \"sub/a.pbrt\"\nWorldEnd\n");
  // Both names below are relative to dir, not to dir/sub (where they do not exist).
  write_file(dir + "/sub/a.pbrt",
             "Include \"sub/b.pbrt\"\nShape \"plymesh\" \"string filename\" \"meshes/tri.ply\"\n");
  write_file(dir + "/sub/b.pbrt", "Shape \"sphere\"\n");
  Build b(Build::FromFile{}, top);
  EXPECT_CLEAN(b);
  ASSERT_EQ(b.scene.shapes.size(), 2u);
  EXPECT_EQ(b.shape(0).params.type_name(), "sphere");
  EXPECT_EQ(b.shape(1).params.type_name(), "plymesh");
  EXPECT_EQ(b.shape(1).params.get_string("filename"), dir + "/meshes/tri.ply");
  ASSERT_EQ(b.scene.meshes.size(), 1u);
  EXPECT_EQ(b.scene.meshes[0].num_triangles(), 1u);
  const std::vector<std::string>& in = b.scene.input_files;
  for (const std::string& f :
       {top, dir + "/sub/a.pbrt", dir + "/sub/b.pbrt", dir + "/meshes/tri.ply"})
    EXPECT_NE(std::find(in.begin(), in.end(), f), in.end()) << f;
}

TEST(PbrtSemantics, IncludedFilesOfInMemoryTextAreInputFiles) {
  std::string dir = scratch_dir("PbrtSemantics.IncludedFilesOfInMemoryText");
  write_file(dir + "/geometry/sphere.pbrt", "Shape \"sphere\"\n");
  Build b(in_world("Include \"geometry/sphere.pbrt\"\n"), dir);
  EXPECT_CLEAN(b);
  EXPECT_EQ(b.scene.shapes.size(), 1u);
  EXPECT_EQ(b.scene.input_files, std::vector<std::string>{dir + "/geometry/sphere.pbrt"});
}

// ---- Effects ----

TEST(PbrtSemantics, PlainSceneCallsForNoEffects) {
  Build b(in_world("LightSource \"point\"\nShape \"sphere\"\n"));
  EXPECT_CLEAN(b);
  const Effects& fx = b.scene.effects;
  EXPECT_FALSE(fx.media);
  EXPECT_FALSE(fx.motion_blur);
  EXPECT_FALSE(fx.textures);
  EXPECT_FALSE(fx.area_lights);
  EXPECT_FALSE(fx.infinite_lights);
  EXPECT_FALSE(fx.subsurface);
  EXPECT_FALSE(fx.instancing);
  EXPECT_FALSE(fx.alpha);
}

TEST(PbrtSemantics, TexturesEffectNeedsAMaterialInUse) {
  Build unused(
      in_world("Texture \"c\" \"spectrum\" \"checkerboard\"\n"
               "Material \"matte\" \"texture Kd\" \"c\"\n"
               "Material \"matte\"\n"
               "Shape \"sphere\"\n"));
  EXPECT_CLEAN(unused);
  EXPECT_FALSE(unused.scene.effects.textures);
  Build used(
      in_world("Texture \"c\" \"spectrum\" \"checkerboard\"\n"
               "Material \"matte\" \"texture Kd\" \"c\"\n"
               "Shape \"sphere\"\n"));
  EXPECT_CLEAN(used);
  EXPECT_TRUE(used.scene.effects.textures);
}

TEST(PbrtSemantics, TexturesEffectThroughAMixedMaterial) {
  Build b(
      in_world("Texture \"c\" \"spectrum\" \"checkerboard\"\n"
               "MakeNamedMaterial \"a\" \"string type\" \"matte\" \"texture Kd\" \"c\"\n"
               "MakeNamedMaterial \"b\" \"string type\" \"matte\"\n"
               "Material \"mix\" \"string namedmaterial1\" \"a\" \"string namedmaterial2\" \"b\"\n"
               "Shape \"sphere\"\n"));
  EXPECT_CLEAN(b);
  EXPECT_TRUE(b.scene.effects.textures);
}

TEST(PbrtSemantics, EffectsOfLightsInstancesAlphaAndSubsurface) {
  Build b(
      in_world("LightSource \"infinite\"\n"
               "ObjectBegin \"o\"\nShape \"sphere\"\nObjectEnd\n"
               "ObjectInstance \"o\"\n"
               "Material \"subsurface\"\n" +
               std::string(kTriangle) + "\"float alpha\" 0\n"));
  EXPECT_CLEAN(b);
  const Effects& fx = b.scene.effects;
  EXPECT_TRUE(fx.infinite_lights);
  EXPECT_TRUE(fx.instancing);
  EXPECT_TRUE(fx.alpha);
  EXPECT_TRUE(fx.subsurface);
  EXPECT_FALSE(fx.media);
  EXPECT_FALSE(fx.motion_blur);
}

TEST(PbrtSemantics, AlphaTextureOnAMeshIsAnAlphaEffectAndATexture) {
  Build b(in_world("Texture \"mask\" \"float\" \"checkerboard\"\n" + std::string(kTriangle) +
                   "\"texture alpha\" \"mask\"\n"));
  EXPECT_CLEAN(b);
  EXPECT_EQ(b.shape(0).params.get_texture("alpha"), 0);
  EXPECT_TRUE(b.scene.effects.alpha);
  EXPECT_TRUE(b.scene.effects.textures);
}

}  // namespace
}  // namespace pbrtc
