// tests/compiler/frontend_errors_test.cpp — what the front end reports for bad scene text.
//
// Each test compiles a small scene and asserts the exact text of the first error, as pbrtc
// prints it: "path:line:col: error: message" with 1-based line and byte column, preceded by
// the gcc-style "In file included from" chain when the error lies in an Include. The last
// tests cover the error limit, warnings and --Werror.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "compiler/diagnostics.h"
#include "compiler/pbrt_v4_names.h"
#include "compiler/scene_builder.h"
#include "test_support.h"

namespace pbrtc {
namespace {

using testing_support::scratch_dir;
using testing_support::write_file;

constexpr const char* kPath = "scene.pbrt";
// Relative paths in the in-memory scenes resolve here; nothing exists there.
constexpr const char* kNoDir = "/nonexistent-pbrtc-test-dir";

// One compile of scene text held in memory (or of a file on disk).
struct Compile {
  SourceFiles files;
  Diagnostics diag{&files};
  SceneDesc scene;
  bool ok = false;

  explicit Compile(const std::string& text, const std::string& base_dir = kNoDir,
                   bool werror = false) {
    diag.werror = werror;
    ok = build_scene_from_string(kPath, text, base_dir, &files, &diag, &scene);
  }
  struct FromFile {};
  Compile(FromFile, const std::string& path) { ok = build_scene(path, &files, &diag, &scene); }

