// runtime/core/animated_transform.h — a transform moving between two keyframes, as pbrt-v3
// interpolates it (book 3rd ed., 2.9).
//
// Each keyframe matrix is decomposed once into translation T, rotation R (a
// unit quaternion, from the polar decomposition of the upper 3x3) and the
// remaining scale/shear S, M = T R S. at(time) clamps time to the keyframes'
// times, interpolates T and S linearly and R by slerp along the shorter arc,
// and recomposes: a spinning object stays rigid, which interpolating the
// matrices would not. motion_bounds() is a box holding b's image at every time
// (sampled densely and padded: rotations bulge between the keyframes).
#pragma once

#include "runtime/core/transform.h"

namespace rt {

class AnimatedTransform {
 public:
  AnimatedTransform() = default;
  // Row-major 4x4 keyframes (the archive's doubles) at times t0 <= t1; with
  // invert, their inverses move (a camera record holds camera-from-world, the
  // camera moves by world-from-camera). Singular keyframes stay as given.
  AnimatedTransform(const double* start, const double* end, float t0, float t1,
                    bool invert = false);

  bool animated() const { return animated_; }
  float start_time() const { return t0_; }
  float end_time() const { return t1_; }
  const Transform& start() const { return start_; }
  Transform at(float time) const;
  // Keyframe k's decomposition when its scale part is diagonal (no shear,
  // scale along the object's own axes): translation, rotation (x, y, z, w)
  // and the three scales; false otherwise.
  bool diagonal_keyframe(int k, float t[3], float q[4], float scale[3]) const;
  Bounds3 motion_bounds(const Bounds3& b) const;

 private:
  struct Key {
    double t[3] = {0, 0, 0};
    double q[4] = {0, 0, 0, 1};  // x, y, z, w
    double s[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  };
  Transform start_, end_;
  Key k0_, k1_;
  float t0_ = 0, t1_ = 1;
  bool animated_ = false;
};

}  // namespace rt
