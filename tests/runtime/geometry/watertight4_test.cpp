// Four triangles tested together (watertight4.h) answer as each tested alone by
// watertight_triangle: the same hit or miss, and t and barycentrics bit for bit. Rays are random
// and aimed at random points of the triangles, and aimed exactly at shared vertices and edges of
// a grid of triangles (where an edge function is exactly 0 and the test decides it in double);
// tmax random, some just past or short of the hit; every subset of lanes. (Fails with the
// error bound on t halved, or with the lanes whose edge functions are 0 left to the float
// answer: tried.)
#include <gtest/gtest.h>

#include <cstring>

#include "runtime/core/rng.h"
#include "runtime/geometry/watertight.h"
#include "runtime/geometry/watertight4.h"

namespace rt {
namespace {

bool same_bits(float a, float b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// Every subset of the four lanes tested together against each lane alone.
void expect_as_alone(Vec3 o, Vec3 d, float tmax, const TriangleLanes& tri, int* edge_lanes,
                     int* hit_lanes) {
  const WatertightRay r = watertight_ray(o, d);
  for (int lanes = 1; lanes < 16; ++lanes) {
    float t[4], b1[4], b2[4];
    const int hits = watertight_triangles4(r, tri, lanes, tmax, t, b1, b2);
    ASSERT_EQ(hits & ~lanes, 0);
    for (int k = 0; k < 4; ++k) {
      if (!(lanes >> k & 1)) continue;
      float ta, b1a, b2a;
      const bool alone = watertight_triangle(o, d, tmax, tri.vertex(0, k), tri.vertex(1, k),
                                             tri.vertex(2, k), &ta, &b1a, &b2a);
      ASSERT_EQ(bool(hits >> k & 1), alone) << "lane " << k;
      if (!alone) continue;
      EXPECT_TRUE(same_bits(t[k], ta) && same_bits(b1[k], b1a) && same_bits(b2[k], b2a))
          << t[k] << " " << ta << " " << b1[k] << " " << b1a << " " << b2[k] << " " << b2a;
      if (lanes == 15) {
        *hit_lanes += 1;
        if (b1a == 0 || b2a == 0 || b1a + b2a == 1) *edge_lanes += 1;
      }
    }
  }
}

TEST(Watertight4, RandomRaysAnswerAsEachTriangleAlone) {
  Rng rng(7);
  auto point = [&](float s) {
    return Vec3{s * (2 * rng.next_float() - 1), s * (2 * rng.next_float() - 1),
                s * (2 * rng.next_float() - 1)};
  };
  int edges = 0, hits = 0;
  for (int i = 0; i < 20000; ++i) {
    TriangleLanes tri{};
    Vec3 v[4][3];
    const float scale = i % 3 == 0 ? 1000.f : 1.f;
    for (int k = 0; k < 4; ++k) {
      for (int j = 0; j < 3; ++j) v[k][j] = point(scale);
      if (i % 7 == 0 && k == 3) v[k][2] = v[k][1];  // degenerate: a segment
      tri.set(k, v[k][0], v[k][1], v[k][2]);
    }
    auto on_triangle = [&](int k) {
      float u = rng.next_float(), w = rng.next_float();
      if (u + w > 1) u = 1 - u, w = 1 - w;
      return (1 - u - w) * v[k][0] + u * v[k][1] + w * v[k][2];
    };
    // Aimed at a random point of one lane's triangle (most of the others missed); every
    // third ray leaves a point of another lane's triangle, as a spawned ray does, where only
    // the error bound on t tells a hit from the surface it leaves.
    const int aim = i % 4;
    const Vec3 target = on_triangle(aim);
    const Vec3 o = i % 3 == 1 ? on_triangle((aim + 1) % 4) : point(2 * scale);
    const Vec3 d = i % 5 == 0 ? point(1) : target - o;
    const float tmax = i % 4 == 0 ? kInfinity : (i % 4 == 1 ? 1.f : 2 * rng.next_float());
    expect_as_alone(o, d, tmax, tri, &edges, &hits);
  }
  EXPECT_GT(hits, 10000);
}

// A grid of unit squares, two triangles each, in the plane z = 0: rays from above aimed
// exactly at grid vertices and edge midpoints meet edge functions of exactly 0.
TEST(Watertight4, RaysAtSharedVerticesAndEdgesAnswerAsEachTriangleAlone) {
  Rng rng(11);
  int edges = 0, hits = 0;
  for (int i = 0; i < 4000; ++i) {
    const int gx = int(rng.next_float() * 4), gy = int(rng.next_float() * 4);
    // The two triangles of square (gx, gy) and of its neighbour to the right.
    auto p = [](int x, int y) { return Vec3{float(x), float(y), 0}; };
    TriangleLanes tri{};
    tri.set(0, p(gx, gy), p(gx + 1, gy), p(gx + 1, gy + 1));
    tri.set(1, p(gx, gy), p(gx + 1, gy + 1), p(gx, gy + 1));
    tri.set(2, p(gx + 1, gy), p(gx + 2, gy), p(gx + 2, gy + 1));
    tri.set(3, p(gx + 1, gy), p(gx + 2, gy + 1), p(gx + 1, gy + 1));
    const float half = 0.5f * float(int(rng.next_float() * 3));  // vertex or edge midpoint
    const Vec3 target{float(gx + 1), float(gy) + half, 0};
    // Straight down (edge functions exactly 0 in float), or slanted.
    const Vec3 o = i % 2 == 0 ? target + Vec3{0, 0, 3}
                              : target + Vec3{rng.next_float() - 0.5f, rng.next_float() - 0.5f, 3};
    const float tmax = i % 3 == 0 ? kInfinity : 3 * (1 + 1e-6f * (rng.next_float() - 0.5f));
    expect_as_alone(o, target - o, tmax, tri, &edges, &hits);
  }
  EXPECT_GT(edges, 1000);  // the double fallback was exercised
}

}  // namespace
}  // namespace rt
