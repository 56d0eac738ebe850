// runtime/medium/majorant_grid.cpp — see majorant_grid.h.
#include "runtime/medium/majorant_grid.h"

namespace rt {

void MajorantGrid::build(const float* density, int nx, int ny, int nz, int cell) {
  const int n[3] = {nx, ny, nz};
  int res[3];
  for (int a = 0; a < 3; ++a) res[a] = std::max(1, (n[a] + cell - 1) / cell);
  mx_ = res[0];
  my_ = res[1];
  mz_ = res[2];
  majorant_.assign(size_t(mx_) * my_ * mz_, 0.f);
  max_ = 0;
  // Samples a lookup at grid coordinate x uses: floor(x n - 1/2) and the next.
  auto range = [&](int a, int c, int* lo, int* hi) {
    *lo = std::max(0, int(std::floor(float(c) / float(res[a]) * float(n[a]) - 0.5f)) - 1);
    *hi =
        std::min(n[a] - 1, int(std::floor(float(c + 1) / float(res[a]) * float(n[a]) - 0.5f)) + 2);
  };
  for (int cz = 0; cz < mz_; ++cz)
    for (int cy = 0; cy < my_; ++cy)
      for (int cx = 0; cx < mx_; ++cx) {
        int x0, x1, y0, y1, z0, z1;
        range(0, cx, &x0, &x1);
        range(1, cy, &y0, &y1);
        range(2, cz, &z0, &z1);
        float m = 0;
        for (int z = z0; z <= z1; ++z)
          for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) m = std::max(m, density[(size_t(z) * ny + y) * nx + x]);
        majorant_[(size_t(cz) * my_ + cy) * mx_ + cx] = m;
        max_ = std::max(max_, m);
      }
}

}  // namespace rt
