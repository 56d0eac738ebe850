// Degenerate input that the compiler accepts renders without crashing and
// without a single non-finite value: zero-area and coincident-vertex
// triangles, zero-length and flipped shading normals, a zero-radius sphere,
// a scale of 0 on one axis (quadric and mesh), degenerate uvs, and area
// lights on shapes of zero area; and a scale of 0 on one axis. Every pixel is scanned, and the
// renderer's count of non-finite samples (it drops them as pbrt-v3 does) must be 0.
#include <gtest/gtest.h>

#include "stability_support.h"

namespace rt {
namespace {

const char* kCamera = R"(
LookAt 0 2 -5  0 0.3 0  0 1 0
Camera "perspective" "float fov" 50
Film "image" "integer xresolution" 32 "integer yresolution" 24
Sampler "random" "integer pixelsamples" 8
)";

const char* kDegenerateWorld = R"(
WorldBegin
LightSource "infinite" "rgb L" [0.3 0.3 0.3]
LightSource "distant" "point from" [1 3 -2] "point to" [0 0 0] "rgb L" [2 2 2]
Material "matte" "rgb Kd" [0.5 0.5 0.5]
# A floor to receive light and shadows.
Shape "trianglemesh" "point P" [-5 -1 -5  5 -1 -5  5 -1 5  -5 -1 5] "integer indices" [0 1 2 0 2 3]
# Zero-area triangles: collinear, and all three vertices coincident; with a normal array.
Shape "trianglemesh" "point P" [-1 0 0  0 0 0  1 0 0  0.5 0.5 0.5]
  "integer indices" [0 1 2  3 3 3  0 0 1]
  "normal N" [0 1 0  0 1 0  0 1 0  0 1 0]
# Zero-length shading normals on a real triangle.
Material "plastic" "rgb Kd" [0.3 0.3 0.6] "rgb Ks" [0.4 0.4 0.4] "float roughness" 0.1
Shape "trianglemesh" "point P" [-2 0 1  -1 0 1  -1.5 1 1]
  "integer indices" [0 1 2]  "normal N" [0 0 0  0 0 0  0 0 0]
# Shading normals flipped against the geometry, and opposite at the vertices.
Material "glass"
Shape "trianglemesh" "point P" [1 0 1  2 0 1  1.5 1 1]
  "integer indices" [0 2 1]  "normal N" [0 0 1  0 0 -1  0 0 1]
# Degenerate uvs (all the same) and tangents along the normal, with bump mapping.
Texture "bumps" "float" "fbm"
Material "matte" "rgb Kd" [0.7 0.7 0.7] "texture bumpmap" "bumps"
Shape "trianglemesh" "point P" [-1 0 -1  0 0 -1  -0.5 1 -1]
  "integer indices" [0 1 2]  "point2 uv" [0.5 0.5  0.5 0.5  0.5 0.5]
  "vector S" [0 0 1  0 0 1  0 0 1]
Material "metal" "float roughness" 0.05
# A zero-radius sphere, a zero-radius disk, a zero-height cylinder.
Shape "sphere" "float radius" 0
Shape "disk" "float radius" 0
Shape "cylinder" "float zmin" 0.5 "float zmax" 0.5
# Area lights of zero area: a zero-radius sphere, a zero-area triangle, a zero-radius disk.
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [5 5 5]
  Translate 0 1.5 0
  Shape "sphere" "float radius" 0
  Shape "trianglemesh" "point P" [0 0 0  1 0 0  2 0 0] "integer indices" [0 1 2]
  Shape "disk" "float radius" 0
AttributeEnd
WorldEnd
)";

// A scale of 0 on one axis makes the shape's transform singular: pbrt-v3
// inverts it anyway (printing "Singular matrix") and renders with
// non-finite values; this renderer refuses the scene with a message that
// names the line. Either way, no crash.
const char* kZeroScaleWorld = R"(
WorldBegin
LightSource "infinite" "rgb L" [0.3 0.3 0.3]
AttributeBegin
  Translate 0.5 0.3 -1.5
  Scale 1 0 1
  Shape "sphere" "float radius" 0.4
AttributeEnd
WorldEnd
)";

TEST(Degenerate, NoCrashAndNoNonFiniteValue) {
  for (const char* integrator :
       {"Integrator \"path\" \"integer maxdepth\" 8", "Integrator \"directlighting\"",
        "Integrator \"whitted\"", "Integrator \"path\" \"string lightsamplestrategy\" \"power\""}) {
    Rendered r = render_text("degenerate", std::string(kCamera) + integrator + kDegenerateWorld, 1);
    ASSERT_TRUE(r.ok) << integrator << ": " << r.error;
    EXPECT_EQ(count_nonfinite(r), 0) << integrator;
    EXPECT_EQ(r.stats.nonfinite_samples, 0u) << integrator;
    // The floor is lit: the render did produce an image.
    EXPECT_GT(mean_and_error(r).mean, 0.05) << integrator;
  }
}

TEST(Degenerate, ZeroScaleIsRefusedWithTheLine) {
  pbrta::SceneArchive a;
  ASSERT_TRUE(testing_support::compile_text(
      testing_support::scratch_dir("degenerate_scale0"),
      std::string(kCamera) + "Integrator \"path\"" + kZeroScaleWorld, &a));
  RenderScene scene;
  std::string error;
  EXPECT_FALSE(load_render_scene(a, &scene, &error));
  EXPECT_NE(error.find("scene.pbrt:12"), std::string::npos) << error;
  EXPECT_NE(error.find("singular"), std::string::npos) << error;
}

}  // namespace
}  // namespace rt
