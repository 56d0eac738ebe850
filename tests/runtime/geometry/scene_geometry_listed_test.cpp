// Listed shapes (prim_list.h) answer as Embree does: a scene built with its shapes listed and
// built again with set_max_listed(0) (everything in Embree) gives the same hits for random
// rays inside it, for rays leaving the surfaces they hit (where a test that misses its own
// error bound hits the surface again), and the same occlusion for segments between hit
// points: what was hit and the whole interaction (bit for bit for quadrics; within the error
// bounds for triangles, whose listed hits keep the list's own watertight values), but where two
// surfaces meet at one distance. Both listings: a small scene listed whole (with an alpha-masked
// wall and one whose shadowalpha is 0), and a larger one whose quadrics alone are tested beside
// Embree's tree. (Fails when the box test drops its rounding margin, when occluded() forgets
// skip_shape, when the list ignores masks or applies shadowalpha to closest hits: tried.)
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "scene_geometry_test_support.h"

namespace rt {
namespace {

std::unique_ptr<LoadedScene> load_listed(const std::string& name, const std::string& world,
                                         size_t max_listed) {
  auto s = std::make_unique<LoadedScene>();
  const std::string text = "Camera \"perspective\"\nWorldBegin\n" + world + "\nWorldEnd\n";
  EXPECT_TRUE(testing_support::compile_text(testing_support::scratch_dir(name), text, &s->archive));
  if (!s->shapes.build(s->archive, &s->error) || !s->textures.build(s->archive, &s->error))
    return s;
  s->geometry.set_max_listed(max_listed);
  s->built = s->geometry.build(s->archive, s->shapes, &s->textures, &s->error);
  return s;
}

// The same hit: the same shape and triangle, and the same interaction, bit for bit for a
// quadric (both test it with intersect_quadric). A listed triangle's interaction is built on
// the list's own watertight t and barycentrics where Embree's is measured again on the same
// vertices: the same normals, the two points apart along the normal by no more than their
// error bounds there (what spawned rays are offset by), and within the plane, as t and uv, to
// the rounding of a point a few units from the origin.
bool same_hit(const ShapeTable& shapes, const SurfaceInteraction& a, const SurfaceInteraction& b) {
  if (a.shape != b.shape || a.prim != b.prim || !same_bits(&a.n, &b.n, sizeof a.n) ||
      !same_bits(&a.shading.n, &b.shading.n, sizeof a.n))
    return false;
  if (shapes[a.shape].kind != ShapeKind::kTriangles)
    return same_bits(&a.t_hit, &b.t_hit, 4) && same_bits(&a.p, &b.p, sizeof a.p) &&
           same_bits(&a.p_error, &b.p_error, sizeof a.p) && same_bits(&a.uv, &b.uv, 8);
  const float near = 1e-5f;
  return std::fabs(dot(a.p - b.p, a.n)) <= dot(abs(a.n), a.p_error + b.p_error) &&
         length(a.p - b.p) <= near && std::fabs(a.t_hit - b.t_hit) <= near &&
         std::fabs(a.uv.x - b.uv.x) <= near && std::fabs(a.uv.y - b.uv.y) <= near;
}

// A floor, a tilted quad, a sphere, a partial sphere, a scaled and rotated cylinder, a mirrored
// sphere with ReverseOrientation, and a disk or (the larger scene) extra_walls walls: shapes
// meeting, touching and inside each other.
std::string world(int extra_walls) {
  std::string w = R"(
Shape "trianglemesh" "integer indices" [0 1 2  0 2 3]
  "point P" [-4 -4 0  4 -4 0  4 4 0  -4 4 0] "float uv" [0 0  1 0  1 1  0 1]
Shape "trianglemesh" "integer indices" [0 1 2  0 2 3]
  "point P" [-1 -1 1.5  1 -1 1.7  1 1 1.9  -1 1 1.6]
Shape "sphere" "float radius" 0.8
AttributeBegin
  Translate 2 1 0.5
  Shape "sphere" "float radius" 0.6 "float zmin" -0.2 "float zmax" 0.4 "float phimax" 270
AttributeEnd
AttributeBegin
  Translate -2 1 0.3
  Rotate 30 1 1 0
  Scale 1 1 2
  Shape "cylinder" "float radius" 0.4 "float zmin" -0.5 "float zmax" 0.5
AttributeEnd
AttributeBegin
  Translate -1.5 -1.5 1
  Scale -1 1 1
  ReverseOrientation
  Shape "sphere" "float radius" 0.5
AttributeEnd
)";
  // The larger scene may have only SceneGeometry::kMaxListedBesideTree quadrics listed.
  if (extra_walls == 0) {
    w += "AttributeBegin\n Translate 1 -2 0.7\n"
         " Shape \"disk\" \"float radius\" 0.9 \"float innerradius\" 0.2\nAttributeEnd\n";
    // A wall with holes (an alpha texture), and one that casts no shadow (shadowalpha 0).
    w += R"(Texture "holes" "float" "dots" "float inside" 0 "float outside" 1
  "float uscale" 4 "float vscale" 4
Shape "trianglemesh" "integer indices" [0 1 2  0 2 3]
  "point P" [-3.5 -1 0  -2.5 -1.2 0  -2.5 -1.2 2.5  -3.5 -1 2.5] "float uv" [0 0  1 0  1 1  0 1]
  "texture alpha" "holes"
Shape "trianglemesh" "integer indices" [0 1 2  0 2 3]
  "point P" [3.5 1 0  3.5 2 0  3.5 2 2  3.5 1 2] "float shadowalpha" 0
)";
  }
  for (int i = 0; i < extra_walls; ++i) {
    const float x = -3.5f + 0.5f * float(i);
    w += "Shape \"trianglemesh\" \"integer indices\" [0 1 2  0 2 3] \"point P\" [" +
         std::to_string(x) + " 3 0  " + std::to_string(x + 0.4f) + " 3.2 0  " +
         std::to_string(x + 0.4f) + " 3.2 2  " + std::to_string(x) + " 3 2]\n";
  }
  return w;
}

