// SceneGeometry with object instances, transformed meshes and quadrics: hits
// land where the transforms put them, transformed and identity meshes agree,
// sheared motion is sampled in time steps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <cstdio>

#include "runtime/core/animated_transform.h"
#include "runtime/core/rng.h"
#include "runtime/geometry/watertight.h"
#include "scene_geometry_test_support.h"

namespace rt {
namespace {

void expect_vec_near(Vec3 a, Vec3 b, float tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

const char* kInstances = R"(
ObjectBegin "tri"
  Shape "trianglemesh" "integer indices" [0 1 2] "point P" [-1 -1 0  1 -1 0  0 1 0]
    "float uv" [0 0 1 0 0 1]
ObjectEnd
ObjectBegin "lifted"
  Translate 0 0 1
  Shape "trianglemesh" "integer indices" [0 1 2] "point P" [-1 -1 0  1 -1 0  0 1 0]
ObjectEnd
AttributeBegin
  Translate 10 0 5
  ObjectInstance "tri"
AttributeEnd
AttributeBegin
  Translate -10 0 5
  Scale 2 2 2
  ObjectInstance "tri"
AttributeEnd
AttributeBegin
  Translate 0 10 5
  Scale -1 1 1
  ObjectInstance "tri"
AttributeEnd
AttributeBegin
  Translate 0 -10 5
  ObjectInstance "lifted"
AttributeEnd
)";

// Under Embree's instances (set_max_placed(0)) and copied into the world.
class SceneGeometryInstanceBoth : public testing::TestWithParam<bool> {};

TEST_P(SceneGeometryInstanceBoth, HitsWhereTheInstanceTransformPutsThem) {
  const bool placed = GetParam();
  auto s = load_world(placed ? "sg_inst_placed" : "sg_inst", kInstances, false,
                      placed ? SceneGeometry::kDefaultMaxPlaced : 0);
  ASSERT_TRUE(s->built) << s->error;
  const GeometryStats& st = s->geometry.stats();
  EXPECT_EQ(st.instances, 4u);
  EXPECT_EQ(st.placed_instances, placed ? 4u : 0u);
  // One per object definition, shared by the instances; or one per instance.
  EXPECT_EQ(st.triangles, placed ? 4u : 2u);
  // "lifted" has its own transform inside the object: copied through it once, or per instance.
  EXPECT_EQ(st.copied_meshes, 1u);
  SurfaceInteraction si;

  // The definition itself is not in the world.
  EXPECT_FALSE(s->geometry.intersect(make_ray({0, 0, -5}, {0, 0, 1}), &si));

  ASSERT_TRUE(s->geometry.intersect(make_ray({10.25f, 0, 0}, {0, 0, 1}), &si));
  EXPECT_EQ(si.instance, 0u);
  EXPECT_EQ(si.shape, 0u);
  expect_vec_near(si.p, {10.25f, 0, 5}, 1e-5f);
  expect_vec_near(si.n, {0, 0, 1}, 1e-6f);
  // Object-space barycentrics of (0.25, 0): b1 = 0.375, b2 = 0.5 -> uv.
  EXPECT_NEAR(si.uv.x, 0.375f, 1e-5f);
  EXPECT_NEAR(si.uv.y, 0.5f, 1e-5f);
  expect_vec_near(si.dpdu, {2, 0, 0}, 1e-5f);

  // The scaled instance: twice as large, same uv at the scaled point.
  ASSERT_TRUE(s->geometry.intersect(make_ray({-9.5f, 0, 0}, {0, 0, 1}), &si));
  EXPECT_EQ(si.instance, 1u);
  expect_vec_near(si.p, {-9.5f, 0, 5}, 1e-5f);
  EXPECT_NEAR(si.uv.x, 0.375f, 1e-5f);
  expect_vec_near(si.dpdu, {4, 0, 0}, 1e-5f);
  EXPECT_GT(si.p_error.x, 0);

  // The mirrored instance: the normal goes through the transform as a normal.
  ASSERT_TRUE(s->geometry.intersect(make_ray({0.25f, 10, 0}, {0, 0, 1}), &si));
  EXPECT_EQ(si.instance, 2u);
  expect_vec_near(si.n, {0, 0, 1}, 1e-6f);

  // A shape with its own transform inside the object: both transforms apply.
  ASSERT_TRUE(s->geometry.intersect(make_ray({0, -10, 0}, {0, 0, 1}), &si));
  EXPECT_EQ(si.instance, 3u);
  EXPECT_EQ(si.shape, 1u);
  expect_vec_near(si.p, {0, -10, 6}, 1e-5f);

  Bounds3 b = s->geometry.world_bounds();
  expect_vec_near(b.lo, {-12, -11, 5}, 1e-5f);
  expect_vec_near(b.hi, {11, 11, 6}, 1e-5f);
}

INSTANTIATE_TEST_SUITE_P(EmbreeOrPlaced, SceneGeometryInstanceBoth, testing::Bool());

TEST(SceneGeometryInstance, QuadricsInWorldAndInInstances) {
  auto s = load_world("sg_inst_quadric", R"(
AttributeBegin
  Translate 0 20 0
  Shape "sphere" "float radius" 1
AttributeEnd
ObjectBegin "ball"
  Translate 0 0 1
  Shape "sphere" "float radius" 0.5
ObjectEnd
AttributeBegin
  Translate 0 -20 0
  ObjectInstance "ball"
AttributeEnd
AttributeBegin
  Translate 5 -20 0
  ObjectInstance "ball"
AttributeEnd
Shape "trianglemesh" "integer indices" [0 1 2] "point P" [-100 -100 -3  100 -100 -3  0 100 -3]
)");
  ASSERT_TRUE(s->built) << s->error;
  // The world's, and the ball's once per instance (placed in the world).
  EXPECT_EQ(s->geometry.stats().quadrics, 3u);
  SurfaceInteraction si;
  ASSERT_TRUE(s->geometry.intersect(make_ray({0, 20, -2}, {0, 0, 1}), &si));
  EXPECT_EQ(si.shape, 0u);
  EXPECT_EQ(si.instance, kNone);
  expect_vec_near(si.p, {0, 20, -1}, 1e-5f);
  expect_vec_near(si.n, {0, 0, -1}, 1e-5f);

  ASSERT_TRUE(s->geometry.intersect(make_ray({5, -20, -2}, {0, 0, 1}), &si));
  EXPECT_EQ(si.shape, 1u);
  EXPECT_EQ(si.instance, 1u);
  expect_vec_near(si.p, {5, -20, 0.5f}, 1e-5f);
  expect_vec_near(si.n, {0, 0, -1}, 1e-5f);

  // Closest hit between a quadric and a triangle, both orders.
  ASSERT_TRUE(s->geometry.intersect(make_ray({0, -20, -10}, {0, 0, 1}), &si));
  EXPECT_EQ(si.shape, 2u);  // the triangle at z = -3 comes first
  ASSERT_TRUE(s->geometry.intersect(make_ray({0, -20, 10}, {0, 0, -1}), &si));
  EXPECT_EQ(si.shape, 1u);  // the ball's top at z = 1.5
  expect_vec_near(si.p, {0, -20, 1.5f}, 1e-5f);

  // tmax and occlusion for quadrics: the world sphere is hit at t = 1.
  EXPECT_FALSE(s->geometry.occluded(make_ray({0, 20, -2}, {0, 0, 1}, 0.99f)));
  EXPECT_TRUE(s->geometry.occluded(make_ray({0, 20, -2}, {0, 0, 1}, 1.01f)));
  EXPECT_FALSE(s->geometry.occluded(make_ray({5, -20, -2}, {0, 0, 1}, 2.49f)));
  EXPECT_TRUE(s->geometry.occluded(make_ray({5, -20, -2}, {0, 0, 1}, 2.51f)));
  EXPECT_FALSE(s->geometry.intersect(make_ray({0, 20, -2}, {0, 0, 1}, 0.99f), &si));
}

// The same world triangles as one transformed mesh (copied through its transform) and written
// out directly: identical hits, error bounds included.
TEST(SceneGeometryInstance, TransformedAndDirectMeshesAgree) {
  std::string indices, P, uv;
  const int n = 12;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      float x = i - n / 2.f, y = j - n / 2.f, z = 0.3f * std::sin(0.7f * x) * std::cos(0.5f * y);
      char buf[96];
      std::snprintf(buf, sizeof buf, " %.9g %.9g %.9g", x, y, z);
      P += buf;
      std::snprintf(buf, sizeof buf, " %.9g %.9g", float(i) / n, float(j) / n);
      uv += buf;
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      indices += " " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(d) + " " +
                 std::to_string(a) + " " + std::to_string(d) + " " + std::to_string(c);
    }
  auto mesh = [&](const std::string& points) {
    return "Shape \"trianglemesh\" \"integer indices\" [" + indices + "] \"point P\" [" + points +
           "] \"float uv\" [" + uv + "]\n";
  };
  auto moved = load_world("sg_group_moved",
                          "Translate 3 -2 40\nRotate 35 1 0.5 0.2\nScale 1.5 0.8 1.2\n" + mesh(P));
  ASSERT_TRUE(moved->built) << moved->error;
  const ShapeInfo& info = moved->shapes[0];
  std::string world_p;
  for (uint32_t v = 0; v < info.mesh.num_vertices; ++v) {
    Vec3 w = info.object_to_world.point(info.mesh.position(v));
    char buf[96];
    std::snprintf(buf, sizeof buf, " %.9g %.9g %.9g", w.x, w.y, w.z);
    world_p += buf;
  }
  auto direct = load_world("sg_group_direct", mesh(world_p));
  ASSERT_TRUE(direct->built) << direct->error;

