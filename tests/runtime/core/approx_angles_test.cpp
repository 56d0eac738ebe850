// The hint angles (approx_angles.h) against the exact ones: within 2e-4 radians over the sphere,
// poles, axes and octant boundaries included, so a prefetch lands on the texel (a 2048-wide
// map's spans 3e-3 radians). (Fails with a wrong octant fold or coefficient: tried.)
#include "runtime/core/approx_angles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "runtime/core/rng.h"
#include "runtime/core/sampling.h"

namespace rt {
namespace {

// Distance between two angles on the circle (phi wraps at 2 pi).
float circle_distance(float a, float b) {
  const float d = std::fabs(a - b);
  return std::min(d, 2 * kPi - d);
}

TEST(ApproxAngles, WithinTwoTenThousandthsOfARadian) {
  std::vector<Vec3> dirs = {{1, 0, 0},   {-1, 0, 0}, {0, 1, 0}, {0, -1, 0},
                            {0, 0, 1},   {0, 0, -1}, {1, 1, 0}, {-1, 1, 0},
                            {-1, -1, 0}, {1, -1, 0}, {1, 1, 1}, {-1, -1, -1}};
  Rng rng(11);
  for (int i = 0; i < 200000; ++i)
    dirs.push_back(uniform_sample_sphere({rng.next_float(), rng.next_float()}));
  float worst_theta = 0, worst_phi = 0;
  for (Vec3 w : dirs) {
    w = normalize(w);
    worst_theta = std::max(worst_theta, std::fabs(approx_spherical_theta(w) - spherical_theta(w)));
    // phi is undefined at the poles; elsewhere compare on the circle.
    if (std::fabs(w.z) < 0.9999f)
      worst_phi = std::max(worst_phi, circle_distance(approx_spherical_phi(w), spherical_phi(w)));
    const float phi = approx_spherical_phi(w);
    EXPECT_TRUE(phi >= 0 && phi <= 2 * kPi) << phi;
  }
  EXPECT_LT(worst_theta, 2e-4f);
  EXPECT_LT(worst_phi, 2e-4f);
}

}  // namespace
}  // namespace rt
