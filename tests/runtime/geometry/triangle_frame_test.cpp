// A listed triangle's interaction built on its frame made once (triangle_frame, as SceneGeometry
// makes them for a scene's few listed triangles) is bit for bit the interaction made with the
// frame computed at the hit: random triangles with and without uv, normals and tangents, with
// degenerate uv and zero area, reversed orientation, mirrored instances, medium boundaries
// passed through; hits anywhere, near the edges (where the hit is moved inside) included.
// Both paths make the frame with the one triangle_frame; what this checks is that every field
// the hit reads comes from the frame of its own triangle, and that nothing the frame holds
// depended on the hit. (Fails with the frame read for the other triangle: tried.)
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "runtime/core/rng.h"
#include "runtime/geometry/triangle_hit.h"

namespace rt {
namespace {

bool same(Vec3 a, Vec3 b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}
bool same(Vec2 a, Vec2 b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

void expect_same(const SurfaceInteraction& a, const SurfaceInteraction& b) {
  EXPECT_TRUE(same(a.p, b.p));
  EXPECT_TRUE(same(a.p_error, b.p_error));
  EXPECT_TRUE(same(a.n, b.n));
  EXPECT_TRUE(same(a.wo, b.wo));
  EXPECT_TRUE(same(a.uv, b.uv));
  EXPECT_TRUE(same(a.dpdu, b.dpdu));
  EXPECT_TRUE(same(a.dpdv, b.dpdv));
  EXPECT_TRUE(same(a.dndu, b.dndu));
  EXPECT_TRUE(same(a.dndv, b.dndv));
  EXPECT_TRUE(same(a.shading.n, b.shading.n));
  EXPECT_TRUE(same(a.shading.dpdu, b.shading.dpdu));
  EXPECT_TRUE(same(a.shading.dpdv, b.shading.dpdv));
  EXPECT_TRUE(same(a.shading.dndu, b.shading.dndu));
  EXPECT_TRUE(same(a.shading.dndv, b.shading.dndv));
}

TEST(TriangleFrame, InteractionOnAFrameMadeOnceIsTheOneMadeAtTheHit) {
  Rng rng(3);
  auto f = [&](float s) { return s * (2 * rng.next_float() - 1); };
  int moved_inside = 0;
  for (int i = 0; i < 20000; ++i) {
    // Four vertices, two triangles; some attributes per case.
    std::vector<float> p, n, s, uv;
    for (int v = 0; v < 4; ++v) {
      const float scale = i % 5 == 0 ? 500.f : 2.f;
      p.insert(p.end(), {f(scale), f(scale), f(scale)});
      n.insert(n.end(), {f(1), f(1), f(1)});
      s.insert(s.end(), {f(1), f(1), f(1)});
      uv.insert(uv.end(), {f(1), f(1)});
    }
    if (i % 7 == 1) std::memcpy(&uv[2], &uv[0], 2 * sizeof(float));  // degenerate uv
    if (i % 11 == 2) std::memcpy(&p[3], &p[0], 3 * sizeof(float));   // zero area
    const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
    ShapeInfo shape;
    shape.mesh.num_vertices = 4;
    shape.mesh.num_triangles = 2;
    shape.mesh.positions = p.data();
    shape.mesh.indices = idx;
    shape.mesh.uv = i % 3 != 0 ? uv.data() : nullptr;
    shape.mesh.normals = i % 4 == 1 ? n.data() : nullptr;
    shape.mesh.tangents = i % 6 == 2 ? s.data() : nullptr;
    shape.reverse_orientation = i % 2 == 0;
    shape.passes_through = i % 9 == 3;
    TriangleSpace space;
    space.positions = p.data();
    space.measured = true;
    space.instance_mirrors = i % 8 == 5;
    const uint32_t prim = uint32_t(i % 2);
    Vec3 tri[3];
    for (int k = 0; k < 3; ++k) tri[k] = shape.mesh.position(idx[3 * prim + uint32_t(k)]);
    // Both triangles' frames, as SceneGeometry keeps them: the hit must read its own.
    TriangleFrame frames[2];
    for (uint32_t t = 0; t < 2; ++t) {
      Vec3 q[3];
      for (int k = 0; k < 3; ++k) q[k] = shape.mesh.position(idx[3 * t + uint32_t(k)]);
      frames[t] = triangle_frame(shape.mesh, t, q);
    }
    // Barycentrics anywhere, or within a hair of an edge.
    float b1 = rng.next_float(), b2 = rng.next_float();
    if (b1 + b2 > 1) b1 = 1 - b1, b2 = 1 - b2;
    if (i % 3 == 1) b1 *= 1e-6f;
    const Vec3 hit = (1 - b1 - b2) * tri[0] + b1 * tri[1] + b2 * tri[2];
    const Ray ray{hit + Vec3{f(3), f(3), 3}, -Vec3{f(3), f(3), 3}};
    float t_alone = 1, t_framed = 1;
    SurfaceInteraction alone, framed;
    triangle_interaction(shape, space, prim, b1, b2, ray, &t_alone, &alone);
    space.frames = frames;
    triangle_interaction(shape, space, prim, b1, b2, ray, &t_framed, &framed);
    expect_same(alone, framed);
    if (::testing::Test::HasFailure()) {
      ADD_FAILURE() << "case " << i;
      return;
    }
    const Vec3 unmoved = (1 - b1 - b2) * tri[0] + b1 * tri[1] + b2 * tri[2];
    if (!same(alone.p, unmoved)) ++moved_inside;
  }
  EXPECT_GT(moved_inside, 1000);  // hits near edges were moved inside, on the frame's edges
}

}  // namespace
}  // namespace rt
