// runtime/core/animated_transform.cpp — see animated_transform.h.
#include "runtime/core/animated_transform.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace rt {
namespace {

using M3 = double[3][3];

bool invert3(const M3 a, M3 out) {
  double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
               a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
               a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  if (det == 0 || !std::isfinite(det)) return false;
  double inv = 1 / det;
  out[0][0] = (a[1][1] * a[2][2] - a[1][2] * a[2][1]) * inv;
  out[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) * inv;
  out[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) * inv;
  out[1][0] = (a[1][2] * a[2][0] - a[1][0] * a[2][2]) * inv;
  out[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) * inv;
  out[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) * inv;
  out[2][0] = (a[1][0] * a[2][1] - a[1][1] * a[2][0]) * inv;
  out[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) * inv;
  out[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) * inv;
  return true;
}

// Rotation matrix (acting on column vectors) to a unit quaternion (x, y, z, w).
void to_quaternion(const M3 r, double q[4]) {
  double trace = r[0][0] + r[1][1] + r[2][2];
  if (trace > 0) {
    double s = std::sqrt(trace + 1) * 2;
    q[3] = s / 4;
    q[0] = (r[2][1] - r[1][2]) / s;
    q[1] = (r[0][2] - r[2][0]) / s;
    q[2] = (r[1][0] - r[0][1]) / s;
  } else {
    int i = 0;
    if (r[1][1] > r[0][0]) i = 1;
    if (r[2][2] > r[i][i]) i = 2;
    int j = (i + 1) % 3, k = (i + 2) % 3;
    double s = std::sqrt(r[i][i] - r[j][j] - r[k][k] + 1) * 2;
    q[i] = s / 4;
    q[3] = (r[k][j] - r[j][k]) / s;
    q[j] = (r[j][i] + r[i][j]) / s;
    q[k] = (r[k][i] + r[i][k]) / s;
  }
  double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (int c = 0; c < 4; ++c) q[c] /= n;
}

void to_matrix(const double q[4], M3 r) {
  double x = q[0], y = q[1], z = q[2], w = q[3];
  r[0][0] = 1 - 2 * (y * y + z * z);
  r[0][1] = 2 * (x * y - z * w);
  r[0][2] = 2 * (x * z + y * w);
  r[1][0] = 2 * (x * y + z * w);
  r[1][1] = 1 - 2 * (x * x + z * z);
  r[1][2] = 2 * (y * z - x * w);
  r[2][0] = 2 * (x * z - y * w);
  r[2][1] = 2 * (y * z + x * w);
  r[2][2] = 1 - 2 * (x * x + y * y);
}

}  // namespace

AnimatedTransform::AnimatedTransform(const double* start_in, const double* end_in, float t0,
                                     float t1, bool invert)
    : t0_(t0), t1_(t1) {
  animated_ = std::memcmp(start_in, end_in, 16 * sizeof(double)) != 0;
  double inv[2][16];
  const double* start = start_in;
  const double* end = end_in;
  if (invert && invert_doubles(start_in, inv[0]) && invert_doubles(end_in, inv[1])) {
    start = inv[0];
    end = inv[1];
  }
  start_ = Transform::from_doubles(start);
  end_ = Transform::from_doubles(end);
  Key* keys[2] = {&k0_, &k1_};
  const double* mats[2] = {start, end};
  for (int k = 0; k < 2; ++k) {
    const double* m = mats[k];
    Key& key = *keys[k];
    for (int i = 0; i < 3; ++i) key.t[i] = m[i * 4 + 3];
    M3 a, r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r[i][j] = a[i][j] = m[i * 4 + j];
    // Polar decomposition: average R with its inverse transpose until it is a rotation.
    for (int it = 0; it < 100; ++it) {
      M3 inv;
      if (!invert3(r, inv)) break;
      double norm = 0;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          double next = 0.5 * (r[i][j] + inv[j][i]);
          norm = std::max(norm, std::fabs(next - r[i][j]));
          r[i][j] = next;
        }
      if (norm < 1e-9) break;
    }
    M3 rinv;
    if (invert3(r, rinv)) {
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          key.s[i][j] = 0;
          for (int l = 0; l < 3; ++l) key.s[i][j] += rinv[i][l] * a[l][j];
        }
    }
    to_quaternion(r, key.q);
  }
  // Interpolate along the shorter arc.
  double d = 0;
  for (int c = 0; c < 4; ++c) d += k0_.q[c] * k1_.q[c];
  if (d < 0)
    for (double& c : k1_.q) c = -c;
}

Transform AnimatedTransform::at(float time) const {
  if (!animated_ || time <= t0_) return start_;
  if (time >= t1_) return end_;
  const double dt = (double(time) - t0_) / (double(t1_) - t0_);
  // Slerp (normalised lerp when the two are nearly parallel).
  double q[4], cos_theta = 0;
  for (int c = 0; c < 4; ++c) cos_theta += k0_.q[c] * k1_.q[c];
  if (cos_theta > 0.9995) {
    double n = 0;
    for (int c = 0; c < 4; ++c) {
      q[c] = (1 - dt) * k0_.q[c] + dt * k1_.q[c];
      n += q[c] * q[c];
    }
    for (double& c : q) c /= std::sqrt(n);
  } else {
    double theta = std::acos(std::clamp(cos_theta, -1.0, 1.0)) * dt;
    double perp[4], n = 0;
    for (int c = 0; c < 4; ++c) {
      perp[c] = k1_.q[c] - k0_.q[c] * cos_theta;
      n += perp[c] * perp[c];
    }
    for (int c = 0; c < 4; ++c)
      q[c] = k0_.q[c] * std::cos(theta) + perp[c] / std::sqrt(n) * std::sin(theta);
  }
  M3 r;
  to_matrix(q, r);
  double m[16] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double v = 0;
      for (int l = 0; l < 3; ++l) v += r[i][l] * ((1 - dt) * k0_.s[l][j] + dt * k1_.s[l][j]);
      m[i * 4 + j] = v;
    }
    m[i * 4 + 3] = (1 - dt) * k0_.t[i] + dt * k1_.t[i];
  }
  return Transform::from_doubles(m);
}

bool AnimatedTransform::diagonal_keyframe(int k, float t[3], float q[4], float scale[3]) const {
  const Key& key = k == 0 ? k0_ : k1_;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (i != j &&
          std::fabs(key.s[i][j]) > 1e-6 * (std::fabs(key.s[i][i]) + std::fabs(key.s[j][j])))
        return false;
  for (int i = 0; i < 3; ++i) {
    t[i] = float(key.t[i]);
    scale[i] = float(key.s[i][i]);
  }
  for (int c = 0; c < 4; ++c) q[c] = float(key.q[c]);
  return true;
}

Bounds3 AnimatedTransform::motion_bounds(const Bounds3& b) const {
  if (!animated_) return start_.bounds(b);
  Bounds3 out;
  constexpr int kSteps = 256;
  for (int i = 0; i <= kSteps; ++i) out.extend(at(t0_ + (t1_ - t0_) * float(i) / kSteps).bounds(b));
  // Between samples a rotating corner moves off the sampled chords by at most
  // a small part of its distance to the axis: pad by 1% of the box's size.
  Vec3 pad = out.diagonal() * 0.01f;
  out.lo = out.lo - pad;
  out.hi = out.hi + pad;
  return out;
}

}  // namespace rt
