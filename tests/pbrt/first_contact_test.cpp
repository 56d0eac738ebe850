// tests/pbrt/first_contact_test.cpp — what a new user does first, on real files nobody here wrote.
//
// Debian's assimp-testmodels (installed by tools/install-deps.sh, never copied here): assimp's
// spider, an OBJ whose MTL names five JPEG maps as Windows paths (`.\SpiderTex.jpg`), converted
// by obj2pbrt into a complete scene that pbrtc compiles and pbrtrun renders; Wuson.ply, written by
// Blender 2.47 with a header line that lacks the `comment` keyword, converted by pbrt-mesh with
// one warning; and a pbrt-v4 cornell box, which pbrtc refuses naming pbrt-v3's equivalents.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "command_runner.h"
#include "format/scene_archive.h"
#include "test_support.h"

namespace {

using testing_support::assimp_models_dir;
using testing_support::kBin;
using testing_support::lines_of;
using testing_support::Outcome;
using testing_support::run_in;
using testing_support::scratch_dir;
using testing_support::write_file;

// The lines of text that hold needle.
std::vector<std::string> lines_with(const std::string& text, const std::string& needle) {
  std::vector<std::string> out;
  for (const std::string& l : lines_of(text))
    if (l.find(needle) != std::string::npos) out.push_back(l);
  return out;
}

TEST(FirstContact, SpiderObjWithJpegTexturesConvertsCompilesAndRenders) {
  const std::string dir = scratch_dir("FirstContact.Spider");
  const std::string obj = assimp_models_dir() + "/OBJ/spider.obj";
  Outcome c = run_in(dir, kBin + "/obj2pbrt --scene '" + obj + "' spider.pbrt", "obj2pbrt");
  ASSERT_EQ(c.status, 0) << c.err;
  EXPECT_TRUE(lines_with(c.err, "not found").empty()) << c.err;
  // Each map times its material's non-black Kd, as pbrt-v3's obj2pbrt writes it: an imagemap
  // and a scale texture per map.
  EXPECT_NE(c.err.find("5 materials, 10 textures"), std::string::npos) << c.err;

  Outcome p = run_in(dir, kBin + "/pbrtc spider.pbrt -o spider.pbrta", "pbrtc");
  ASSERT_EQ(p.status, 0) << p.err;
  EXPECT_TRUE(lines_with(p.err, "error").empty()) << p.err;
  pbrta::SceneArchive a;
  std::string error;
  ASSERT_TRUE(a.load(dir + "/spider.pbrta", 1, &error)) << error;
  // Five JPEG maps, each its own texture; none a power of two wide, so each also keeps its
  // decoded source beside its pyramid.
  size_t image_textures = 0;
  for (const pbrta::ImageRecord& im : a.images) image_textures += im.levels > 1 ? 1 : 0;
  EXPECT_EQ(image_textures, 5u);

  Outcome r = run_in(dir,
                     kBin +
                         "/pbrtrun spider.pbrta --spp 1 --resdiv 8 --quiet --outfile s.exr "
                         "--preview s.png",
                     "pbrtrun");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir + "/s.png"));
}

TEST(FirstContact, SpiderWithAMissingMapWarnsAndKeepsItsColourUnlessStrict) {
  const std::string dir = scratch_dir("FirstContact.MissingMap");
  // The spider's OBJ and MTL beside each other, with one of the five maps missing.
  const std::string models = assimp_models_dir() + "/OBJ/";
  for (const char* f : {"spider.obj", "spider.mtl", "wal67ar_small.jpg", "wal69ar_small.jpg",
                        "SpiderTex.jpg", "drkwood2.jpg"})
    std::filesystem::copy_file(models + f, dir + "/" + f);
  Outcome c = run_in(dir, kBin + "/obj2pbrt --scene spider.obj spider.pbrt", "lenient");
  ASSERT_EQ(c.status, 0) << c.err;
  const std::vector<std::string> missing = lines_with(c.err, "not found");
  ASSERT_EQ(missing.size(), 1u) << c.err;
  EXPECT_NE(missing[0].find("obj2pbrt: warning: "), std::string::npos) << missing[0];
  EXPECT_NE(missing[0].find("spider.mtl:38: map_Kd file \".\\engineflare1.jpg\" not found"),
            std::string::npos)
      << missing[0];
  EXPECT_NE(c.err.find("5 materials, 8 textures"), std::string::npos) << c.err;
  Outcome p = run_in(dir, kBin + "/pbrtc spider.pbrt -o spider.pbrta", "pbrtc");
  EXPECT_EQ(p.status, 0) << p.err;

  Outcome s = run_in(dir, kBin + "/obj2pbrt --strict --scene spider.obj strict.pbrt", "strict");
  EXPECT_EQ(s.status, 1);
  EXPECT_NE(s.err.find("obj2pbrt: error: "), std::string::npos) << s.err;
  EXPECT_NE(s.err.find("engineflare1.jpg"), std::string::npos) << s.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/strict.pbrt"));
}

