#include "compiler/transform.h"

#include <cmath>
#include <utility>

namespace pbrtc {

Matrix4 mul(const Matrix4& a, const Matrix4& b) {
  Matrix4 r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a.at(i, k) * b.at(k, j);
      r.at(i, j) = s;
    }
  return r;
}

Matrix4 transpose(const Matrix4& a) {
  Matrix4 r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r.at(i, j) = a.at(j, i);
  return r;
}

bool invert(const Matrix4& a, Matrix4* inv) {
  // Gauss-Jordan with partial pivoting on an augmented copy.
  double w[4][8];
  double largest = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      w[i][j] = a.at(i, j);
      w[i][j + 4] = i == j ? 1 : 0;
      largest = std::max(largest, std::abs(a.at(i, j)));
    }
  if (largest == 0 || !std::isfinite(largest)) return false;
  for (int col = 0; col < 4; ++col) {
    int pivot = col;
    for (int r = col + 1; r < 4; ++r)
      if (std::abs(w[r][col]) > std::abs(w[pivot][col])) pivot = r;
    if (std::abs(w[pivot][col]) <= 1e-14 * largest) return false;
    if (pivot != col)
      for (int j = 0; j < 8; ++j) std::swap(w[pivot][j], w[col][j]);
    double d = 1.0 / w[col][col];
    for (int j = 0; j < 8; ++j) w[col][j] *= d;
    for (int r = 0; r < 4; ++r) {
      if (r == col) continue;
      double f = w[r][col];
      if (f == 0) continue;
      for (int j = 0; j < 8; ++j) w[r][j] -= f * w[col][j];
    }
  }
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) inv->at(i, j) = w[i][j + 4];
  return true;
}

bool is_identity(const Matrix4& a) {
  return a == Matrix4();
}

bool swaps_handedness(const Matrix4& a) {
  double det = a.at(0, 0) * (a.at(1, 1) * a.at(2, 2) - a.at(1, 2) * a.at(2, 1)) -
               a.at(0, 1) * (a.at(1, 0) * a.at(2, 2) - a.at(1, 2) * a.at(2, 0)) +
               a.at(0, 2) * (a.at(1, 0) * a.at(2, 1) - a.at(1, 1) * a.at(2, 0));
  return det < 0;
}

bool is_projective(const Matrix4& a) {
  return a.at(3, 0) != 0 || a.at(3, 1) != 0 || a.at(3, 2) != 0 || a.at(3, 3) != 1;
}

Matrix4 translate(double x, double y, double z) {
  Matrix4 r;
  r.at(0, 3) = x;
  r.at(1, 3) = y;
  r.at(2, 3) = z;
  return r;
}

Matrix4 scale(double x, double y, double z) {
  Matrix4 r;
  r.at(0, 0) = x;
  r.at(1, 1) = y;
  r.at(2, 2) = z;
  return r;
}

Matrix4 rotate(double angle_degrees, double x, double y, double z) {
  double len = std::sqrt(x * x + y * y + z * z);
  x /= len;
  y /= len;
  z /= len;
  double theta = angle_degrees * M_PI / 180.0;
  double s = std::sin(theta), c = std::cos(theta);
  // Rodrigues' rotation formula: R = cI + s[a]x + (1 - c) a a^T.
  Matrix4 r;
  r.at(0, 0) = x * x + (1 - x * x) * c;
  r.at(0, 1) = x * y * (1 - c) - z * s;
  r.at(0, 2) = x * z * (1 - c) + y * s;
  r.at(1, 0) = x * y * (1 - c) + z * s;
  r.at(1, 1) = y * y + (1 - y * y) * c;
  r.at(1, 2) = y * z * (1 - c) - x * s;
  r.at(2, 0) = x * z * (1 - c) - y * s;
  r.at(2, 1) = y * z * (1 - c) + x * s;
  r.at(2, 2) = z * z + (1 - z * z) * c;
  return r;
}

bool look_at(const double eye[3], const double look[3], const double up[3], Matrix4* out) {
  double dir[3] = {look[0] - eye[0], look[1] - eye[1], look[2] - eye[2]};
  double dl = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
  if (dl == 0) return false;
  for (double& v : dir) v /= dl;
  double ul = std::sqrt(up[0] * up[0] + up[1] * up[1] + up[2] * up[2]);
  if (ul == 0) return false;
  double u[3] = {up[0] / ul, up[1] / ul, up[2] / ul};
  // right = normalize(up x dir)
  double right[3] = {u[1] * dir[2] - u[2] * dir[1], u[2] * dir[0] - u[0] * dir[2],
                     u[0] * dir[1] - u[1] * dir[0]};
  double rl = std::sqrt(right[0] * right[0] + right[1] * right[1] + right[2] * right[2]);
  if (rl < 1e-9) return false;
  for (double& v : right) v /= rl;
  double new_up[3] = {dir[1] * right[2] - dir[2] * right[1], dir[2] * right[0] - dir[0] * right[2],
                      dir[0] * right[1] - dir[1] * right[0]};
  // world-from-camera has columns right, up, dir, eye; LookAt returns its inverse.
  Matrix4 world_from_camera;
  for (int i = 0; i < 3; ++i) {
    world_from_camera.at(i, 0) = right[i];
    world_from_camera.at(i, 1) = new_up[i];
    world_from_camera.at(i, 2) = dir[i];
    world_from_camera.at(i, 3) = eye[i];
  }
  return invert(world_from_camera, out);
}

Matrix4 from_pbrt_columns(const std::array<double, 16>& v) {
  Matrix4 r;
  r.m = v;
  return transpose(r);
}

}  // namespace pbrtc
