// Placed instances (SceneGeometry::set_max_placed) answer as Embree's instances do: a scene
// built with its small objects' instances copied into the world and built again with
// set_max_placed(0) (every instance under an Embree instance) gives the same hits for random
// rays: what was hit, which instance, and for triangles the interaction bit for bit but its
// error bound, which placed hits need no wider than the triangle's own (Embree intersected the
// very vertices the hit is rebuilt on); a placed quadric is tested through the product of the
// two transforms, so its hits agree up to that product's rounding. Rays leaving those hits,
// from each build's own point, never hit their own triangle again and hit the same thing.
// Objects with a moving instance, and objects over the budget, stay instanced. (Fails when the
// copy skips the shape's own transform, when a placed hit reports no instance, when a
// placed quadric takes the instance's transform alone, or when an instanced quadric's box is
// tested with the world ray instead of Embree's ray in the instance's space: tried.)
#include <gtest/gtest.h>

#include "scene_geometry_test_support.h"

namespace rt {
namespace {

// A tent with vertex normals and uv, a box with its own transform and ReverseOrientation, both
// in one object; a ball object (a quadric: stays instanced); instances plain, rotated, scaled,
// mirrored; a floor.
const char* kWorld = R"(
ObjectBegin "tent"
  Shape "trianglemesh" "integer indices" [0 1 2  0 2 3]
    "point P" [-0.5 -0.5 0  0.5 -0.5 0  0.5 0.5 0.6  -0.5 0.5 0.6]
    "normal N" [0 -0.7 0.7  0 -0.7 0.7  0.1 -0.6 0.8  -0.1 -0.6 0.8]
    "float uv" [0 0  1 0  1 1  0 1]
  AttributeBegin
    Translate 0 0 0.3
    Rotate 20 0 0 1
    Scale 0.3 0.2 0.25
    ReverseOrientation
    Shape "trianglemesh" "integer indices" [0 1 2  0 2 3  4 5 6  4 6 7  0 4 5  0 5 1
                                            1 5 6  1 6 2  2 6 7  2 7 3  3 7 4  3 4 0]
      "point P" [-1 -1 -1  1 -1 -1  1 1 -1  -1 1 -1  -1 -1 1  1 -1 1  1 1 1  -1 1 1]
  AttributeEnd
ObjectEnd
ObjectBegin "ball"
  Translate 0.1 0 0.05
  Shape "sphere" "float radius" 0.3
ObjectEnd
AttributeBegin
  Translate -1.5 -1 0
  ObjectInstance "tent"
AttributeEnd
AttributeBegin
  Translate 1.5 -1 0
  Rotate 40 0 0 1
  Rotate 10 1 0 0
  ObjectInstance "tent"
AttributeEnd
AttributeBegin
  Translate -1.2 1.2 0.1
  Scale 1.5 1.2 1.3
  ObjectInstance "tent"
AttributeEnd
AttributeBegin
  Translate 1.3 1.3 0
  Scale -1 1 1
  Rotate 70 0 0 1
  ObjectInstance "tent"
AttributeEnd
AttributeBegin
  Translate 0 0 0.5
  Scale 1 1.5 1
  ObjectInstance "ball"
AttributeEnd
ObjectBegin "spinner"
  Translate 0 0 0.2
  Shape "sphere" "float radius" 0.2
ObjectEnd
AttributeBegin
  Translate 0 -2.5 0.3
  ActiveTransform EndTime
  Translate 0.3 0 0
  ActiveTransform All
  ObjectInstance "spinner"
AttributeEnd
Shape "trianglemesh" "integer indices" [0 1 2  0 2 3]
  "point P" [-4 -4 -0.01  4 -4 -0.01  4 4 -0.01  -4 4 -0.01]
)";

bool same_bits_hit(const SurfaceInteraction& a, const SurfaceInteraction& b) {
  return a.shape == b.shape && a.prim == b.prim && a.instance == b.instance &&
         same_bits(&a.t_hit, &b.t_hit, 4) && same_bits(&a.p, &b.p, sizeof a.p) &&
         same_bits(&a.n, &b.n, sizeof a.n) && same_bits(&a.uv, &b.uv, 8) &&
         same_bits(&a.dpdu, &b.dpdu, sizeof a.dpdu) && same_bits(&a.dpdv, &b.dpdv, sizeof a.dpdv) &&
         same_bits(&a.shading.n, &b.shading.n, sizeof a.n) &&
         same_bits(&a.shading.dpdu, &b.shading.dpdu, sizeof a.n) &&
         same_bits(&a.shading.dndu, &b.shading.dndu, sizeof a.n);
}

TEST(SceneGeometryPlaced, HitsAsUnderEmbreeInstances) {
  auto placed = load_world("sg_placed", kWorld);
  auto instanced = load_world("sg_placed_inst", kWorld, false, 0);
  ASSERT_TRUE(placed->built) << placed->error;
  ASSERT_TRUE(instanced->built) << instanced->error;
  EXPECT_EQ(placed->geometry.stats().instances, 6u);
  EXPECT_EQ(placed->geometry.stats().placed_instances, 5u);  // the moving spinner stays
  EXPECT_EQ(instanced->geometry.stats().placed_instances, 0u);
  // pbrt-v3's world bound: the object's box through each instance's transform, both ways.
  const Bounds3 bp = placed->geometry.world_bounds(), bi = instanced->geometry.world_bounds();
  EXPECT_TRUE(same_bits(&bp, &bi, sizeof bp));

  Rng rng(7);
  int hits = 0, in_instances = 0, mirrored = 0, leaving = 0, balls = 0;
  for (int i = 0; i < 20000; ++i) {
    const Ray ray = random_ray(rng, {-3, -3, 0}, {6, 6, 2});
    SurfaceInteraction a, b;
    const bool ha = placed->geometry.intersect(ray, &a),
               hb = instanced->geometry.intersect(ray, &b);
    ASSERT_EQ(ha, hb) << i;
    if (!ha) continue;
    ++hits;
    if (a.instance == 4) {  // the ball, placed
      ++balls;
      ASSERT_EQ(a.shape, b.shape) << i;
      ASSERT_EQ(b.instance, 4u) << i;
      // (Near a silhouette t moves by about the square root of the transforms' rounding.)
      EXPECT_NEAR(a.t_hit, b.t_hit, 1e-4f * b.t_hit) << i;
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(a.p[k], b.p[k], 1e-4f) << i;
        EXPECT_NEAR(a.n[k], b.n[k], 1e-4f) << i;
      }
    } else {
      ASSERT_TRUE(same_bits_hit(a, b)) << i << ": shape " << a.shape << "/" << b.shape
                                       << " instance " << a.instance << "/" << b.instance;
    }
    if (a.instance == kNone) continue;
    ++in_instances;
    mirrored += a.instance == 3;
    if (a.instance != 4) {
      for (int k = 0; k < 3; ++k) EXPECT_LE(a.p_error[k], b.p_error[k]) << i;
    }
    // Leaving the hit into either side, from each build's own point.
    const Vec3 d = uniform_sample_sphere({rng.next_float(), rng.next_float()});
    SurfaceInteraction a2, b2;
    const bool ha2 = placed->geometry.intersect(a.spawn_ray(d), &a2),
               hb2 = instanced->geometry.intersect(b.spawn_ray(d), &b2);
    ASSERT_EQ(ha2, hb2) << i;
    if (!ha2) continue;
    ++leaving;
    // (A sphere is met again from inside; a triangle never.)
    if (placed->shapes[a.shape].kind == ShapeKind::kTriangles) {
      EXPECT_FALSE(a2.shape == a.shape && a2.prim == a.prim && a2.instance == a.instance) << i;
    }
    EXPECT_EQ(a2.shape, b2.shape) << i;
    EXPECT_EQ(a2.prim, b2.prim) << i;
    EXPECT_EQ(a2.instance, b2.instance) << i;
  }
  EXPECT_GT(in_instances, 1000);
  EXPECT_GT(mirrored, 100);
  EXPECT_GT(balls, 100);
  EXPECT_GT(leaving, 500);
  EXPECT_GT(hits, in_instances);
}

