// runtime/medium/majorant_grid.h — upper bounds of a density grid over coarse cells, and the
// walk of a ray through them.
//
// Each cell covers a block of density samples and holds the largest density
// that trilinear interpolation can return anywhere inside it (the samples
// the lookups of its points touch, one more on each side for rounding).
// walk() visits the cells a ray crosses in order (a 3D DDA, Amanatides and
// Woo 1987) and calls visit(t0, t1, majorant) for each crossing with a
// non-zero majorant; visit returns true to stop. Tracking methods can then
// take exponential steps with each cell's own bound: by the memorylessness
// of the exponential, restarting at each cell boundary keeps the expectation.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "runtime/core/vec.h"

namespace rt {

class MajorantGrid {
 public:
  // density: nx * ny * nz samples, x fastest. cell: samples per cell side.
  void build(const float* density, int nx, int ny, int nz, int cell);
  int cells() const { return mx_ * my_ * mz_; }
  float max_density() const { return max_; }

  // o, d: the ray in grid space ([0,1]^3), d per unit of the caller's t;
  // [t0, t1] the part inside the unit cube.
  template <typename Visit>
  void walk(Vec3 o, Vec3 d, float t0, float t1, Visit&& visit) const {
    const int res[3] = {mx_, my_, mz_};
    int cell[3], step[3], end[3];
    float next[3], delta[3];
    Vec3 p = o + d * t0;
    for (int a = 0; a < 3; ++a) {
      cell[a] = std::clamp(int(p[a] * float(res[a])), 0, res[a] - 1);
      if (d[a] == 0) {
        next[a] = kInfinity;
        delta[a] = 0;
        step[a] = 0;
        end[a] = -2;
      } else if (d[a] > 0) {
        next[a] = t0 + (float(cell[a] + 1) / float(res[a]) - p[a]) / d[a];
        delta[a] = 1 / (float(res[a]) * d[a]);
        step[a] = 1;
        end[a] = res[a];
      } else {
        next[a] = t0 + (float(cell[a]) / float(res[a]) - p[a]) / d[a];
        delta[a] = -1 / (float(res[a]) * d[a]);
        step[a] = -1;
        end[a] = -1;
      }
    }
    float t = t0;
    for (;;) {
      int a = next[0] < next[1] ? (next[0] < next[2] ? 0 : 2) : (next[1] < next[2] ? 1 : 2);
      float t_exit = std::min(next[a], t1);
      float m = majorant_[size_t((cell[2] * my_ + cell[1]) * mx_ + cell[0])];
      if (m > 0 && t_exit > t && visit(t, t_exit, m)) return;
      if (t_exit >= t1) return;
      t = t_exit;
      cell[a] += step[a];
      if (cell[a] == end[a]) return;
      next[a] += delta[a];
    }
  }

 private:
  int mx_ = 0, my_ = 0, mz_ = 0;
  float max_ = 0;
  std::vector<float> majorant_;
};

}  // namespace rt
