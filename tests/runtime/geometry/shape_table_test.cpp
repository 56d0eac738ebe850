// The shape table: quadric defaults computed as pbrt-v3 computes them, meshes
// viewed in place in the archive, orientation flags carried over.
#include <gtest/gtest.h>

#include "runtime/geometry/shape_table.h"
#include "runtime/runtime_test_support.h"
#include "test_support.h"

namespace rt {
namespace {

TEST(ShapeTable, QuadricDefaultsAndMeshViews) {
  pbrta::SceneArchive a;
  ASSERT_TRUE(testing_support::compile_text(testing_support::scratch_dir("shape_table"), R"(
Camera "perspective"
WorldBegin
Shape "sphere" "float radius" 2
AttributeBegin
  ReverseOrientation
  Scale -1 1 1
  Shape "disk" "float phimax" 90
AttributeEnd
Shape "trianglemesh" "integer indices" [0 1 2] "point P" [0 0 0 1 0 0 0 1 0]
  "float alpha" 0.5
WorldEnd
)",
                                            &a));
  ShapeTable t;
  std::string error;
  ASSERT_TRUE(t.build(a, &error)) << error;
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t[0].kind, ShapeKind::kSphere);
  EXPECT_FLOAT_EQ(t[0].q.zmin, -2);
  EXPECT_FLOAT_EQ(t[0].q.zmax, 2);
  EXPECT_EQ(t[1].kind, ShapeKind::kDisk);
  EXPECT_NEAR(t[1].q.phimax, kPi / 2, 1e-6);
  EXPECT_TRUE(t[1].reverse_orientation);
  EXPECT_TRUE(t[1].swaps_handedness);
  EXPECT_FALSE(t[1].flip_normals());  // both: they cancel, as in pbrt-v3
  EXPECT_EQ(t[2].kind, ShapeKind::kTriangles);
  ASSERT_EQ(t[2].mesh.num_triangles, 1u);
  EXPECT_EQ(t[2].mesh.position(1).x, 1.f);
  EXPECT_TRUE(t[2].has_alpha());
  EXPECT_FLOAT_EQ(t[2].alpha, 0.5f);
}

}  // namespace
}  // namespace rt