TEST(SceneGeometryPlaced, ObjectsOverTheBudgetStayInstanced) {
  // Objects in the archive's order: the tent's 4 instances are 56 copies (14 triangles each),
  // the ball's 1 a copy of one quadric.
  auto ball = load_world("sg_placed_budget", kWorld, false, 55);
  ASSERT_TRUE(ball->built) << ball->error;
  EXPECT_EQ(ball->geometry.stats().placed_instances, 1u);
  auto tents = load_world("sg_placed_budget2", kWorld, false, 56);
  ASSERT_TRUE(tents->built) << tents->error;
  EXPECT_EQ(tents->geometry.stats().placed_instances, 4u);
  auto both = load_world("sg_placed_budget3", kWorld, false, 57);
  ASSERT_TRUE(both->built) << both->error;
  EXPECT_EQ(both->geometry.stats().placed_instances, 5u);
  // Copies count as triangles Embree holds: the floor's 2, the tent's 14 per instance.
  EXPECT_EQ(tents->geometry.stats().triangles, 2u + 4 * 14);
  EXPECT_EQ(ball->geometry.stats().triangles, 2u + 14);
  // Quadrics: the ball's copy, or its definition, and the spinner's.
  EXPECT_EQ(both->geometry.stats().quadrics, 2u);
  EXPECT_EQ(tents->geometry.stats().quadrics, 2u);
}

}  // namespace
}  // namespace rt