TEST(FirstContact, BlenderPlyWithABareHeaderLineConvertsWithOneWarning) {
  const std::string dir = scratch_dir("FirstContact.Wuson");
  const std::string ply = assimp_models_dir() + "/PLY/Wuson.ply";
  Outcome c = run_in(dir, kBin + "/pbrt-mesh convert '" + ply + "' wuson.obj", "convert");
  ASSERT_EQ(c.status, 0) << c.err;
  const std::vector<std::string> warnings = lines_with(c.err, "warning");
  ASSERT_EQ(warnings.size(), 1u) << c.err;
  EXPECT_EQ(warnings[0], "pbrt-mesh: warning: " + ply +
                             ": header line 3: skipped 'Created by Blender3D 247 - "
                             "www.blender.o...' (not a PLY header keyword)");
  EXPECT_NE(c.out.find("11184 vertices, 3732 triangles"), std::string::npos) << c.out;

  // pbrtc reads it too, and says the same once, located at the file name.
  write_file(dir + "/scene.pbrt",
             "Camera \"perspective\"\nWorldBegin\nShape \"plymesh\" "
             "\"string filename\" \"" +
                 ply + "\"\nWorldEnd\n");
  Outcome p = run_in(dir, kBin + "/pbrtc scene.pbrt -o scene.pbrta", "pbrtc");
  ASSERT_EQ(p.status, 0) << p.err;
  const std::vector<std::string> said = lines_with(p.err, "warning");
  ASSERT_EQ(said.size(), 1u) << p.err;
  EXPECT_EQ(said[0].rfind("scene.pbrt:3:35: warning: PLY file \"" + ply +
                              "\": header line 3: skipped 'Created by Blender3D",
                          0),
            0u)
      << said[0];
}

// pbrt-v4's cornell box as pbrt-v4's own scene collection writes it (its structure and
// directives; the geometry cut to one wall of each material).
const char kV4Cornell[] = R"(LookAt 0 1 6.8  0 1 0  0 1 0
Camera "perspective" "float fov" 19.5
Sampler "zsobol" "integer pixelsamples" 1024
Integrator "volpath" "integer maxdepth" 100
Film "rgb" "string filename" "cornell-box.exr"
    "integer xresolution" [1024] "integer yresolution" [1024]

WorldBegin

MakeNamedMaterial "LeftWall" "string type" "diffuse" "rgb reflectance" [0.63 0.065 0.05]
MakeNamedMaterial "RightWall" "string type" "diffuse" "rgb reflectance" [0.14 0.45 0.091]
MakeNamedMaterial "Light" "string type" "diffuse" "rgb reflectance" [0.78 0.78 0.78]

NamedMaterial "LeftWall"
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
    "point3 P" [-1 0 1  -1 0 -1  -1 2 -1  -1 2 1]
    "normal N" [1 0 0  1 0 0  1 0 0  1 0 0]
NamedMaterial "RightWall"
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
    "point3 P" [1 0 -1  1 0 1  1 2 1  1 2 -1]
AttributeBegin
    AreaLightSource "diffuse" "rgb L" [17 12 4]
    NamedMaterial "Light"
    Shape "trianglemesh" "integer indices" [0 1 2 0 2 3]
        "point3 P" [-0.24 1.98 -0.22  0.23 1.98 -0.22  0.23 1.98 0.16  -0.24 1.98 0.16]
AttributeEnd
)";

TEST(FirstContact, PbrtV4CornellBoxNamesPbrtV3Equivalents) {
  const std::string dir = scratch_dir("FirstContact.V4Cornell");
  write_file(dir + "/cornell-box.pbrt", kV4Cornell);
  Outcome p = run_in(dir, kBin + "/pbrtc cornell-box.pbrt", "pbrtc");
  EXPECT_EQ(p.status, 1) << p.err;
  EXPECT_EQ(lines_of(p.err),
            (std::vector<std::string>{
                "cornell-box.pbrt:3:1: error: unknown sampler type \"zsobol\" (a pbrt-v4 name; "
                "pbrt-v3 calls it \"sobol\")",
                "cornell-box.pbrt:5:1: error: unknown film type \"rgb\" (a pbrt-v4 name; pbrt-v3 "
                "calls it \"image\")",
                "cornell-box.pbrt:10:44: error: unknown material type \"diffuse\" (a pbrt-v4 "
                "name; pbrt-v3 calls it \"matte\")",
                "cornell-box.pbrt:11:45: error: unknown material type \"diffuse\" (a pbrt-v4 "
                "name)",
                "cornell-box.pbrt:12:41: error: unknown material type \"diffuse\" (a pbrt-v4 "
                "name)",
                "cornell-box.pbrt:27:1: error: missing WorldEnd at end of input (pbrt-v4 scenes "
                "end without one; pbrt-v3 needs it)",
                "cornell-box.pbrt: 6 errors, 0 warnings; no archive written"}))
      << p.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/cornell-box.pbrta"));
}

}  // namespace