  Rng rng(7);
  int compared = 0;
  for (uint32_t prim = 0; prim < info.mesh.num_triangles; ++prim) {
    const uint32_t* idx = info.mesh.indices + 3 * prim;
    Vec3 c;
    for (int k = 0; k < 3; ++k) c += info.object_to_world.point(info.mesh.position(idx[k])) / 3.f;
    Vec3 o = c + Vec3{rng.next_float() - 0.5f, rng.next_float() - 0.5f, 20};
    Ray ray = make_ray(o, c - o);
    SurfaceInteraction a, b;
    bool ha = moved->geometry.intersect(ray, &a), hb = direct->geometry.intersect(ray, &b);
    ASSERT_EQ(ha, hb) << "prim " << prim;
    if (!ha) continue;
    ++compared;
    EXPECT_EQ(a.prim, b.prim);
    expect_vec_near(a.p, b.p, 0);
    expect_vec_near(a.p_error, b.p_error, 0);
    expect_vec_near(a.n, b.n, 0);
    EXPECT_EQ(a.uv.x, b.uv.x);
    EXPECT_EQ(a.uv.y, b.uv.y);
    expect_vec_near(a.dpdu, b.dpdu, 0);
  }
  EXPECT_GT(compared, int(info.mesh.num_triangles) / 2);
  EXPECT_EQ(moved->geometry.stats().copied_meshes, 1u);
  Bounds3 ba = moved->geometry.world_bounds(), bb = direct->geometry.world_bounds();
  expect_vec_near(ba.lo, bb.lo, 0);
  expect_vec_near(ba.hi, bb.hi, 0);
}

// A moving quadric is where its transform puts it at the ray's time (issue 36): a unit sphere
// sliding from x = 0 to x = 4 over the shutter, looked at along z at x = 0 and x = 4.
TEST(SceneGeometryInstance, MovingQuadricAtTheRaysTime) {
  auto moving = load_world("sg_anim_sphere", R"(
ActiveTransform EndTime
Translate 4 0 0
ActiveTransform All
Shape "sphere"
)");
  ASSERT_TRUE(moving->built) << moving->error;
  SurfaceInteraction si;
  for (float x : {0.f, 4.f})
    for (float time : {0.f, 0.5f, 1.f}) {
      Ray r = make_ray({x, 0, -5}, {0, 0, 1});
      r.time = time;
      const bool should_hit = std::fabs(x - 4 * time) < 1;
      ASSERT_EQ(moving->geometry.intersect(r, &si), should_hit) << x << " at " << time;
      EXPECT_EQ(moving->geometry.occluded(r), should_hit) << x << " at " << time;
      if (should_hit) {
        expect_vec_near(si.p, {x, 0, -1}, 1e-4f);
        expect_vec_near(si.n, {0, 0, -1}, 1e-4f);
      }
    }
  // The scene's bound holds the whole motion.
  EXPECT_LE(moving->geometry.world_bounds().lo.x, -1);
  EXPECT_GE(moving->geometry.world_bounds().hi.x, 5);
}

// A moving mesh (Embree's quaternion motion blur, hits rebuilt at the ray's time): a quad at
// z = 0 turning 90 degrees about y over the shutter is hit head-on at time 0 and edge-on (so
// missed) at time 1, and at time 0.5 where the 45-degree turn puts it.
TEST(SceneGeometryInstance, MovingMeshAtTheRaysTime) {
  auto moving = load_world("sg_anim_mesh", R"(
ActiveTransform EndTime
Rotate 90 0 1 0
ActiveTransform All
Shape "trianglemesh" "point3 P" [-1 -1 0 1 -1 0 1 1 0 -1 1 0] "integer indices" [0 1 2 0 2 3]
)");
  ASSERT_TRUE(moving->built) << moving->error;
  SurfaceInteraction si;
  Ray r = make_ray({0.5f, 0.2f, -5}, {0, 0, 1});
  r.time = 0;
  ASSERT_TRUE(moving->geometry.intersect(r, &si));
  expect_vec_near(si.p, {0.5f, 0.2f, 0}, 1e-4f);
  r.time = 0.5f;  // the quad now lies in the plane x = -z: hit at z = -0.5
  ASSERT_TRUE(moving->geometry.intersect(r, &si));
  expect_vec_near(si.p, {0.5f, 0.2f, -0.5f}, 1e-4f);
  EXPECT_NEAR(std::fabs(si.n.x), std::sqrt(0.5f), 1e-4f);
  r.time = 1;  // edge-on
  EXPECT_FALSE(moving->geometry.intersect(r, &si));
  EXPECT_FALSE(moving->geometry.occluded(r));
  r.time = 0;
  EXPECT_TRUE(moving->geometry.occluded(r));
}

// Where a ray along +z from (x, y, -10) meets the plane of triangle (a, b, c) moved by m:
// the exact pbrt-v3 position the sampled time steps must reproduce.
float exact_depth(const Transform& m, Vec3 a, Vec3 b, Vec3 c, float x, float y) {
  const Vec3 pa = m.point(a), pb = m.point(b), pc = m.point(c);
  const Vec3 n = cross(pb - pa, pc - pa);
  // n . ((x, y, z) - pa) = 0
  return pa.z - (n.x * (x - pa.x) + n.y * (y - pa.y)) / n.z;
}

// Keyframes with shear (a scale along axes the rotation turns, so pbrt-v3's decomposition has
// a symmetric S with off-diagonal terms that Embree's quaternion form cannot hold): a moving
// mesh and a moving instance are sampled at time steps, and at every time a ray meets them
// within 1e-3 of where pbrt-v3's interpolation puts them; hits are rebuilt exactly.
TEST(SceneGeometryInstance, ShearedMotionAtTheRaysTime) {
  const char* quad =
      R"(Shape "trianglemesh" "point3 P" [-1 -1 0 1 -1 0 1 1 0 -1 1 0] "integer indices" [0 1 2 0 2 3])";
  const char* motion = R"(
ActiveTransform EndTime
Scale 1 1 3
Rotate 60 0 1 0
ActiveTransform All
)";
  auto mesh = load_world("sg_anim_shear_mesh", std::string(motion) + quad);
  auto instance =
      load_world("sg_anim_shear_inst", "ObjectBegin \"o\"\n" + std::string(quad) + "\nObjectEnd\n" +
                                           motion + "ObjectInstance \"o\"\n");
  // The same motion, from the same keyframes: end = Scale(1, 1, 3) * Rotate(60, y).
  const double c = std::cos(kPi / 3), sn = std::sin(kPi / 3);
  const double start[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  const double end[16] = {c, 0, sn, 0, 0, 1, 0, 0, -3 * sn, 0, 3 * c, 0, 0, 0, 0, 1};
  const AnimatedTransform exact(start, end, 0, 1);
  float tt[3], tq[4], ts[3];
  ASSERT_FALSE(exact.diagonal_keyframe(1, tt, tq, ts));  // the case under test
  for (const auto* s : {mesh.get(), instance.get()}) {
    ASSERT_TRUE(s->built) << s->error;
    EXPECT_EQ(s->geometry.stats().sampled_motions, 1u);
    SurfaceInteraction si;
    for (int i = 0; i <= 40; ++i) {
      const float time = i / 40.f;
      const Transform m = exact.at(time);
      for (float x : {-0.3f, 0.2f, 0.45f}) {
        Ray r = make_ray({x, 0.3f, -10}, {0, 0, 1});
        r.time = time;
        ASSERT_TRUE(s->geometry.intersect(r, &si)) << time << " " << x;
        const float z = exact_depth(m, {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, x, 0.3f);
        EXPECT_NEAR(si.p.z, z, 1e-3f) << "time " << time << " x " << x;
        EXPECT_TRUE(s->geometry.occluded(r));
      }
    }
  }
  // Past the turned quad's edge at time 1 (its x reaches cos 60 = 0.5), inside it at time 0.
  Ray r = make_ray({0.9f, 0.3f, -10}, {0, 0, 1});
  r.time = 1;
  SurfaceInteraction si;
  EXPECT_FALSE(mesh->geometry.intersect(r, &si));
  r.time = 0;
  EXPECT_TRUE(mesh->geometry.intersect(r, &si));
}

// Moving meshes inside object definitions (issue 36): each instance of the object gets the
// mesh in the top level, its motion composed with the instance's transform or motion as
// pbrt-v3's two TransformedPrimitives compose them: as one exact motion under an instance that
// is a similarity and at most translates, sampled in time steps under one that turns. A quad
// turning 60 degrees about y and sliding 2 along x within its object, instanced still at z = 5,
// moving from z = 10 up by 10 and back by 10, at (6, 0, 10) turning 20 degrees about y, and
// at (-6, 0, 10) still but stretched 1.5 along y (no similarity, so sampled):
// hit where the composition puts it at each time, and left cleanly.
TEST(SceneGeometryInstance, MovingMeshesInsideObjects) {
  auto s = load_world("sg_moving_mesh_in_objects", R"(
ObjectBegin "o"
  ActiveTransform EndTime
  Translate 2 0 0
  Rotate 60 0 1 0
  ActiveTransform All
  Shape "trianglemesh" "point3 P" [-1 -1 0 1 -1 0 1 1 0 -1 1 0] "integer indices" [0 1 2 0 2 3]
ObjectEnd
AttributeBegin
  Translate 0 0 5
  ObjectInstance "o"
AttributeEnd
AttributeBegin
  Translate 0 0 10
  ActiveTransform EndTime
  Translate 0 10 10
  ActiveTransform All
  ObjectInstance "o"
AttributeEnd
AttributeBegin
  Translate 6 0 10
  ActiveTransform EndTime
  Rotate 20 0 1 0
  ActiveTransform All
  ObjectInstance "o"
AttributeEnd
AttributeBegin
  Translate -6 0 10
  Scale 1 1.5 1
  ObjectInstance "o"
AttributeEnd
)");
  ASSERT_TRUE(s->built) << s->error;
  EXPECT_EQ(s->geometry.stats().instances, 4u);
  // The turning instance's and the still but stretched one's (no similarity).
  EXPECT_EQ(s->geometry.stats().sampled_motions, 2u);
  const double c = 0.5, sn = std::sqrt(0.75);
  const double start[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  const double end[16] = {c, 0, sn, 2, 0, 1, 0, 0, -sn, 0, c, 0, 0, 0, 0, 1};
  const AnimatedTransform inner(start, end, 0, 1);
  const double at10[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 10, 0, 0, 0, 1};
  const double lift[16] = {1, 0, 0, 0, 0, 1, 0, 10, 0, 0, 1, 20, 0, 0, 0, 1};
  const AnimatedTransform sliding(at10, lift, 0, 1);
  const double c4 = std::cos(20 * kPi / 180), s4 = std::sin(20 * kPi / 180);
  const double at6[16] = {1, 0, 0, 6, 0, 1, 0, 0, 0, 0, 1, 10, 0, 0, 0, 1};
  const double turned[16] = {c4, 0, s4, 6, 0, 1, 0, 0, -s4, 0, c4, 10, 0, 0, 0, 1};
  const AnimatedTransform turning(at6, turned, 0, 1);
  for (int i = 0; i <= 10; ++i) {
    const float time = i / 10.f;
    SCOPED_TRACE(time);
    for (int which = 0; which < 4; ++which) {
      const Transform outer = which == 0   ? translate({0, 0, 5})
                              : which == 1 ? sliding.at(time)
                              : which == 2 ? turning.at(time)
                                           : translate({-6, 0, 10}) * scale(1, 1.5f, 1);
      const Transform m = outer * inner.at(time);
      // Aim at the quad's point (0.3, 0.2) in its own space, along z, from before it.
      const Vec3 target = m.point({0.3f, 0.2f, 0});
      Ray r = make_ray({target.x, target.y, which == 0 ? -5.f : 7.5f}, {0, 0, 1});
      r.time = time;
      SurfaceInteraction si;
      ASSERT_TRUE(s->geometry.intersect(r, &si)) << "instance " << which;
      EXPECT_NEAR(si.p.z, target.z, which < 2 ? 1e-4f : 2e-3f) << "instance " << which;
      EXPECT_EQ(si.instance, uint32_t(which));
      const Vec3 n = dot(si.n, r.d) < 0 ? si.n : -si.n;
      Ray out = si.spawn_ray(n);
      out.time = time;
      SurfaceInteraction again;  // a way back may meet another instance, never its own
      EXPECT_FALSE(s->geometry.intersect(out, &again) && again.instance == uint32_t(which))
          << "instance " << which;
    }
  }
}

// Moving shapes inside object definitions: a sphere and a curve that move within their
// object, instanced twice (one instance itself moving): each is where its motion, composed
// with its instance's transform at the ray's time, puts it.
TEST(SceneGeometryInstance, MovingShapesInsideObjects) {
  auto s = load_world("sg_moving_in_objects", R"(
ObjectBegin "o"
  AttributeBegin
    ActiveTransform EndTime
    Translate 2 0 0
    ActiveTransform All
    Shape "sphere" "float radius" 0.5
  AttributeEnd
  AttributeBegin
    Translate 0 3 0
    ActiveTransform EndTime
    Translate 2 0 0
    ActiveTransform All
    Shape "curve" "point P" [0 -1 0  0 -0.3 0  0 0.3 0  0 1 0] "float width" 0.2
  AttributeEnd
ObjectEnd
AttributeBegin
  Translate 0 0 5
  ObjectInstance "o"
AttributeEnd
AttributeBegin
  Translate 0 0 10
  ActiveTransform EndTime
  Translate 0 10 10
  ActiveTransform All
  ObjectInstance "o"
AttributeEnd
)");
  ASSERT_TRUE(s->built) << s->error;
  for (float time : {0.f, 0.5f, 1.f}) {
    SCOPED_TRACE(time);
    const float x = 2 * time;  // the shapes' own motion
    SurfaceInteraction si;
    Ray sphere = make_ray({x, 0, -5}, {0, 0, 1});
    sphere.time = time;
    ASSERT_TRUE(s->geometry.intersect(sphere, &si));
    EXPECT_NEAR(si.p.z, 4.5f, 1e-3f);
    Ray curve = make_ray({x, 3, -5}, {0, 0, 1});
    curve.time = time;
    ASSERT_TRUE(s->geometry.intersect(curve, &si));
    EXPECT_NEAR(si.p.z, 5, 1e-3f);
    // The moving instance: its own motion (10 up, 10 back at the end) on top of the shapes'.
    Ray moved = make_ray({x, 10 * time, 0}, {0, 0, 1});
    moved.time = time;
    moved.o.z = 6;  // past the first instance
    ASSERT_TRUE(s->geometry.intersect(moved, &si));
    EXPECT_NEAR(si.p.z, 10 + 10 * time - 0.5f, 1e-3f);
    Ray stale = make_ray({x + 1.5f, 0, -5}, {0, 0, 1});
    stale.time = time;
    EXPECT_FALSE(s->geometry.occluded(stale));
  }
}

// A moving object instance (a triangle, a sphere and a curve inside): everything in it is
// where the instance's interpolated transform puts it at the ray's time, and the world bound
// holds the whole motion.
TEST(SceneGeometryInstance, MovingInstanceAtTheRaysTime) {
  auto moving = load_world("sg_anim_inst", R"(
ObjectBegin "o"
  Shape "trianglemesh" "point3 P" [-1 -1 0 1 -1 0 1 1 0 -1 1 0] "integer indices" [0 1 2 0 2 3]
  Translate 0 0 2
  Shape "sphere" "float radius" 0.5
  Translate 0 0 2
  Shape "curve" "point P" [-1 0 0  -0.3 0 0  0.3 0 0  1 0 0] "float width" 0.2
ObjectEnd
ActiveTransform EndTime
Translate 4 0 0
ActiveTransform All
ObjectInstance "o"
)");
  ASSERT_TRUE(moving->built) << moving->error;
  EXPECT_GE(moving->geometry.world_bounds().hi.x, 5);
  for (float time : {0.f, 0.25f, 1.f}) {
    SCOPED_TRACE(time);
    const float x = 4 * time;
    SurfaceInteraction si;
    Ray quad = make_ray({x + 0.5f, 0.2f, -5}, {0, 0, 1});
    quad.time = time;
    ASSERT_TRUE(moving->geometry.intersect(quad, &si));
    expect_vec_near(si.p, {x + 0.5f, 0.2f, 0}, 1e-4f);
    EXPECT_EQ(si.instance, 0u);
    Ray sphere = make_ray({x, 0, 10}, {0, 0, -1});
    sphere.time = time;
    ASSERT_TRUE(moving->geometry.intersect(sphere, &si));
    EXPECT_NEAR(si.p.z, 4, 1e-4f);  // the curve at z = 4 is nearer than the sphere's top
    Ray beside = make_ray({x + 0.7f, 0.3f, 10}, {0, 0, -1});  // past the curve's width
    beside.time = time;
    ASSERT_TRUE(moving->geometry.intersect(beside, &si));
    EXPECT_NEAR(si.p.z, 0, 1e-4f);
    Ray old_place = make_ray({x - 1.5f, 0.2f, -5}, {0, 0, 1});
    old_place.time = time;
    EXPECT_FALSE(moving->geometry.occluded(old_place));
  }
}

// A box in an instance whose motion shears, against the box moved exactly (pbrt-v3's
// interpolation, brute-force ray/triangle tests) at 21 times: the same hits and misses at the
// same distances; and rays leaving each hit outwards never meet the box again, though Embree
// traces the sampled motion: the hit's error bound covers the difference.
TEST(SceneGeometryInstance, ShearedInstanceHitsTheExactBoxAndLeavesIt) {
  auto s = load_world("sg_shear_box", R"(
ObjectBegin "thing"
  Shape "trianglemesh" "point P" [-0.6 -0.6 -0.6  0.6 -0.6 -0.6  0.6 0.6 -0.6  -0.6 0.6 -0.6
                                  -0.6 -0.6 0.6  0.6 -0.6 0.6  0.6 0.6 0.6  -0.6 0.6 0.6]
    "integer indices" [0 2 1 0 3 2  4 5 6 4 6 7  0 1 5 0 5 4  3 7 6 3 6 2  0 4 7 0 7 3  1 2 6 1 6 5]
ObjectEnd
ActiveTransform EndTime
Scale 2.2 1 1
Rotate 70 0 1 0
ActiveTransform All
ObjectInstance "thing"
)");
  ASSERT_TRUE(s->built) << s->error;
  const double c = std::cos(70 * kPi / 180), sn = std::sin(70 * kPi / 180);
  const double start[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  const double end[16] = {2.2 * c, 0, 2.2 * sn, 0, 0, 1, 0, 0, -sn, 0, c, 0, 0, 0, 0, 1};
  const AnimatedTransform exact(start, end, 0, 1);
  const float P[8][3] = {{-0.6f, -0.6f, -0.6f}, {0.6f, -0.6f, -0.6f}, {0.6f, 0.6f, -0.6f},
                         {-0.6f, 0.6f, -0.6f},  {-0.6f, -0.6f, 0.6f}, {0.6f, -0.6f, 0.6f},
                         {0.6f, 0.6f, 0.6f},    {-0.6f, 0.6f, 0.6f}};
  const int I[36] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                     3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};
  int bad = 0, total = 0, hits = 0;
  for (int i = 0; i <= 20; ++i) {
    const float time = i / 20.f;
    const Transform m = exact.at(time);
    for (float x = -2; x <= 2; x += 0.1f) {
      Ray r = make_ray({x, 0.1f, -10}, {0, 0, 1});
      r.time = time;
      float best = kInfinity;
      for (int k = 0; k < 12; ++k) {
        Vec3 p[3];
        for (int j = 0; j < 3; ++j) {
          const float* q = P[I[3 * k + j]];
          p[j] = m.point({q[0], q[1], q[2]});
        }
        float t, b1, b2;
        if (watertight_triangle(r.o, r.d, kInfinity, p[0], p[1], p[2], &t, &b1, &b2))
          best = std::min(best, t);
      }
      SurfaceInteraction si;
      const bool hit = s->geometry.intersect(r, &si);
      ++total;
      if (hit != (best < kInfinity) || (hit && std::fabs(si.t_hit - best) > 1e-3f)) {
        ++bad;
        ADD_FAILURE() << "time " << time << " x " << x << ": ours " << hit << " "
                      << (hit ? si.t_hit : 0.f) << ", exact " << best;
        continue;
      }
      if (!hit) continue;
      ++hits;
      // Outwards along the normal (faced to the ray's side) and towards the camera.
      const Vec3 n = dot(si.n, r.d) < 0 ? si.n : -si.n;
      for (Vec3 d : {n, -r.d}) {
        Ray out = si.spawn_ray(d);
        out.time = time;
        SurfaceInteraction again;
        if (s->geometry.intersect(out, &again)) {
          ++bad;
          ADD_FAILURE() << "time " << time << " x " << x << ": the box again at " << again.t_hit;
        }
      }
    }
  }
  EXPECT_EQ(bad, 0) << total;
  EXPECT_GT(hits, total / 3);
  EXPECT_EQ(s->geometry.stats().sampled_motions, 1u);
}
// A sphere inside an object, instanced far from the origin under a rotation, a mirror and
// non-uniform scales inside and outside the object, is tested in the instance's space as
// pbrt-v3 nests its transforms. Against the same sphere written in the world under the
// product of the two transforms: the same hits, points, normals (up to pbrt-v3's orientation
// rule) and tangents, to float rounding (the two scenes' transforms round differently). And rays
// leaving each hit outwards, or back towards their origin, never meet it again, in a still and in a
// turning instance: the hit's error bound is carried out of the instance's space.
TEST(SceneGeometryInstance, QuadricsInInstancesAgreeWithTheComposedTransformAndLeaveCleanly) {
  const std::string inner = "Rotate 30 1 1 0\n Scale 1 0.6 1.4\n";
  const std::string outer = "Translate 1000 -500 300\n Rotate 70 0 0 1\n Scale -1.5 1 2\n";
  const std::string sphere = "Shape \"sphere\" \"float radius\" 2\n";
  auto instanced =
      load_world("sg_inst_quadric_nested", "ObjectBegin \"ball\"\n" + inner + sphere +
                                               "ObjectEnd\nAttributeBegin\n" + outer +
                                               "ObjectInstance \"ball\"\nAttributeEnd\n");
  auto composed = load_world("sg_inst_quadric_composed",
                             "AttributeBegin\n" + outer + inner + sphere + "AttributeEnd\n");
  auto turning =
      load_world("sg_inst_quadric_turning", "ObjectBegin \"ball\"\n" + inner + sphere +
                                                "ObjectEnd\nAttributeBegin\n" + outer +
                                                "ActiveTransform EndTime\n"
                                                "Rotate 90 0 1 0\n"
                                                "ActiveTransform All\n"
                                                "ObjectInstance \"ball\"\nAttributeEnd\n");
  ASSERT_TRUE(instanced->built) << instanced->error;
  ASSERT_TRUE(composed->built) << composed->error;
  ASSERT_TRUE(turning->built) << turning->error;
  const Vec3 center{1000, -500, 300};
  // The ellipsoid's shortest semi-axis is at least 2 * 0.6 * 1: rays aimed within 1 of its
  // center hit it in both scenes.
  Rng rng(7);
  auto in_ball = [&](float radius) {
    for (;;) {
      Vec3 v{2 * rng.next_float() - 1, 2 * rng.next_float() - 1, 2 * rng.next_float() - 1};
      if (length_squared(v) <= 1) return v * radius;
    }
  };
  int self_hits = 0, compared = 0;
  auto leaves_cleanly = [&](const LoadedScene& s, const Ray& r, const SurfaceInteraction& si) {
    const Vec3 n = dot(si.n, r.d) < 0 ? si.n : -si.n;
    for (Vec3 d : {n, -r.d}) {
      Ray out = si.spawn_ray(d);
      out.time = r.time;
      SurfaceInteraction again;
      if (s.geometry.intersect(out, &again)) ++self_hits;
    }
  };
  for (int i = 0; i < 2000; ++i) {
    Vec3 from = in_ball(1);
    from = center + normalize(from) * 20.f;
    const Vec3 to = center + in_ball(1);
    Ray r = make_ray(from, to - from);
    SurfaceInteraction a, b;
    ASSERT_TRUE(instanced->geometry.intersect(r, &a)) << i;
    ASSERT_TRUE(composed->geometry.intersect(r, &b)) << i;
    ++compared;
    EXPECT_NEAR(a.t_hit, b.t_hit, 2e-3f / length(r.d)) << i;
    expect_vec_near(a.p, b.p, 2e-3f);
    // pbrt-v3 flips a quadric's normal by its own transform's handedness, not an instance's:
    // the mirrored world sphere's normals point inwards, the instanced one's outwards.
    expect_vec_near(a.n, -b.n, 1e-3f);
    expect_vec_near(a.shading.n, -b.shading.n, 1e-3f);
    EXPECT_GT(dot(a.n, a.p - center), 0);
    // The parametrisation is ill-conditioned near the poles: looser there.
    expect_vec_near(a.dpdu, b.dpdu, 5e-3f * length(b.dpdu));
    expect_vec_near(a.dpdv, b.dpdv, 5e-3f * length(b.dpdv));
    expect_vec_near(a.dndu, b.dndu, 5e-3f * (1 + length(b.dndu)));
    EXPECT_NEAR(a.uv.x, b.uv.x, 2e-3f);
    EXPECT_NEAR(a.uv.y, b.uv.y, 2e-3f);
    // A bound for a float point must cover at least its own rounding (half an ulp; 3e-5 at
    // 1000): the instance-space bound alone (about 1e-6 here) would not.
    for (int c = 0; c < 3; ++c) EXPECT_GE(a.p_error[c], std::fabs(a.p[c]) * 0x1p-24f) << i;
    leaves_cleanly(*instanced, r, a);
    r.time = rng.next_float();
    SurfaceInteraction m;
    if (turning->geometry.intersect(r, &m)) leaves_cleanly(*turning, r, m);
  }
  EXPECT_EQ(compared, 2000);
  EXPECT_EQ(self_hits, 0);
}
}  // namespace
}  // namespace rt
