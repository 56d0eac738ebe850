// runtime/texture/noise.h — Perlin noise, FBm and turbulence as pbrt-v3 computes them
// (book section 10.6).
//
// noise() is Perlin's gradient noise on the integer lattice with his
// permutation table and the 6t^5 - 15t^4 + 10t^3 fade; it is 0 at lattice
// points and lies within about [-1, 1]. fbm() and turbulence() sum octaves
// (frequency x1.99, amplitude x omega per octave), with the number of
// octaves cut by the screen-space footprint dp/dx, dp/dy to avoid aliasing.
#pragma once

#include "runtime/core/vec.h"

namespace rt {

float noise(float x, float y = .5f, float z = .5f);
inline float noise(Vec3 p) {
  return noise(p.x, p.y, p.z);
}
float fbm(Vec3 p, Vec3 dpdx, Vec3 dpdy, float omega, int max_octaves);
float turbulence(Vec3 p, Vec3 dpdx, Vec3 dpdy, float omega, int max_octaves);

}  // namespace rt
