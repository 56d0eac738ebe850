// AnimatedTransform (book 2.9): the keyframes at their times and beyond, rigid interpolation of
// rotations (slerp, not a matrix blend that would shrink the object half-way), translation and
// scale interpolated linearly, and motion bounds that hold the moving box at every time.
#include <gtest/gtest.h>

#include <cmath>

#include "runtime/core/animated_transform.h"

namespace rt {
namespace {

// Row-major: rotation by deg about z, then scale s, then translation (tx, 0, 0).
void trs(double deg, double s, double tx, double m[16]) {
  double c = std::cos(deg * M_PI / 180), n = std::sin(deg * M_PI / 180);
  double v[16] = {c * s, -n * s, 0, tx, n * s, c * s, 0, 0, 0, 0, s, 0, 0, 0, 0, 1};
  for (int i = 0; i < 16; ++i) m[i] = v[i];
}

TEST(AnimatedTransform, KeyframesAndClamping) {
  double a[16], b[16];
  trs(0, 1, 0, a);
  trs(90, 2, 4, b);
  AnimatedTransform at(a, b, 0.5f, 1.5f);
  ASSERT_TRUE(at.animated());
  Vec3 p{1, 0, 0};
  for (float t : {-1.f, 0.5f}) {
    Vec3 q = at.at(t).point(p);
    EXPECT_NEAR(q.x, 1, 1e-5f);
    EXPECT_NEAR(q.y, 0, 1e-5f);
  }
  for (float t : {1.5f, 3.f}) {
    Vec3 q = at.at(t).point(p);
    EXPECT_NEAR(q.x, 4, 1e-5f);
    EXPECT_NEAR(q.y, 2, 1e-5f);
  }
}

TEST(AnimatedTransform, RotationIsInterpolatedRigidly) {
  double a[16], b[16];
  trs(0, 1, 0, a);
  trs(90, 3, 2, b);
  AnimatedTransform at(a, b, 0, 1);
  Vec3 q = at.at(0.5f).point({1, 0, 0});
  // Half-way: 45 degrees, scale 2, translation 1; a matrix blend would give length 2/sqrt(2).
  EXPECT_NEAR(q.x, 1 + 2 * std::cos(M_PI / 4), 1e-4f);
  EXPECT_NEAR(q.y, 2 * std::sin(M_PI / 4), 1e-4f);
  EXPECT_NEAR(q.z, 0, 1e-5f);
}

TEST(AnimatedTransform, MotionBoundsHoldTheBoxAtEveryTime) {
  double a[16], b[16];
  trs(10, 1, 0, a);
  trs(170, 1.5, 1, b);
  AnimatedTransform at(a, b, 0, 1);
  Bounds3 box;
  box.extend(Vec3{-1, -0.5f, -0.2f});
  box.extend(Vec3{2, 0.5f, 0.3f});
  Bounds3 mb = at.motion_bounds(box);
  for (int i = 0; i <= 1000; ++i) {
    Transform x = at.at(i / 1000.f);
    for (int c = 0; c < 8; ++c) {
      Vec3 corner{c & 1 ? box.hi.x : box.lo.x, c & 2 ? box.hi.y : box.lo.y,
                  c & 4 ? box.hi.z : box.lo.z};
      Vec3 w = x.point(corner);
      for (int k = 0; k < 3; ++k) {
        EXPECT_GE(w[k], mb.lo[k]);
        EXPECT_LE(w[k], mb.hi[k]);
      }
    }
  }
}

}  // namespace
}  // namespace rt
