// SceneGeometry on world triangle meshes: hits rebuilt as pbrt-v3's
// Triangle::Intersect (t, p, n, uv, dp/du, shading normals from N,
// orientation flips), tmax respected, archive buffers used in place.
#include <gtest/gtest.h>

#include "scene_geometry_test_support.h"

namespace rt {
namespace {

void expect_vec_near(Vec3 a, Vec3 b, float tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

// A triangle in the plane z = 2 and a ray from the origin hitting it at
// t = 2, p = (0.4, 0.6, 2): barycentrics (0.25, 0.35, 0.4).
const char* kTriangle = R"(
Shape "trianglemesh" "integer indices" [0 1 2] "point P" [-1 -1 2  3 -1 2  -1 3 2]
  "float uv" [0 0 1 0 0 1]
)";
const Vec3 kDir{0.2f, 0.3f, 1};

TEST(SceneGeometryTriangle, HitAtExpectedPlace) {
  auto s = load_world("sg_tri_hit", kTriangle);
  ASSERT_TRUE(s->built) << s->error;
  SurfaceInteraction si;
  Ray ray = make_ray({0, 0, 0}, kDir);
  ASSERT_TRUE(s->geometry.intersect(ray, &si));
  expect_vec_near(si.p, {0.4f, 0.6f, 2}, 2e-6f);
  EXPECT_GT(si.p_error.x, 0);
  EXPECT_LE(std::fabs(si.p.z - 2), si.p_error.z);
  expect_vec_near(si.n, {0, 0, 1}, 1e-6f);
  expect_vec_near(si.shading.n, {0, 0, 1}, 1e-6f);
  expect_vec_near(si.wo, -normalize(kDir), 1e-6f);
  EXPECT_NEAR(si.uv.x, 0.35f, 1e-6f);
  EXPECT_NEAR(si.uv.y, 0.4f, 1e-6f);
  expect_vec_near(si.dpdu, {4, 0, 0}, 1e-5f);
  expect_vec_near(si.dpdv, {0, 4, 0}, 1e-5f);
  expect_vec_near(si.dndu, {0, 0, 0}, 0);
  EXPECT_EQ(si.shape, 0u);
  EXPECT_EQ(si.prim, 0u);
  EXPECT_EQ(si.instance, kNone);
  EXPECT_EQ(si.face_index, 0);
  // A miss beside it.
  EXPECT_FALSE(s->geometry.intersect(make_ray({0, 0, 0}, {-1, -1, 1}), &si));
  // World bound: the vertices.
  Bounds3 b = s->geometry.world_bounds();
  expect_vec_near(b.lo, {-1, -1, 2}, 0);
  expect_vec_near(b.hi, {3, 3, 2}, 0);
}

TEST(SceneGeometryTriangle, DefaultUvAndFaceIndices) {
  auto s = load_world("sg_tri_uv", R"(
Shape "trianglemesh" "integer indices" [0 1 2  0 2 3] "point P" [0 0 2  4 0 2  4 4 2  0 4 2]
  "integer faceIndices" [7 9]
)");
  ASSERT_TRUE(s->built) << s->error;
  SurfaceInteraction si;
  // (3, 1, 2) lies in triangle 0: p = b0 (0,0) + b1 (4,0) + b2 (4,4) -> b1 = .5, b2 = .25.
  ASSERT_TRUE(s->geometry.intersect(make_ray({3, 1, 0}, {0, 0, 1}), &si));
  EXPECT_EQ(si.prim, 0u);
  EXPECT_EQ(si.face_index, 7);
  // pbrt-v3's default uv: (0,0) (1,0) (1,1) -> (b1 + b2, b2).
  EXPECT_NEAR(si.uv.x, 0.75f, 1e-6f);
  EXPECT_NEAR(si.uv.y, 0.25f, 1e-6f);
  ASSERT_TRUE(s->geometry.intersect(make_ray({1, 3, 0}, {0, 0, 1}), &si));
  EXPECT_EQ(si.prim, 1u);
  EXPECT_EQ(si.face_index, 9);
}

TEST(SceneGeometryTriangle, ShadingNormalsFromN) {
  // N tilted and unnormalised: ns = normalize(b0 n0 + b1 n1 + b2 n2).
  auto s = load_world("sg_tri_n", std::string(kTriangle) + R"(
  "normal N" [0 0 1  1 0 1  0 1 1]
)");
  ASSERT_TRUE(s->built) << s->error;
  SurfaceInteraction si;
  ASSERT_TRUE(s->geometry.intersect(make_ray({0, 0, 0}, kDir), &si));
  Vec3 ns = normalize(Vec3{0.35f, 0.4f, 1});
  expect_vec_near(si.shading.n, ns, 1e-6f);
  expect_vec_near(si.n, {0, 0, 1}, 1e-6f);  // already on the shading normal's side
  // Shading frame: ss from dp/du made perpendicular to ns, ts = ns x ss.
  EXPECT_NEAR(dot(si.shading.dpdu, ns), 0, 1e-6f);
  EXPECT_NEAR(dot(si.shading.dpdv, ns), 0, 1e-6f);
  EXPECT_NEAR(length(si.shading.dpdu), 1, 1e-6f);
  // pbrt-v3's Gram-Schmidt (ts = ss x ns, ss = ts x ns) turns ss against dp/du.
  EXPECT_LT(si.shading.dpdu.x, -0.9f);
  expect_vec_near(cross(si.shading.dpdu, si.shading.dpdv), ns, 1e-6f);
  // dn/du, dn/dv from the normals' uv differences: N = (u, v, 1).
  expect_vec_near(si.shading.dndu, {1, 0, 0}, 1e-6f);
  expect_vec_near(si.shading.dndv, {0, 1, 0}, 1e-6f);
  // Geometric values stay geometric.
  expect_vec_near(si.dpdu, {4, 0, 0}, 1e-5f);
}

TEST(SceneGeometryTriangle, GeometricNormalFollowsN) {
  // N pointing away from the edge cross product: the geometric normal flips to it.
  auto s = load_world("sg_tri_nflip", std::string(kTriangle) + R"(
  "normal N" [0 0 -1  0 0 -1  0 0 -1]
)");
  ASSERT_TRUE(s->built) << s->error;
  SurfaceInteraction si;
  ASSERT_TRUE(s->geometry.intersect(make_ray({0, 0, 0}, kDir), &si));
  expect_vec_near(si.shading.n, {0, 0, -1}, 1e-6f);
  expect_vec_near(si.n, {0, 0, -1}, 1e-6f);
}

TEST(SceneGeometryTriangle, ReverseOrientationFlipsNormal) {
  auto s = load_world("sg_tri_ro", std::string("ReverseOrientation\n") + kTriangle);
  ASSERT_TRUE(s->built) << s->error;
  SurfaceInteraction si;
  ASSERT_TRUE(s->geometry.intersect(make_ray({0, 0, 0}, kDir), &si));
  expect_vec_near(si.n, {0, 0, -1}, 1e-6f);
  expect_vec_near(si.shading.n, {0, 0, -1}, 1e-6f);

  // With N, pbrt-v3's SetShadingGeometry flips the shading normal too, and
  // the geometric normal follows it.
  auto sn = load_world("sg_tri_ro_n", std::string("ReverseOrientation\n") + kTriangle +
                                          R"("normal N" [0 0 1  1 0 1  0 1 1])");
  ASSERT_TRUE(sn->built) << sn->error;
  ASSERT_TRUE(sn->geometry.intersect(make_ray({0, 0, 0}, kDir), &si));
  expect_vec_near(si.shading.n, -normalize(Vec3{0.35f, 0.4f, 1}), 1e-6f);
  expect_vec_near(si.n, {0, 0, -1}, 1e-6f);
}

TEST(SceneGeometryTriangle, MirroredTransformFlipsNormal) {
  // The same world triangle three ways: written directly (x negated), through
  // a mirroring transform, and through the mirror with ReverseOrientation.
  const char* mirrored_direct = R"(
Shape "trianglemesh" "integer indices" [0 1 2] "point P" [1 -1 2  -3 -1 2  1 3 2]
  "float uv" [0 0 1 0 0 1])";
  auto direct = load_world("sg_tri_mirror_direct", mirrored_direct);
  auto mirror = load_world("sg_tri_mirror", std::string("Scale -1 1 1\n") + kTriangle);
  auto both =
      load_world("sg_tri_mirror_ro", std::string("Scale -1 1 1\nReverseOrientation\n") + kTriangle);
  ASSERT_TRUE(direct->built && mirror->built && both->built);
  Ray ray = make_ray({0, 0, 0}, {-kDir.x, kDir.y, kDir.z});
  SurfaceInteraction a, b, c;
  ASSERT_TRUE(direct->geometry.intersect(ray, &a));
  ASSERT_TRUE(mirror->geometry.intersect(ray, &b));
  ASSERT_TRUE(both->geometry.intersect(ray, &c));
  // Written directly the edges wind clockwise seen from +z: n = -z. Through
  // the mirror pbrt-v3 flips it back (the normal transforms as a normal).
  expect_vec_near(a.n, {0, 0, -1}, 1e-6f);
  expect_vec_near(b.n, {0, 0, 1}, 1e-6f);
  expect_vec_near(c.n, {0, 0, -1}, 1e-6f);
  expect_vec_near(a.p, b.p, 1e-6f);
  EXPECT_NEAR(a.uv.x, b.uv.x, 1e-6f);
  EXPECT_EQ(mirror->geometry.stats().copied_meshes, 1u);  // through its transform
}

TEST(SceneGeometryTriangle, OccludedAndIntersectRespectTmax) {
  auto s = load_world("sg_tri_tmax", kTriangle);
  ASSERT_TRUE(s->built) << s->error;
  SurfaceInteraction si;
  // The hit is at t = 2.
  EXPECT_FALSE(s->geometry.occluded(make_ray({0, 0, 0}, kDir, 1.99f)));
  EXPECT_TRUE(s->geometry.occluded(make_ray({0, 0, 0}, kDir, 2.01f)));
  EXPECT_FALSE(s->geometry.intersect(make_ray({0, 0, 0}, kDir, 1.99f), &si));
  EXPECT_TRUE(s->geometry.intersect(make_ray({0, 0, 0}, kDir, 2.01f), &si));
  // Behind the origin: only t > 0 counts.
  EXPECT_FALSE(s->geometry.occluded(make_ray({0.4f, 0.6f, 3}, {0, 0, 1})));
  // spawn_ray_to stops short of the target: a point on the surface is not
  // occluded by the surface itself.
  Interaction from;
  from.p = {0.5f, 0.5f, 0};
  EXPECT_FALSE(s->geometry.occluded(from.spawn_ray_to(Vec3{0.5f, 0.5f, 2})));
  EXPECT_TRUE(s->geometry.occluded(from.spawn_ray_to(Vec3{0.5f, 0.5f, 2.5f})));
}

// World meshes sit in the top level: with the identity transform on the archive's own arrays,
// with another transform on a copy of their positions through it (as pbrt-v3 transforms them
// at load); no Embree instance either way.
TEST(SceneGeometryTriangle, WorldMeshesInTheTopLevel) {
  auto s = load_world("sg_tri_inplace", std::string(kTriangle) + R"(
AttributeBegin
  Translate 0 0 1
  Shape "trianglemesh" "integer indices" [0 1 2  2 1 3] "point P" [0 0 0  1 0 0  0 1 0  1 1 0]
AttributeEnd
AttributeBegin
  Translate 0 0 1
  Shape "trianglemesh" "integer indices" [0 1 2] "point P" [5 5 0  6 5 0  5 6 0]
AttributeEnd
)");
  ASSERT_TRUE(s->built) << s->error;
  const GeometryStats& st = s->geometry.stats();
  EXPECT_EQ(st.copied_meshes, 2u);
  EXPECT_EQ(st.triangles, 4u);
  EXPECT_EQ(st.instances, 0u);
  EXPECT_GT(st.embree_bytes, 0u);
  // Both translated meshes hit where the transform puts them.
  SurfaceInteraction si;
  ASSERT_TRUE(s->geometry.intersect(make_ray({5.2f, 5.2f, 5}, {0, 0, -1}), &si));
  EXPECT_EQ(si.shape, 2u);
  EXPECT_NEAR(si.p.z, 1, 1e-6f);
  ASSERT_TRUE(s->geometry.intersect(make_ray({0.2f, 0.2f, -5}, {0, 0, 1}), &si));
  EXPECT_EQ(si.shape, 1u);
  EXPECT_NEAR(si.p.z, 1, 1e-6f);
  ASSERT_TRUE(s->geometry.intersect(make_ray({0.2f, 0.2f, 5}, {0, 0, -1}), &si));
  EXPECT_EQ(si.shape, 0u);  // the z = 2 triangle is above the z = 1 one
  EXPECT_NEAR(si.p.z, 2, 1e-6f);
  Bounds3 b = s->geometry.world_bounds();
  EXPECT_EQ(b.hi.x, 6.f);
  EXPECT_EQ(b.lo.z, 1.f);
}

}  // namespace
}  // namespace rt