  std::vector<std::string> texts(Severity s) const {
    std::vector<std::string> out;
    for (const Diagnostic& d : diag.all())
      if (d.severity == s) out.push_back(d.text);
    return out;
  }
  std::vector<std::string> errors() const { return texts(Severity::kError); }
  std::vector<std::string> warnings() const { return texts(Severity::kWarning); }
  std::string first_error() const {
    std::vector<std::string> e = errors();
    return e.empty() ? "(no error)" : e.front();
  }
};

// The first error of a scene; also checks that the build reported failure.
std::string first_error(const std::string& text, const std::string& base_dir = kNoDir) {
  Compile c(text, base_dir);
  EXPECT_FALSE(c.ok);
  EXPECT_TRUE(c.diag.failed());
  return c.first_error();
}

// A scene with a world block around `world`.
std::string in_world(const std::string& world) {
  return "WorldBegin\n" + world + "WorldEnd\n";
}

// ---- Directives and types ----

TEST(FrontendErrors, UnknownDirectiveIsNamedAtItsStart) {
  EXPECT_EQ(first_error(in_world("  Shpe \"sphere\"\n")),
            "scene.pbrt:2:3: error: unknown directive 'Shpe'");
}

TEST(FrontendErrors, UnknownShapeTypeSuggestsTheNearMiss) {
  EXPECT_EQ(first_error(in_world("Shape \"sphee\"\n")),
            "scene.pbrt:2:1: error: unknown shape type \"sphee\" (did you mean \"sphere\"?)");
}

TEST(FrontendErrors, UnknownMaterialType) {
  EXPECT_EQ(first_error(in_world("Material \"matt\"\n")),
            "scene.pbrt:2:1: error: unknown material type \"matt\" (did you mean \"matte\"?)");
}

TEST(FrontendErrors, UnknownLightType) {
  EXPECT_EQ(first_error(in_world("LightSource \"sun\"\n")),
            "scene.pbrt:2:1: error: unknown light type \"sun\"");
}

TEST(FrontendErrors, UnknownAreaLightType) {
  EXPECT_EQ(first_error(in_world("AreaLightSource \"diffuze\"\n")),
            "scene.pbrt:2:1: error: unknown area light type \"diffuze\" (did you mean "
            "\"diffuse\"?)");
}

TEST(FrontendErrors, UnknownCameraType) {
  EXPECT_EQ(first_error("Camera \"fisheye\"\nWorldBegin\nWorldEnd\n"),
            "scene.pbrt:1:1: error: unknown camera type \"fisheye\"");
}

TEST(FrontendErrors, UnknownSamplerType) {
  EXPECT_EQ(first_error("Sampler \"bluenoise\"\nWorldBegin\nWorldEnd\n"),
            "scene.pbrt:1:1: error: unknown sampler type \"bluenoise\"");
}

TEST(FrontendErrors, UnknownFilterType) {
  EXPECT_EQ(first_error("PixelFilter \"lanczos\"\nWorldBegin\nWorldEnd\n"),
            "scene.pbrt:1:1: error: unknown filter type \"lanczos\"");
}

TEST(FrontendErrors, UnknownFilmType) {
  EXPECT_EQ(first_error("Film \"hdr\"\nWorldBegin\nWorldEnd\n"),
            "scene.pbrt:1:1: error: unknown film type \"hdr\"");
}

TEST(FrontendErrors, UnknownIntegratorType) {
  EXPECT_EQ(first_error("Integrator \"pathh\"\nWorldBegin\nWorldEnd\n"),
            "scene.pbrt:1:1: error: unknown integrator type \"pathh\" (did you mean \"path\"?)");
}

TEST(FrontendErrors, UnknownMediumTypeIsReportedAtTheTypeValue) {
  EXPECT_EQ(first_error("MakeNamedMedium \"m\" \"string type\" \"fog\"\nWorldBegin\nWorldEnd\n"),
            "scene.pbrt:1:35: error: unknown medium type \"fog\"");
}

TEST(FrontendErrors, UnknownAcceleratorType) {
  EXPECT_EQ(first_error("Accelerator \"octree\"\nWorldBegin\nWorldEnd\n"),
            "scene.pbrt:1:1: error: unknown accelerator type \"octree\" (did you mean "
            "\"kdtree\"?)");
}

TEST(FrontendErrors, UnknownFloatTextureType) {
  EXPECT_EQ(first_error(in_world("Texture \"t\" \"float\" \"wood\"\n")),
            "scene.pbrt:2:1: error: unknown float texture type \"wood\"");
}

TEST(FrontendErrors, UnknownSpectrumTextureType) {
  EXPECT_EQ(first_error(in_world("Texture \"t\" \"spectrum\" \"checkerbord\"\n")),
            "scene.pbrt:2:1: error: unknown spectrum texture type \"checkerbord\" (did you mean "
            "\"checkerboard\"?)");
}

TEST(FrontendErrors, TextureClassOtherThanFloatOrSpectrum) {
  EXPECT_EQ(first_error(in_world("Texture \"t\" \"vector\" \"constant\"\n")),
            "scene.pbrt:2:1: error: unknown texture class \"vector\" (pbrt-v3 has \"float\" and "
            "\"spectrum\")");
}

// ---- Parameter declarations and values ----

TEST(FrontendErrors, DeclarationWithOnlyATypeIsMalformed) {
  EXPECT_EQ(first_error(in_world("Shape \"sphere\" \"float\" 1\n")),
            "scene.pbrt:2:16: error: malformed parameter declaration \"float\": expected \"type "
            "name\"");
}

TEST(FrontendErrors, DeclarationWithThreeWordsIsMalformed) {
  EXPECT_EQ(first_error(in_world("Shape \"sphere\" \"float radius x\" 1\n")),
            "scene.pbrt:2:16: error: malformed parameter declaration \"float radius x\": "
            "expected \"type name\"");
}

TEST(FrontendErrors, UnknownParameterType) {
  EXPECT_EQ(first_error(in_world("Shape \"sphere\" \"double radius\" 1\n")),
            "scene.pbrt:2:16: error: unknown parameter type 'double' in \"double radius\"");
}

TEST(FrontendErrors, StringGivenForAFloat) {
  EXPECT_EQ(first_error(in_world("Shape \"sphere\" \"float radius\" \"big\"\n")),
            "scene.pbrt:2:31: error: parameter \"float radius\" takes numbers, got \"big\"");
}

TEST(FrontendErrors, NumberGivenForAString) {
  EXPECT_EQ(first_error(in_world("Shape \"plymesh\" \"string filename\" 3\n")),
            "scene.pbrt:2:35: error: parameter \"string filename\" takes quoted strings, got '3'");
}

TEST(FrontendErrors, BoolMustBeQuotedTrueOrFalse) {
  EXPECT_EQ(first_error(in_world("AreaLightSource \"diffuse\" \"bool twosided\" \"yes\"\n")),
            "scene.pbrt:2:43: error: value \"yes\" of bool parameter \"bool twosided\" must be "
            "\"true\" or \"false\"");
}

TEST(FrontendErrors, IntegerGivenAFraction) {
  EXPECT_EQ(first_error("Sampler \"halton\" \"integer pixelsamples\" 1.5\nWorldBegin\nWorldEnd\n"),
            "scene.pbrt:1:41: error: expected an integer, got '1.5'");
}

TEST(FrontendErrors, IntegerOutOfRange) {
  EXPECT_EQ(first_error("Sampler \"halton\" \"integer pixelsamples\" [ 99999999999 ]\n"
                        "WorldBegin\nWorldEnd\n"),
            "scene.pbrt:1:43: error: integer '99999999999' is out of range");
}

TEST(FrontendErrors, MalformedNumber) {
  EXPECT_EQ(first_error(in_world("Shape \"sphere\" \"float radius\" [ 1.2.3 ]\n")),
            "scene.pbrt:2:33: error: malformed number '1.2.3'");
}

TEST(FrontendErrors, ParameterWithoutValue) {
  EXPECT_EQ(first_error(in_world("Shape \"sphere\" \"float radius\"\n")),
            "scene.pbrt:3:1: error: parameter \"float radius\" has no value (got 'WorldEnd')");
}

TEST(FrontendErrors, EmptyArrayHasNoValues) {
  EXPECT_EQ(first_error(in_world("Shape \"sphere\" \"float radius\" [ ]\n")),
            "scene.pbrt:2:33: error: parameter \"float radius\" has no values");
}

// ---- Value counts ----

TEST(FrontendErrors, RgbOfTwoNumbers) {
  EXPECT_EQ(first_error(in_world("Material \"matte\" \"rgb Kd\" [0.1 0.2]\n")),
            "scene.pbrt:2:28: error: parameter \"rgb Kd\" needs 3 values per color, got 2 values");
}

TEST(FrontendErrors, TransformOfFifteenNumbers) {
  EXPECT_EQ(first_error(in_world("Transform [1 0 0 0 0 1 0 0 0 0 1 0 0 0 0]\n")),
            "scene.pbrt:2:11: error: Transform needs 16 numbers, got 15");
}

TEST(FrontendErrors, ConcatTransformWithoutBrackets) {
  EXPECT_EQ(first_error(in_world("ConcatTransform 1 0 0 0\n")),
            "scene.pbrt:2:17: error: ConcatTransform needs 16 numbers in [ ], got '1'");
}

TEST(FrontendErrors, Point3ArrayNotAMultipleOfThree) {
  EXPECT_EQ(first_error(in_world("Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 1 1] "
                                 "\"integer indices\" [0 1 2]\n")),
            "scene.pbrt:2:34: error: parameter \"point3 P\" needs 3 values per element, got 8 "
            "values");
}

TEST(FrontendErrors, RotateWithTooFewNumbers) {
  EXPECT_EQ(first_error(in_world("Rotate 90 0 1\n")),
            "scene.pbrt:3:1: error: Rotate needs 4 numbers (angle x y z), got 3 before "
            "'WorldEnd'");
}

TEST(FrontendErrors, TranslateWithTooFewNumbers) {
  EXPECT_EQ(first_error(in_world("Translate 1 2\n")),
            "scene.pbrt:3:1: error: Translate needs 3 numbers (x y z), got 2 before 'WorldEnd'");
}

TEST(FrontendErrors, LookAtWithTooFewNumbers) {
  EXPECT_EQ(first_error("LookAt 0 0 0  0 0 1  0 1\nWorldBegin\nWorldEnd\n"),
            "scene.pbrt:2:1: error: LookAt needs 9 numbers (eye, look and up points), got 8 "
            "before 'WorldBegin'");
}

TEST(FrontendErrors, ScaleCutShortByEndOfFile) {
  EXPECT_EQ(first_error("WorldBegin\nScale 1 2"),
            "scene.pbrt:2:10: error: Scale needs 3 numbers (x y z), got 2 before the end of file");
}

TEST(FrontendErrors, MissingDirectiveArgumentDoesNotSwallowTheNextDirective) {
  // WorldEnd is read as the next directive: no "missing WorldEnd" follows.
  Compile c(in_world("Texture \"a\" \"float\"\nTransform\nActiveTransform\nNamedMaterial\n"));
  EXPECT_EQ(c.errors(),
            (std::vector<std::string>{
                "scene.pbrt:3:1: error: Texture needs a quoted texture type, got 'Transform'",
                "scene.pbrt:4:1: error: Transform needs 16 numbers in [ ], got 'ActiveTransform'",
                "scene.pbrt:5:1: error: ActiveTransform needs StartTime, EndTime or All, got "
                "'NamedMaterial'",
                "scene.pbrt:6:1: error: NamedMaterial needs a quoted material name, got "
                "'WorldEnd'"}));
}

TEST(FrontendErrors, ScalarParameterGivenTwoValues) {
  EXPECT_EQ(first_error(in_world("Shape \"sphere\" \"float radius\" [1 2]\n")),
            "scene.pbrt:2:32: error: parameter \"float radius\" of sphere shape takes one value, "
            "got 2");
}

TEST(FrontendErrors, CropWindowOfThreeValues) {
  EXPECT_EQ(first_error("Film \"image\" \"float cropwindow\" [0 1 0]\nWorldBegin\nWorldEnd\n"),
            "scene.pbrt:1:34: error: parameter \"float cropwindow\" of image film takes 4 values, "
            "got 3");
}

TEST(FrontendErrors, CropWindowIsOrderedAndClampedWithAWarning) {
  // pbrt-v3 silently takes min/max of each pair and clamps them to [0, 1].
  Compile c("Film \"image\" \"float cropwindow\" [0.6 0.4 -0.1 1.2]\nWorldBegin\nWorldEnd\n");
  EXPECT_TRUE(c.ok);
  EXPECT_EQ(c.warnings(), std::vector<std::string>{
                              "scene.pbrt:1:34: warning: film cropwindow [0.6 0.4 -0.1 1.2] is "
                              "read as [0.4 0.6 0 1] (pbrt-v3 orders each pair and clamps it to "
                              "[0, 1])"});
  uint32_t n = 0;
  const float* crop = c.scene.film.get_floats("cropwindow", &n);
  ASSERT_EQ(n, 4u);
  EXPECT_EQ(std::vector<float>(crop, crop + 4), (std::vector<float>{0.4f, 0.6f, 0, 1}));
}

TEST(FrontendErrors, EmptyCropWindow) {
  EXPECT_EQ(
      first_error("Film \"image\" \"float cropwindow\" [0.5 0.5 0 1]\nWorldBegin\nWorldEnd\n"),
      "scene.pbrt:1:34: error: film cropwindow [x0 x1 y0 y1] is empty (needs x0 < x1 and y0 < "
      "y1)");
}

// ---- Curves and heterogeneous media: pbrt-v3's checks across parameters ----

// Four control points: one cubic Bezier segment, or two quadratic B-spline segments.
constexpr const char* kCurveP = "\"point3 P\" [0 0 0 1 1 0 2 1 0 3 0 0]";

std::string curve(const std::string& more, const char* P = kCurveP) {
  return in_world(std::string("Shape \"curve\" ") + P + more + "\n");
}

TEST(FrontendErrors, CurvesPbrtV3AcceptsCompile) {
  for (const std::string& more :
       {std::string(), std::string(" \"string basis\" \"bspline\" \"integer degree\" 2"),
        std::string(" \"string type\" \"ribbon\" \"normal N\" [0 0 1 0 0 1]"),
        std::string(" \"string type\" \"cylinder\"")}) {
    Compile c(curve(more));
    EXPECT_TRUE(c.ok) << more << ": " << c.first_error();
    EXPECT_TRUE(c.warnings().empty()) << more;
  }
  // pbrt-v3's Bezier test passes 7 points of a cubic (two segments) and, degree 2, 1 point
  // (no segment at all).
  EXPECT_TRUE(Compile(curve("", "\"point3 P\" [0 0 0 1 1 0 2 1 0 3 0 0 4 1 0 5 1 0 6 0 0]")).ok);
  EXPECT_TRUE(Compile(curve(" \"integer degree\" 2", "\"point3 P\" [0 0 0]")).ok);
}

TEST(FrontendErrors, CurveDegreeBasisAndType) {
  EXPECT_EQ(first_error(curve(" \"integer degree\" 4")),
            "scene.pbrt:2:69: error: curve \"degree\" 4: only degree 2 and 3 curves are supported");
  EXPECT_EQ(first_error(curve(" \"string basis\" \"catmull\"")),
            "scene.pbrt:2:67: error: curve \"basis\" \"catmull\": only \"bezier\" and "
            "\"bspline\" are supported");
  EXPECT_EQ(first_error(curve(" \"string type\" \"tube\"")),
            "scene.pbrt:2:66: error: curve \"type\" \"tube\" unknown: \"flat\", \"ribbon\" or "
            "\"cylinder\" (pbrt-v3 would use \"cylinder\")");
}

TEST(FrontendErrors, CurveControlPointCounts) {
  EXPECT_EQ(first_error(curve("", "\"point3 P\" [0 0 0 1 1 0 2 1 0 3 0 0 4 0 0]")),
            "scene.pbrt:2:27: error: curve has 5 control points: a degree 3 Bezier curve needs "
            "3 n + 4 for some n >= 0");
  EXPECT_EQ(first_error(curve(" \"string basis\" \"bspline\"", "\"point3 P\" [0 0 0 1 1 0 2 1 0]")),
            "scene.pbrt:2:27: error: curve has 3 control points: a degree 3 B-spline needs at "
            "least 4");
}

TEST(FrontendErrors, RibbonCurveNormals) {
  EXPECT_EQ(first_error(curve(" \"string type\" \"ribbon\"")),
            "scene.pbrt:2:1: error: a \"ribbon\" curve needs normals \"N\" at its segments' ends");
  EXPECT_EQ(first_error(curve(" \"string type\" \"ribbon\" \"normal N\" [0 0 1]")),
            "scene.pbrt:2:87: error: a ribbon curve of 1 segment needs 2 normals, not 1");
  // Normals on another type are ignored with a warning, as pbrt-v3 does.
  Compile flat(curve(" \"normal N\" [0 0 1 0 0 1]"));
  EXPECT_TRUE(flat.ok) << flat.first_error();
  EXPECT_EQ(flat.warnings(),
            std::vector<std::string>{"scene.pbrt:2:64: warning: curve normals are only used by "
                                     "\"ribbon\" curves (ignored, as pbrt-v3 does)"});
}

TEST(FrontendErrors, HeterogeneousMediumDensityCount) {
  const std::string medium =
      "MakeNamedMedium \"smoke\" \"string type\" \"heterogeneous\" \"integer nx\" 2 "
      "\"integer ny\" 2 \"integer nz\" 2 ";
  EXPECT_TRUE(Compile(in_world(medium + "\"float density\" [1 2 3 4 5 6 7 8]\n")).ok);
  EXPECT_EQ(first_error(in_world(medium + "\"float density\" [1 2 3 4 5 6 7]\n")),
            "scene.pbrt:2:117: error: heterogeneous medium has 7 density values; nx * ny * nz = "
            "2 * 2 * 2 = 8");
  EXPECT_EQ(first_error(in_world(medium + "\n")),
            "scene.pbrt:2:1: error: heterogeneous medium needs parameter \"float density\"");
  // Three int32s whose product needs more than 64 bits.
  EXPECT_EQ(first_error(in_world("MakeNamedMedium \"m\" \"string type\" \"heterogeneous\" "
                                 "\"float density\" [1] \"integer nx\" 2000000000 "
                                 "\"integer ny\" 2000000000 \"integer nz\" 2000000000\n")),
            "scene.pbrt:2:68: error: heterogeneous medium has 1 density values; nx * ny * nz = "
            "2000000000 * 2000000000 * 2000000000");
}

// A measured preset is resolved by pbrtc: the archive holds its coefficients (pbrt-v3's table,
// mm^-1), and given sigma_a/sigma_s win over it, as in pbrt-v3's MakeMedium.
TEST(FrontendErrors, MediumPresetIsResolvedAtCompileTime) {
  Compile c(
      in_world("MakeNamedMedium \"m\" \"string type\" \"homogeneous\" \"string preset\" "
               "\"Skin1\"\nMakeNamedMedium \"n\" \"string type\" \"homogeneous\" "
               "\"string preset\" \"Ketchup\" \"rgb sigma_s\" [1 2 3]\n"));
  ASSERT_TRUE(c.ok) << c.first_error();
  ASSERT_EQ(c.scene.media.size(), 2u);
  const Entity& skin = c.scene.media[0].params;
  EXPECT_EQ(std::vector<float>(skin.get_floats("sigma_a"), skin.get_floats("sigma_a") + 3),
            (std::vector<float>{0.032f, 0.17f, 0.48f}));
  EXPECT_EQ(std::vector<float>(skin.get_floats("sigma_s"), skin.get_floats("sigma_s") + 3),
            (std::vector<float>{0.74f, 0.88f, 1.01f}));
  EXPECT_TRUE(skin.given("sigma_a"));
  const Entity& ketchup = c.scene.media[1].params;
  EXPECT_EQ(std::vector<float>(ketchup.get_floats("sigma_a"), ketchup.get_floats("sigma_a") + 3),
            (std::vector<float>{0.061f, 0.97f, 1.45f}));
  EXPECT_EQ(std::vector<float>(ketchup.get_floats("sigma_s"), ketchup.get_floats("sigma_s") + 3),
            (std::vector<float>{1, 2, 3}));
}

// The subsurface material's preset is resolved by pbrtc too, with g forced to 0 as pbrt-v3
// does (the table holds reduced coefficients), and its profile table is derived for its g and
// eta (format/bssrdf_table.h).
TEST(FrontendErrors, SubsurfacePresetAndTable) {
  Compile c(
      in_world("Material \"subsurface\" \"string name\" \"Skin1\" \"float g\" 0.7\n"
               "Shape \"sphere\"\nMaterial \"kdsubsurface\" \"float eta\" 1.5\n"
               "Shape \"sphere\"\n"));
  ASSERT_TRUE(c.ok) << c.first_error();
  const Entity* skin = nullptr;
  const Entity* kd = nullptr;
  for (const MaterialDesc& m : c.scene.materials) {
    if (m.params.type_name() == "subsurface") skin = &m.params;
    if (m.params.type_name() == "kdsubsurface") kd = &m.params;
  }
  ASSERT_TRUE(skin && kd);
  EXPECT_EQ(std::vector<float>(skin->get_floats("sigma_a"), skin->get_floats("sigma_a") + 3),
            (std::vector<float>{0.032f, 0.17f, 0.48f}));
  EXPECT_EQ(std::vector<float>(skin->get_floats("sigma_s"), skin->get_floats("sigma_s") + 3),
            (std::vector<float>{0.74f, 0.88f, 1.01f}));
  EXPECT_EQ(skin->get_float("g"), 0);
  for (const Entity* e : {skin, kd}) {
    uint32_t n_rho = 0, n_profile = 0;
    e->get_floats("bssrdfrho", &n_rho);
    e->get_floats("bssrdfprofile", &n_profile);
    EXPECT_EQ(n_rho, 100u);
    EXPECT_EQ(n_profile, 6400u);
  }
  // The profile depends on eta: the two tables differ.
  uint32_t n = 0;
  const float* a = skin->get_floats("bssrdfrhoeff", &n);
  const float* b = kd->get_floats("bssrdfrhoeff");
  EXPECT_NE(a[n - 1], b[n - 1]);
  EXPECT_EQ(
      first_error(in_world("Material \"subsurface\" \"string name\" \"Skin7\"\n")).substr(0, 72),
      "scene.pbrt:2:37: error: unknown subsurface preset \"Skin7\" (known: Apple,");
}

TEST(FrontendErrors, GridMediumWithColouredExtinctionWarns) {
  Compile c(
      in_world("MakeNamedMedium \"m\" \"string type\" \"heterogeneous\" "
               "\"float density\" [1] \"rgb sigma_a\" [1 2 3] \"rgb sigma_s\" [1 1 1]\n"));
  EXPECT_TRUE(c.ok) << c.first_error();
  EXPECT_EQ(c.warnings(),
            std::vector<std::string>{"scene.pbrt:2:1: warning: heterogeneous medium: sigma_a + "
                                     "sigma_s differs between channels; its extinction is the "
                                     "red channel's in all three (as in pbrt-v3)"});
  EXPECT_TRUE(Compile(in_world("MakeNamedMedium \"m\" \"string type\" \"heterogeneous\" "
                               "\"float density\" [1] \"rgb sigma_a\" [1 2 3] "
                               "\"rgb sigma_s\" [3 2 1]\n"))
                  .warnings()
                  .empty());
}

TEST(FrontendErrors, MediumBadValues) {
  const std::string unknown =
      first_error(in_world("MakeNamedMedium \"m\" \"string type\" \"homogeneous\" "
                           "\"string preset\" \"Skin3\"\n"));
  EXPECT_EQ(unknown.substr(0, 79),
            "scene.pbrt:2:65: error: unknown medium preset \"Skin3\" (known: Apple, Chicken1, ");
  EXPECT_EQ(first_error(in_world("MakeNamedMedium \"m\" \"string type\" \"homogeneous\" "
                                 "\"rgb sigma_s\" [1 -0.5 1]\n")),
            "scene.pbrt:2:64: error: medium \"sigma_s\" has a negative component");
  EXPECT_EQ(first_error(in_world("MakeNamedMedium \"m\" \"string type\" \"homogeneous\" "
                                 "\"float scale\" -2\n")),
            "scene.pbrt:2:63: error: medium \"scale\" must not be negative");
  EXPECT_EQ(first_error(in_world("MakeNamedMedium \"m\" \"string type\" \"homogeneous\" "
                                 "\"float g\" -1\n")),
            "scene.pbrt:2:59: error: medium \"g\" must lie in (-1, 1): Henyey-Greenstein has no "
            "density at +-1");
  EXPECT_EQ(first_error(in_world("MakeNamedMedium \"m\" \"string type\" \"heterogeneous\" "
                                 "\"integer nx\" 2 \"float density\" [0.5 -1]\n")),
            "scene.pbrt:2:83: error: heterogeneous medium density value 1 is -1.000000 "
            "(densities are finite and not negative)");
}

// ---- Meshes ----

constexpr const char* kTriangleP = "\"point3 P\" [0 0 0 1 0 0 1 1 0]";

TEST(FrontendErrors, MeshIndexOutOfRange) {
  EXPECT_EQ(first_error(in_world(std::string("Shape \"trianglemesh\" ") + kTriangleP +
                                 " \"integer indices\" [0 1 3]\n")),
            "scene.pbrt:2:72: error: trianglemesh index 3 (entry 2) is out of range: 3 vertices");
}

TEST(FrontendErrors, MeshIndexNegative) {
  EXPECT_EQ(first_error(in_world(std::string("Shape \"trianglemesh\" ") + kTriangleP +
                                 " \"integer indices\" [0 -1 2]\n")),
            "scene.pbrt:2:72: error: trianglemesh index -1 (entry 1) is out of range: 3 vertices");
}

TEST(FrontendErrors, MeshIndicesNotAMultipleOfThree) {
  EXPECT_EQ(first_error(in_world(std::string("Shape \"trianglemesh\" ") + kTriangleP +
                                 " \"integer indices\" [0 1 2 0]\n")),
            "scene.pbrt:2:72: error: trianglemesh has 4 indices, not a multiple of 3");
}

TEST(FrontendErrors, MeshIndicesMissingForMoreThanThreeVertices) {
  EXPECT_EQ(
      first_error(in_world("Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 1 1 0 0 1 0]\n")),
      "scene.pbrt:2:1: error: trianglemesh shape needs parameter \"integer indices\"");
}

TEST(FrontendErrors, MeshIndicesDeclaredFloatWarnsThenIsMissing) {
  Compile c(in_world(std::string("Shape \"trianglemesh\" ") + kTriangleP +
                     " \"float indices\" [0 1 2]\n"));
  EXPECT_EQ(c.warnings(),
            std::vector<std::string>{"scene.pbrt:2:53: warning: parameter \"float indices\" of "
                                     "trianglemesh shape should be integer; it is ignored "
                                     "(pbrt-v3 does not use it either)"});
  EXPECT_EQ(c.errors(), std::vector<std::string>{"scene.pbrt:2:1: error: trianglemesh shape "
                                                 "needs parameter \"integer indices\""});
}

TEST(FrontendErrors, MeshUvCountWrong) {
  EXPECT_EQ(first_error(in_world(std::string("Shape \"trianglemesh\" ") + kTriangleP +
                                 " \"integer indices\" [0 1 2] \"float uv\" [0 0 1 0]\n")),
            "scene.pbrt:2:91: error: trianglemesh \"float uv\" has 4 numbers; 3 vertices need 6");
}

TEST(FrontendErrors, MeshNormalCountWrong) {
  EXPECT_EQ(first_error(in_world(std::string("Shape \"trianglemesh\" ") + kTriangleP +
                                 " \"integer indices\" [0 1 2] \"normal N\" [0 0 1]\n")),
            "scene.pbrt:2:91: error: trianglemesh \"normal N\" has 1 elements for 3 vertices");
}

TEST(FrontendErrors, MissingPlyFile) {
  std::string dir = scratch_dir("FrontendErrors.MissingPlyFile");
  EXPECT_EQ(first_error(in_world("Shape \"plymesh\" \"string filename\" \"nope.ply\"\n"), dir),
            "scene.pbrt:2:35: error: cannot open file \"" + dir +
                "/nope.ply\" named by parameter \"string filename\"");
}

TEST(FrontendErrors, RequiredParameterOfTheWrongTypeIsAnError) {
  Compile c(in_world("Shape \"plymesh\" \"texture filename\" \"x.ply\"\n"));
  EXPECT_FALSE(c.ok);
  EXPECT_EQ(c.first_error(),
            "scene.pbrt:2:1: error: plymesh shape needs parameter \"string filename\"");
  ASSERT_EQ(c.warnings().size(), 1u);
}

// ---- Undefined names ----

TEST(FrontendErrors, UndefinedNamedMaterial) {
  EXPECT_EQ(first_error(in_world("NamedMaterial \"gold\"\n")),
            "scene.pbrt:2:1: error: undefined named material \"gold\"");
}

TEST(FrontendErrors, UndefinedFloatTextureIsReportedAtItsName) {
  EXPECT_EQ(first_error(in_world("Material \"matte\" \"texture sigma\" \"rough\"\n")),
            "scene.pbrt:2:34: error: undefined float texture \"rough\" for parameter \"texture "
            "sigma\"");
}

TEST(FrontendErrors, UndefinedSpectrumTexture) {
  EXPECT_EQ(first_error(in_world("Material \"matte\" \"texture Kd\" \"checks\"\n")),
            "scene.pbrt:2:31: error: undefined spectrum texture \"checks\" for parameter \"texture "
            "Kd\"");
}

TEST(FrontendErrors, UndefinedSpectrumTextureNamesTheFloatOneOfThatName) {
  EXPECT_EQ(first_error(in_world("Texture \"c\" \"float\" \"constant\"\n"
                                 "Material \"matte\" \"texture Kd\" \"c\"\n")),
            "scene.pbrt:3:31: error: undefined spectrum texture \"c\" for parameter \"texture Kd\" "
            "(there is a float texture of that name)");
}

TEST(FrontendErrors, UndefinedMediumIsReportedOnceAtTheMediumInterface) {
  Compile c(in_world("MediumInterface \"fog\"\nShape \"sphere\"\nShape \"sphere\"\n"));
  EXPECT_EQ(c.errors(), std::vector<std::string>{"scene.pbrt:2:1: error: undefined medium \"fog\" "
                                                 "(named in MediumInterface)"});
}

TEST(FrontendErrors, UndefinedObject) {
  EXPECT_EQ(first_error(in_world("ObjectInstance \"tree\"\n")),
            "scene.pbrt:2:1: error: undefined object \"tree\"");
}

TEST(FrontendErrors, UndefinedCoordinateSystem) {
  EXPECT_EQ(first_error(in_world("CoordSysTransform \"lamp\"\n")),
            "scene.pbrt:2:1: error: undefined coordinate system \"lamp\"");
}

TEST(FrontendErrors, MixMaterialNamingAnUndefinedMaterial) {
  EXPECT_EQ(first_error(in_world("MakeNamedMaterial \"a\" \"string type\" \"matte\"\n"
                                 "Material \"mix\" \"string namedmaterial1\" \"a\" "
                                 "\"string namedmaterial2\" \"b\"\n")),
            "scene.pbrt:3:68: error: undefined named material \"b\" in mix material");
}

TEST(FrontendErrors, MixMaterialWithoutNamesReportsEachOnce) {
  Compile c(in_world("Material \"mix\"\n"));
  EXPECT_EQ(c.errors(),
            (std::vector<std::string>{
                "scene.pbrt:2:1: error: mix material needs parameter \"string namedmaterial1\"",
                "scene.pbrt:2:1: error: mix material needs parameter \"string namedmaterial2\""}));
}

TEST(FrontendErrors, MakeNamedMaterialWithoutStringType) {
  EXPECT_EQ(first_error(in_world("MakeNamedMaterial \"a\" \"rgb Kd\" [1 1 1]\n")),
            "scene.pbrt:2:1: error: MakeNamedMaterial \"a\" needs a \"string type\" parameter");
}

TEST(FrontendErrors, MakeNamedMediumWithoutStringType) {
  EXPECT_EQ(first_error("MakeNamedMedium \"m\" \"float g\" 0\nWorldBegin\nWorldEnd\n"),
            "scene.pbrt:1:1: error: MakeNamedMedium \"m\" needs a \"string type\" parameter");
}

// ---- Include ----

TEST(FrontendErrors, MissingIncludeFile) {
  std::string dir = scratch_dir("FrontendErrors.MissingIncludeFile");
  EXPECT_EQ(first_error("Include \"nope.pbrt\"\nWorldBegin\nWorldEnd\n", dir),
            "scene.pbrt:1:1: error: cannot open Include file \"" + dir +
                "/nope.pbrt\": No such file or directory");
}

TEST(FrontendErrors, IncludeCycleShowsTheIncludeChain) {
  std::string dir = scratch_dir("FrontendErrors.IncludeCycle");
  std::string top = write_file(dir + "/top.pbrt", "WorldBegin\nInclude \"a.pbrt\"\nWorldEnd\n");
  write_file(dir + "/a.pbrt", "Include \"b.pbrt\"\n");
  write_file(dir + "/b.pbrt", "# b\nShape \"sphere\"\nInclude \"a.pbrt\"\n");
  Compile c(Compile::FromFile{}, top);
  EXPECT_FALSE(c.ok);
  EXPECT_EQ(c.errors(), std::vector<std::string>{"In file included from " + dir + "/a.pbrt:1,\n" +
                                                 "                 from " + dir + "/top.pbrt:2:\n" +
                                                 dir + "/b.pbrt:3:1: error: Include cycle: \"" +
                                                 dir + "/a.pbrt\" is already being read"});
  // The sphere before the cycle still counts.
  EXPECT_EQ(c.scene.shapes.size(), 1u);
}

TEST(FrontendErrors, ErrorInsideAnIncludeNamesTheIncludeLine) {
  std::string dir = scratch_dir("FrontendErrors.ErrorInsideInclude");
  write_file(dir + "/geometry.pbrt", "\n  Shape \"cube\"\n");
  EXPECT_EQ(first_error("WorldBegin\n\nInclude \"geometry.pbrt\"\nWorldEnd\n", dir),
            "In file included from scene.pbrt:3:\n" + dir +
                "/geometry.pbrt:2:3: error: unknown shape type \"cube\" (did you mean \"cone\"?)");
}

// ---- Strings and bytes ----

TEST(FrontendErrors, UnterminatedStringAtNewlineReportsItsStart) {
  Compile c(in_world("Shape \"sphere\" \"float radius 1\n"));
  // The lexical error ends the file; nothing that follows from it is reported.
  EXPECT_EQ(c.errors(), std::vector<std::string>{"scene.pbrt:2:16: error: unterminated string (a "
                                                 "quoted string cannot span lines)"});
}

TEST(FrontendErrors, UnterminatedStringAtEndOfFileReportsItsStart) {
  Compile c("WorldBegin\nWorldEnd\nNamedMaterial \"ab");
  EXPECT_EQ(c.errors(), std::vector<std::string>{"scene.pbrt:3:15: error: unterminated string "
                                                 "(end of file inside quotes)"});
}

TEST(FrontendErrors, NulByteIsNotSceneText) {
  Compile c(in_world(std::string("Shape \"sphere\"") + '\0' + "\n"));
  EXPECT_EQ(c.errors(), std::vector<std::string>{"scene.pbrt:2:15: error: unexpected byte 0x00 "
                                                 "outside a string or comment: is this a text "
                                                 "file?"});
}

TEST(FrontendErrors, FFBytesAreNotSceneText) {
  Compile c(in_world("\xFF\xFFShape \"sphere\"\n"));
  EXPECT_EQ(c.errors(), std::vector<std::string>{"scene.pbrt:2:1: error: unexpected byte 0xFF "
                                                 "outside a string or comment: is this a text "
                                                 "file?"});
}

TEST(FrontendErrors, ControlByteInsideAString) {
  EXPECT_EQ(first_error(in_world("Shape \"sph\x01"
                                 "ere\"\n")),
            "scene.pbrt:2:11: error: control byte 0x01 inside a string: is this a text file?");
}

TEST(FrontendErrors, NulByteInsideAnArrayDoesNotCascade) {
  Compile c(in_world(std::string("Shape \"sphere\" \"float radius\" [ 1 ") + '\0' + " ]\n"));
  EXPECT_EQ(c.errors(), std::vector<std::string>{"scene.pbrt:2:35: error: unexpected byte 0x00 "
                                                 "outside a string or comment: is this a text "
                                                 "file?"});
}

TEST(FrontendErrors, UnterminatedArray) {
  EXPECT_EQ(first_error("WorldBegin\nShape \"sphere\" \"float radius\" [ 1 "),
            "scene.pbrt:2:35: error: unterminated '[' array at end of file");
}

// ---- Blocks ----

TEST(FrontendErrors, AttributeEndWithoutBegin) {
  EXPECT_EQ(first_error(in_world("AttributeEnd\n")),
            "scene.pbrt:2:1: error: AttributeEnd without a matching AttributeBegin");
}

TEST(FrontendErrors, TransformEndClosingAnAttributeBegin) {
  EXPECT_EQ(first_error(in_world("AttributeBegin\nTransformEnd\nAttributeEnd\n")),
            "scene.pbrt:3:1: error: TransformEnd closes the AttributeBegin at scene.pbrt:2:1");
}

TEST(FrontendErrors, BlockLeftOpenAtWorldEndIsOnlyAWarning) {
  // pbrt-v3 warns ("Missing end to pbrtAttributeBegin()") and closes it: the scene is complete.
  Compile c(in_world("AttributeBegin\n  TransformBegin\n"));
  EXPECT_TRUE(c.ok);
  EXPECT_EQ(c.warnings(), (std::vector<std::string>{
                              "scene.pbrt:2:1: warning: AttributeBegin is not closed before the "
                              "WorldEnd at scene.pbrt:4:1",
                              "scene.pbrt:3:3: warning: TransformBegin is not closed before the "
                              "WorldEnd at scene.pbrt:4:1"}));
}

TEST(FrontendErrors, BlocksLeftOpenAtEndOfFileAreEachReported) {
  Compile c("WorldBegin\nAttributeBegin\n  TransformBegin\n");
  EXPECT_EQ(c.errors(), (std::vector<std::string>{
                            "scene.pbrt:2:1: error: AttributeBegin is not closed at end of file",
                            "scene.pbrt:3:3: error: TransformBegin is not closed at end of file",
                            "scene.pbrt:4:1: error: missing WorldEnd at end of input"}));
}

TEST(FrontendErrors, NestedObjectBegin) {
  EXPECT_EQ(first_error(in_world("ObjectBegin \"a\"\nObjectBegin \"b\"\nObjectEnd\n")),
            "scene.pbrt:3:1: error: ObjectBegin \"b\" inside the definition of \"a\": object "
            "definitions cannot nest");
}

TEST(FrontendErrors, ObjectInstanceInsideObjectBegin) {
  EXPECT_EQ(first_error(in_world("ObjectBegin \"a\"\nObjectEnd\nObjectBegin \"b\"\n"
                                 "ObjectInstance \"a\"\nObjectEnd\n")),
            "scene.pbrt:5:1: error: ObjectInstance inside an object definition (pbrt-v3 does not "
            "nest instances)");
}

TEST(FrontendErrors, ObjectDefinedTwice) {
  EXPECT_EQ(first_error(in_world("ObjectBegin \"a\"\nObjectEnd\nObjectBegin \"a\"\nObjectEnd\n")),
            "scene.pbrt:4:1: error: object \"a\" is already defined");
}

// ---- Options block and world block ----

TEST(FrontendErrors, ShapeBeforeWorldBegin) {
  EXPECT_EQ(first_error("Shape \"sphere\"\nWorldBegin\nWorldEnd\n"),
            "scene.pbrt:1:1: error: Shape is only allowed between WorldBegin and WorldEnd");
}

TEST(FrontendErrors, MaterialBeforeWorldBegin) {
  EXPECT_EQ(first_error("Material \"matte\"\nWorldBegin\nWorldEnd\n"),
            "scene.pbrt:1:1: error: Material is only allowed between WorldBegin and WorldEnd");
}

TEST(FrontendErrors, AttributeBeginBeforeWorldBegin) {
  EXPECT_EQ(first_error("AttributeBegin\nWorldBegin\nWorldEnd\n"),
            "scene.pbrt:1:1: error: AttributeBegin is only allowed between WorldBegin and "
            "WorldEnd");
}

TEST(FrontendErrors, CameraAfterWorldBegin) {
  EXPECT_EQ(first_error(in_world("Camera \"perspective\"\n")),
            "scene.pbrt:2:1: error: Camera is only allowed before WorldBegin");
}

TEST(FrontendErrors, FilmAfterWorldBegin) {
  EXPECT_EQ(first_error(in_world("Film \"image\"\n")),
            "scene.pbrt:2:1: error: Film is only allowed before WorldBegin");
}

TEST(FrontendErrors, TransformTimesAfterWorldBegin) {
  EXPECT_EQ(first_error(in_world("TransformTimes 0 1\n")),
            "scene.pbrt:2:1: error: TransformTimes is only allowed before WorldBegin");
}

TEST(FrontendErrors, DirectiveAfterWorldEnd) {
  EXPECT_EQ(first_error("WorldBegin\nWorldEnd\nShape \"sphere\"\n"),
            "scene.pbrt:3:1: error: Shape after WorldEnd: pbrtc compiles one scene per file");
}

TEST(FrontendErrors, MissingWorldEnd) {
  EXPECT_EQ(first_error("WorldBegin\nShape \"sphere\"\n"),
            "scene.pbrt:3:1: error: missing WorldEnd at end of input");
}

TEST(FrontendErrors, MissingWorldBegin) {
  EXPECT_EQ(first_error("Camera \"perspective\"\n"),
            "scene.pbrt:2:1: error: missing WorldBegin: the file describes no scene");
}

// ---- Numbers and geometry ----

TEST(FrontendErrors, OverflowingNumberIsNotFinite) {
  EXPECT_EQ(first_error(in_world("Shape \"sphere\" \"float radius\" 1e999\n")),
            "scene.pbrt:2:31: error: number '1e999' is not finite");
}

TEST(FrontendErrors, OverflowingNumberInAnArrayIsNotFinite) {
  EXPECT_EQ(first_error(in_world("Material \"matte\" \"rgb Kd\" [ .5 1e999 .5 ]\n")),
            "scene.pbrt:2:32: error: number '1e999' is not finite");
}

TEST(FrontendErrors, NegativeInfinityIsNotFinite) {
  EXPECT_EQ(first_error(in_world("Translate 1 -inf 0\n")),
            "scene.pbrt:2:13: error: number '-inf' is not finite");
}

TEST(FrontendErrors, ZeroFilmResolution) {
  EXPECT_EQ(first_error("Film \"image\" \"integer xresolution\" 0\nWorldBegin\nWorldEnd\n"),
            "scene.pbrt:1:36: error: film xresolution must be positive, got 0");
}

TEST(FrontendErrors, NegativeFilmResolution) {
  EXPECT_EQ(first_error("Film \"image\" \"integer yresolution\" [-5]\nWorldBegin\nWorldEnd\n"),
            "scene.pbrt:1:37: error: film yresolution must be positive, got -5");
}

TEST(FrontendErrors, LookAtWithEyeAtTheLookPoint) {
  EXPECT_EQ(first_error("LookAt 1 2 3  1 2 3  0 1 0\nWorldBegin\nWorldEnd\n"),
            "scene.pbrt:1:1: error: degenerate LookAt: the eye and look points coincide, or the "
            "up vector is parallel to the viewing direction");
}

TEST(FrontendErrors, LookAtWithUpAlongTheViewDirection) {
  EXPECT_EQ(first_error("LookAt 0 0 0  0 0 1  0 0 2\nWorldBegin\nWorldEnd\n"),
            "scene.pbrt:1:1: error: degenerate LookAt: the eye and look points coincide, or the "
            "up vector is parallel to the viewing direction");
}

TEST(FrontendErrors, RotateAroundAZeroAxis) {
  EXPECT_EQ(first_error(in_world("Rotate 90 0 0 0\n")),
            "scene.pbrt:2:1: error: Rotate axis (0, 0, 0) has no direction");
}

TEST(FrontendErrors, SingularCameraTransform) {
  EXPECT_EQ(first_error("Scale 0 1 1\nCamera \"perspective\"\nWorldBegin\nWorldEnd\n"),
            "scene.pbrt:2:1: error: the camera transform is singular (a Scale of 0?)");
}

// ---- pbrt-v4 syntax ----

// pbrt-v4's type names get pbrt-v3's nearest equivalent where each first appears, in every
// category; later uses only say whence. A definition that failed is not "undefined" later.
TEST(FrontendErrors, PbrtV4TypeNamesNamePbrtV3Equivalents) {
  Compile c(
      "Sampler \"pmj02bn\"\nIntegrator \"aov\"\nWorldBegin\n"
      "Texture \"t\" \"float\" \"directionmix\"\n"
      "MakeNamedMedium \"fog\" \"string type\" \"cloud\"\n"
      "Material \"coatedconductor\" \"texture roughness\" \"t\"\n"
      "Material \"matte\" \"texture sigma\" \"t\"\n"
      "Shape \"bilinearmesh\"\nShape \"bilinearmesh\"\nWorldEnd\n");
  EXPECT_EQ(c.errors(),
            (std::vector<std::string>{
                "scene.pbrt:1:1: error: unknown sampler type \"pmj02bn\" (a pbrt-v4 name; "
                "pbrt-v3 calls it \"02sequence\")",
                "scene.pbrt:2:1: error: unknown integrator type \"aov\" (a pbrt-v4 name; "
                "pbrt-v3 has no equivalent)",
                "scene.pbrt:4:1: error: unknown float texture type \"directionmix\" (a pbrt-v4 "
                "name; pbrt-v3 calls it \"mix\")",
                "scene.pbrt:5:37: error: unknown medium type \"cloud\" (a pbrt-v4 name; "
                "pbrt-v3 has no equivalent)",
                "scene.pbrt:6:1: error: unknown material type \"coatedconductor\" (a pbrt-v4 "
                "name; pbrt-v3 comes nearest with \"metal\", without the coating)",
                "scene.pbrt:8:1: error: unknown shape type \"bilinearmesh\" (a pbrt-v4 name; "
                "pbrt-v3 comes nearest with \"trianglemesh\", two triangles per quad)",
                "scene.pbrt:9:1: error: unknown shape type \"bilinearmesh\" (a pbrt-v4 name)"}));
}

TEST(FrontendErrors, EveryPbrtV4HintNamesARealPbrtV3Type) {
  size_t n = 0;
  const PbrtV4Name* names = pbrt_v4_names(&n);
  ASSERT_GE(n, 20u);
  for (size_t i = 0; i < n; ++i) {
    EXPECT_LT(pbrta::find_type(names[i].category, names[i].v4), 0) << names[i].v4;
    if (!names[i].v3.empty()) {
      EXPECT_GE(pbrta::find_type(names[i].category, names[i].v3), 0) << names[i].v3;
    }
  }
}

TEST(FrontendErrors, BareTrueIsV4SyntaxAndReportedOnce) {
  Compile c(in_world("AreaLightSource \"diffuse\" \"bool twosided\" true\n"));
  EXPECT_EQ(c.errors(), std::vector<std::string>{"scene.pbrt:2:43: error: bare true is pbrt-v4 "
                                                 "syntax; pbrt-v3 writes \"true\" in quotes"});
}

TEST(FrontendErrors, BareFalseInBracketsIsV4Syntax) {
  EXPECT_EQ(first_error(in_world("AreaLightSource \"diffuse\" \"bool twosided\" [ false ]\n")),
            "scene.pbrt:2:45: error: bare false is pbrt-v4 syntax; pbrt-v3 writes \"false\" in "
            "quotes");
}

TEST(FrontendErrors, ImportIsAV4Directive) {
  EXPECT_EQ(first_error("Import \"geometry.pbrt\"\nWorldBegin\nWorldEnd\n"),
            "scene.pbrt:1:1: error: 'Import' is a pbrt-v4 directive; pbrt-v3 has no Import");
}

TEST(FrontendErrors, AttributeIsAV4Directive) {
  EXPECT_EQ(first_error(in_world("Attribute \"shape\" \"float radius\" 2\n")),
            "scene.pbrt:2:1: error: 'Attribute' is a pbrt-v4 directive; pbrt-v3 has no "
            "Attribute");
}

TEST(FrontendErrors, ColorSpaceIsAV4Directive) {
  EXPECT_EQ(first_error("ColorSpace \"aces2065-1\"\nWorldBegin\nWorldEnd\n"),
            "scene.pbrt:1:1: error: 'ColorSpace' is a pbrt-v4 directive; pbrt-v3 has no "
            "ColorSpace");
}

TEST(FrontendErrors, OptionIsAV4DirectiveAndItsBareTrueIsNotReportedAgain) {
  Compile c("Option \"bool disablepixeljitter\" true\nWorldBegin\nWorldEnd\n");
  EXPECT_EQ(c.errors(), std::vector<std::string>{"scene.pbrt:1:1: error: 'Option' is a pbrt-v4 "
                                                 "directive; pbrt-v3 has no Option"});
}

TEST(FrontendErrors, NamedSpectrumIsV4Syntax) {
  EXPECT_EQ(first_error(in_world("Material \"metal\" \"spectrum eta\" \"metal-Au-eta\"\n")),
            "scene.pbrt:2:33: error: named spectrum \"metal-Au-eta\" is pbrt-v4 syntax; pbrt-v3 "
            "reads spectra from .spd files");
}

TEST(FrontendErrors, BlackbodyWithOneValueIsV4Syntax) {
  EXPECT_EQ(first_error(in_world("LightSource \"point\" \"blackbody I\" [6500]\n")),
            "scene.pbrt:2:36: error: parameter \"blackbody I\" needs (temperature, scale) pairs, "
            "got 1 value (a lone temperature is pbrt-v4 syntax)");
}

TEST(FrontendErrors, BlackbodyTemperatureMustBePositive) {
  EXPECT_EQ(first_error(in_world("LightSource \"point\" \"blackbody I\" [-5 1]\n")),
            "scene.pbrt:2:36: error: blackbody temperature must be positive, got -5 K");
}

TEST(FrontendErrors, MissingSpdFile) {
  std::string dir = scratch_dir("FrontendErrors.MissingSpdFile");
  EXPECT_EQ(first_error(in_world("Material \"metal\" \"spectrum eta\" \"spds/Au.eta.spd\"\n"), dir),
            "scene.pbrt:2:33: error: cannot open spectrum file \"" + dir + "/spds/Au.eta.spd\"");
}

// ---- Limits, exit status, warnings ----

TEST(FrontendErrors, TwentyFiveErrorsStopAtMaxErrors) {
  std::string text = "WorldBegin\n";
  for (int i = 0; i < 25; ++i) text += "Shape \"nothing" + std::to_string(i) + "\"\n";
  text += "WorldEnd\n";
  Compile c(text);
  EXPECT_FALSE(c.ok);
  EXPECT_EQ(c.diag.max_errors, 20);
  EXPECT_EQ(c.diag.error_count(), 20);
  EXPECT_TRUE(c.diag.should_stop());
  std::vector<std::string> e = c.errors();
  ASSERT_EQ(e.size(), 20u);
  EXPECT_EQ(e.front(), "scene.pbrt:2:1: error: unknown shape type \"nothing0\"");
  EXPECT_EQ(e.back(), "scene.pbrt:21:1: error: unknown shape type \"nothing19\"");
}

TEST(FrontendErrors, FailedMeansErrorsNotWarnings) {
  Compile clean(in_world("Shape \"sphere\"\n"));
  EXPECT_TRUE(clean.ok);
  EXPECT_FALSE(clean.diag.failed());
  EXPECT_EQ(clean.diag.all().size(), 0u);

  Compile warned(in_world("Shape \"sphere\" \"float radiu\" 2\n"));
  EXPECT_TRUE(warned.ok);
  EXPECT_FALSE(warned.diag.failed());
  EXPECT_EQ(warned.diag.warning_count(), 1);

  Compile failed(in_world("Shape \"sphee\"\n"));
  EXPECT_FALSE(failed.ok);
  EXPECT_TRUE(failed.diag.failed());
  EXPECT_EQ(failed.diag.error_count(), 1);
}

TEST(FrontendErrors, LocationsAreOneBasedLinesAndByteColumns) {
  // A tab and a UTF-8 comment before the error count as bytes.
  Compile c("# caf\xC3\xA9\nWorldBegin\n\tShape \"sphee\"\nWorldEnd\n");
  ASSERT_EQ(c.diag.all().size(), 1u);
  LineCol lc = c.files.line_col(c.diag.all()[0].loc);
  EXPECT_EQ(lc.line, 3u);
  EXPECT_EQ(lc.column, 2u);
  EXPECT_EQ(c.diag.all()[0].message, "unknown shape type \"sphee\" (did you mean \"sphere\"?)");
  EXPECT_EQ(c.first_error(),
            "scene.pbrt:3:2: error: unknown shape type \"sphee\" (did you mean \"sphere\"?)");
}

TEST(FrontendErrors, UnusedParameterWarnsWithDidYouMean) {
  Compile c(in_world("Shape \"sphere\" \"float radiu\" 2\n"));
  EXPECT_EQ(c.warnings(), std::vector<std::string>{"scene.pbrt:2:16: warning: parameter \"float "
                                                   "radiu\" is not used by sphere shape (did you "
                                                   "mean \"radius\"?)"});
  EXPECT_EQ(c.scene.shapes.at(0).params.get_float("radius"), 1.0f);
}

TEST(FrontendErrors, UnusedParameterWithoutNearMiss) {
  Compile c(in_world("Shape \"sphere\" \"string exporter\" \"blender\"\n"));
  EXPECT_EQ(c.warnings(), std::vector<std::string>{"scene.pbrt:2:16: warning: parameter \"string "
                                                   "exporter\" is not used by sphere shape"});
}

TEST(FrontendErrors, WrongDeclaredTypeForAKnownParameterWarns) {
  Compile c(in_world("Shape \"sphere\" \"integer radius\" 2\n"));
  EXPECT_TRUE(c.ok);
  EXPECT_EQ(c.warnings(), std::vector<std::string>{"scene.pbrt:2:16: warning: parameter "
                                                   "\"integer radius\" of sphere shape should be "
                                                   "float; it is ignored (pbrt-v3 does not use it "
                                                   "either)"});
  EXPECT_EQ(c.scene.shapes.at(0).params.get_float("radius"), 1.0f);
}

TEST(FrontendErrors, WrongDeclaredTypeForABulkMeshParameterWarns) {
  Compile c(in_world(std::string("Shape \"trianglemesh\" ") + kTriangleP +
                     " \"integer indices\" [0 1 2] \"float N\" [0 0 1 0 0 1 0 0 1]\n"));
  EXPECT_TRUE(c.ok);
  EXPECT_EQ(c.warnings(), std::vector<std::string>{"scene.pbrt:2:79: warning: parameter \"float "
                                                   "N\" of trianglemesh shape should be normal; "
                                                   "it is ignored (pbrt-v3 does not use it "
                                                   "either)"});
  EXPECT_TRUE(c.scene.meshes.at(0).N.empty());
}

TEST(FrontendErrors, RedefinedNamedMaterialWarns) {
  Compile c(
      in_world("MakeNamedMaterial \"a\" \"string type\" \"matte\"\n"
               "MakeNamedMaterial \"a\" \"string type\" \"plastic\"\n"));
  EXPECT_TRUE(c.ok);
  EXPECT_EQ(c.warnings(),
            std::vector<std::string>{"scene.pbrt:3:1: warning: named material \"a\" redefined"});
}

TEST(FrontendErrors, RedefinedTextureWarns) {
  Compile c(
      in_world("Texture \"t\" \"color\" \"constant\"\n"
               "Texture \"t\" \"spectrum\" \"constant\"\n"));
  EXPECT_TRUE(c.ok);
  EXPECT_EQ(c.warnings(),
            std::vector<std::string>{"scene.pbrt:3:1: warning: spectrum texture \"t\" redefined"});
}

TEST(FrontendErrors, WerrorTurnsAWarningIntoAnError) {
  Compile c(in_world("Shape \"sphere\" \"float radiu\" 2\n"), kNoDir, /*werror=*/true);
  EXPECT_FALSE(c.ok);
  EXPECT_TRUE(c.diag.failed());
  EXPECT_EQ(c.diag.warning_count(), 0);
  EXPECT_EQ(c.errors(), std::vector<std::string>{"scene.pbrt:2:16: error: parameter \"float "
                                                 "radiu\" is not used by sphere shape (did you "
                                                 "mean \"radius\"?)"});
}

TEST(FrontendErrors, ErrorsContinueToTheNextDirective) {
  Compile c(
      in_world("Shape \"sphere\" \"float radius\" \"x\" \"float zmin\" 0\n"
               "Shape \"sphee\"\nShape \"sphere\"\n"));
  EXPECT_EQ(c.errors(),
            (std::vector<std::string>{
                "scene.pbrt:2:31: error: parameter \"float radius\" takes numbers, got \"x\"",
                "scene.pbrt:3:1: error: unknown shape type \"sphee\" (did you mean \"sphere\"?)"}));
  EXPECT_EQ(c.scene.shapes.size(), 1u);
}

}  // namespace
}  // namespace pbrtc