void expect_listed_as_embree(const std::string& name, int extra_walls, bool whole) {
  SCOPED_TRACE(name);
  auto listed = load_listed(name + "_listed", world(extra_walls), 32);
  auto embree = load_listed(name + "_embree", world(extra_walls), 0);
  ASSERT_TRUE(listed->built) << listed->error;
  ASSERT_TRUE(embree->built) << embree->error;
  const GeometryStats& st = listed->geometry.stats();
  EXPECT_EQ(st.listed, whole ? st.triangles + st.quadrics : st.quadrics);
  EXPECT_EQ(embree->geometry.stats().listed, 0u);
  Rng rng(23);
  int hits = 0, leaving = 0, ties = 0, occlusions = 0, blocked = 0;
  for (int i = 0; i < 20000; ++i) {
    const Ray ray = random_ray(rng, {-4, -4, 0.01f}, {8, 8, 3});
    SurfaceInteraction a, b;
    const bool ha = listed->geometry.intersect(ray, &a), hb = embree->geometry.intersect(ray, &b);
    ASSERT_EQ(ha, hb) << i;
    if (!ha) continue;
    ++hits;
    if (!same_hit(listed->shapes, a, b)) {
      // Two surfaces at one distance: which is nearer is a rounding either way.
      EXPECT_NEAR(a.t_hit, b.t_hit, 1e-5f * a.t_hit) << i;
      ++ties;
      continue;
    }
    // A ray leaving the hit point, into either side.
    const Vec3 d = uniform_sample_sphere({rng.next_float(), rng.next_float()});
    const Ray out = a.spawn_ray(d);
    SurfaceInteraction a2, b2;
    const bool ha2 = listed->geometry.intersect(out, &a2),
               hb2 = embree->geometry.intersect(out, &b2);
    ASSERT_EQ(ha2, hb2) << i;
    if (ha2) {
      ++leaving;
      if (!same_hit(listed->shapes, a2, b2)) {
        EXPECT_NEAR(a2.t_hit, b2.t_hit, 1e-5f * a2.t_hit) << i;
        ++ties;
        continue;
      }
      // The segment between the two hits, as a shadow ray spawns it, and the same with the
      // second hit's own shape skipped, as an area light's is: nothing in between.
      const Ray seg = a.spawn_ray_to(a2);
      EXPECT_FALSE(listed->geometry.occluded(seg)) << i;
      EXPECT_FALSE(listed->geometry.occluded(seg, a2.shape)) << i;
      EXPECT_EQ(embree->geometry.occluded(seg), false) << i;
    }
    // A segment from the hit to a point anywhere in the scene, with and without the first
    // hit's shape skipped.
    Interaction q;
    q.p = {-4 + 8 * rng.next_float(), -4 + 8 * rng.next_float(), 0.01f + 3 * rng.next_float()};
    const Ray seg = a.spawn_ray_to(q);
    const bool oa = listed->geometry.occluded(seg), ob = embree->geometry.occluded(seg);
    ASSERT_EQ(oa, ob) << i;
    ++occlusions;
    blocked += oa;
    ASSERT_EQ(listed->geometry.occluded(seg, a.shape), embree->geometry.occluded(seg, a.shape))
        << i;
  }
  EXPECT_GT(hits, 5000);
  EXPECT_GT(leaving, 1000);
  EXPECT_GT(occlusions, 5000);
  EXPECT_GT(blocked, 500);
  EXPECT_LE(ties, hits / 1000);
}

TEST(SceneGeometryListed, SmallSceneListedWholeAnswersAsEmbree) {
  expect_listed_as_embree("sg_listed_whole", 0, true);
}

TEST(SceneGeometryListed, QuadricsListedBesideEmbreesTreeAnswerAsEmbree) {
  // 4 + 2 * 10 triangles: more than a scene listed whole may have.
  expect_listed_as_embree("sg_listed_quadrics", 10, false);
}

}  // namespace
}  // namespace rt
