// tests/runtime/sampler/sampler_test_support.h — builds a scene's sampler from
// real pbrt-v3 text, and checks point-set stratification.
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "runtime/runtime_test_support.h"
#include "runtime/sampler/sampler.h"
#include "test_support.h"

namespace rt {

// Compiles a scene whose sampler line is `sampler_line` and builds its sampler.
inline std::unique_ptr<Sampler> sampler_from_text(const std::string& name,
                                                  const std::string& sampler_line,
                                                  int spp_override = 0, uint64_t seed = 7,
                                                  Bounds2i bounds = {{0, 0}, {64, 64}},
                                                  std::string* error_out = nullptr) {
  pbrta::SceneArchive archive;
  std::string text = sampler_line + R"(
Camera "perspective"
WorldBegin
Shape "sphere"
WorldEnd
)";
  if (!testing_support::compile_text(testing_support::scratch_dir(name), text, &archive))
    return nullptr;
  std::string error;
  auto s = make_sampler(archive, spp_override, seed, bounds, &error);
  if (error_out) *error_out = error;
  EXPECT_TRUE(s != nullptr || error_out) << error;
  return s;
}

// True when every cell of an nx x ny grid over [0,1)^2 holds exactly one point.
inline bool one_per_cell(const std::vector<Vec2>& pts, int nx, int ny) {
  if (int64_t(pts.size()) != int64_t(nx) * ny) return false;
  std::vector<int> count(pts.size(), 0);
  for (Vec2 p : pts) {
    if (!(p.x >= 0 && p.x < 1 && p.y >= 0 && p.y < 1)) return false;
    int cx = int(p.x * nx), cy = int(p.y * ny);
    if (++count[size_t(cy * nx + cx)] > 1) return false;
  }
  return true;
}

// A (0,m,2)-net in base 2: one point in every elementary interval of area 1/n.
inline bool is_02_net(const std::vector<Vec2>& pts) {
  int n = int(pts.size()), k = 0;
  while ((1 << k) < n) ++k;
  if ((1 << k) != n) return false;
  for (int j = 0; j <= k; ++j)
    if (!one_per_cell(pts, 1 << j, 1 << (k - j))) return false;
  return true;
}

inline bool one_per_stratum(const std::vector<float>& v) {
  std::vector<Vec2> pts;
  for (float x : v) pts.push_back({x, 0.5f});
  return one_per_cell(pts, int(v.size()), 1);
}

// The first 2-D value of each of pixel p's samples.
inline std::vector<Vec2> first_2d(Sampler& s, Point2i p) {
  std::vector<Vec2> pts;
  s.start_pixel(p);
  do pts.push_back(s.get_2d());
  while (s.start_next_sample());
  return pts;
}

}  // namespace rt
