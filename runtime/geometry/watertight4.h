// runtime/geometry/watertight4.h — watertight_triangle (watertight.h) on four triangles at once.
//
// A ray through a listed scene (prim_list.h) meets several triangles' boxes (a room's walls,
// a cube's faces), and each test is a chain of dependent products and a division: in the lanes
// of SSE registers four such chains run side by side (hm-lights/point: the list's share of the
// render 27% -> 23%, perf, 1 thread). Each lane does watertight_triangle's arithmetic in its
// order (the build forbids fused multiply-adds), so its answer has the bits that function gives
// for the same triangle; a lane with an edge function exactly 0, which that function decides
// again in double, is handed to it.
#pragma once

#include "runtime/core/vec.h"

namespace rt {

// The part of the test that depends on the ray alone.
struct WatertightRay {
  Vec3 o, d;         // as given
  float po[3];       // o permuted: kx, ky, kz
  float sx, sy, sz;  // the shear
  int kx, ky, kz;    // kz: d's largest component
  bool valid;        // d is not zero
};
WatertightRay watertight_ray(Vec3 o, Vec3 d);

// Four triangles: p[vertex][world axis][lane].
struct alignas(16) TriangleLanes {
  float p[3][3][4];
  Vec3 vertex(int v, int lane) const { return {p[v][0][lane], p[v][1][lane], p[v][2][lane]}; }
  void set(int lane, Vec3 p0, Vec3 p1, Vec3 p2);
};

// The lanes among `lanes` (bit k: lane k) whose triangle the ray hits in (0, tmax), as bits;
// for each, t[k] and the barycentrics b1[k], b2[k] of vertices 1 and 2.
int watertight_triangles4(const WatertightRay& r, const TriangleLanes& tri, int lanes, float tmax,
                          float t[4], float b1[4], float b2[4]);

}  // namespace rt
