// runtime/core/transform.cpp — see transform.h.
#include "runtime/core/transform.h"

#include <cmath>

namespace rt {

bool Matrix4::is_identity() const {
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (m[i][j] != (i == j ? 1.f : 0.f)) return false;
  return true;
}

bool Matrix4::operator==(const Matrix4& o) const {
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (m[i][j] != o.m[i][j]) return false;
  return true;
}

Matrix4 mul(const Matrix4& a, const Matrix4& b) {
  Matrix4 r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += double(a.m[i][k]) * b.m[k][j];
      r.m[i][j] = float(s);
    }
  return r;
}

Matrix4 transpose(const Matrix4& a) {
  Matrix4 r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r.m[i][j] = a.m[j][i];
  return r;
}

namespace {

// Gauss-Jordan elimination with partial pivoting in double precision.
bool invert(const double in[4][4], double out[4][4]) {
  double w[4][8];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      w[i][j] = in[i][j];
      w[i][j + 4] = i == j ? 1 : 0;
    }
  for (int c = 0; c < 4; ++c) {
    int piv = c;
    for (int r = c + 1; r < 4; ++r)
      if (std::fabs(w[r][c]) > std::fabs(w[piv][c])) piv = r;
    if (w[piv][c] == 0) return false;
    if (piv != c)
      for (int j = 0; j < 8; ++j) std::swap(w[piv][j], w[c][j]);
    double inv = 1 / w[c][c];
    for (int j = 0; j < 8; ++j) w[c][j] *= inv;
    for (int r = 0; r < 4; ++r) {
      if (r == c || w[r][c] == 0) continue;
      double f = w[r][c];
      for (int j = 0; j < 8; ++j) w[r][j] -= f * w[c][j];
    }
  }
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) out[i][j] = w[i][j + 4];
  return true;
}

}  // namespace

bool invert_doubles(const double* m, double* out) {
  double in[4][4], inv[4][4];
  for (int i = 0; i < 16; ++i) in[i / 4][i % 4] = m[i];
  if (!invert(in, inv)) return false;
  for (int i = 0; i < 16; ++i) out[i] = inv[i / 4][i % 4];
  return true;
}

bool inverse(const Matrix4& a, Matrix4* out) {
  double in[4][4], inv[4][4];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) in[i][j] = a.m[i][j];
  if (!invert(in, inv)) return false;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) out->m[i][j] = float(inv[i][j]);
  return true;
}

Transform::Transform(const Matrix4& m) : m_(m) {
  invertible_ = rt::inverse(m, &inv_);
  if (!invertible_) inv_ = Matrix4{{{0}}};
}

Transform Transform::from_doubles(const double* v) {
  // Invert in double before rounding, so the pair stays as consistent as the
  // archive's precision allows.
  double in[4][4], inv[4][4];
  Matrix4 m;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m.m[i][j] = float(in[i][j] = v[i * 4 + j]);
  Transform t;
  t.m_ = m;
  if (!invert(in, inv)) {
    t.inv_ = Matrix4{{{0}}};
    t.invertible_ = false;
    return t;
  }
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) t.inv_.m[i][j] = float(inv[i][j]);
  return t;
}

bool Transform::is_projective() const {
  return m_.m[3][0] != 0 || m_.m[3][1] != 0 || m_.m[3][2] != 0 || m_.m[3][3] != 1;
}

bool Transform::swaps_handedness() const {
  const auto& m = m_.m;
  double det = double(m[0][0]) * (double(m[1][1]) * m[2][2] - double(m[1][2]) * m[2][1]) -
               double(m[0][1]) * (double(m[1][0]) * m[2][2] - double(m[1][2]) * m[2][0]) +
               double(m[0][2]) * (double(m[1][0]) * m[2][1] - double(m[1][1]) * m[2][0]);
  return det < 0;
}

bool Transform::has_scale() const {
  auto len2 = [&](Vec3 v) { return length_squared(vector(v)); };
  auto not_one = [](float x) { return x < .999f || x > 1.001f; };
  return not_one(len2({1, 0, 0})) || not_one(len2({0, 1, 0})) || not_one(len2({0, 0, 1}));
}

Bounds3 Transform::bounds(const Bounds3& b) const {
  Bounds3 r;
  if (b.empty()) return r;
  for (int c = 0; c < 8; ++c)
    r.extend(point({c & 1 ? b.hi.x : b.lo.x, c & 2 ? b.hi.y : b.lo.y, c & 4 ? b.hi.z : b.lo.z}));
  return r;
}

Transform operator*(const Transform& a, const Transform& b) {
  Transform t(mul(a.m_, b.m_), mul(b.inv_, a.inv_));
  t.invertible_ = a.invertible_ && b.invertible_;
  return t;
}

Transform translate(Vec3 d) {
  Matrix4 m, inv;
  m.m[0][3] = d.x;
  m.m[1][3] = d.y;
  m.m[2][3] = d.z;
  inv.m[0][3] = -d.x;
  inv.m[1][3] = -d.y;
  inv.m[2][3] = -d.z;
  return Transform(m, inv);
}

Transform scale(float x, float y, float z) {
  Matrix4 m, inv;
  m.m[0][0] = x;
  m.m[1][1] = y;
  m.m[2][2] = z;
  inv.m[0][0] = 1 / x;
  inv.m[1][1] = 1 / y;
  inv.m[2][2] = 1 / z;
  return Transform(m, inv);
}

Transform perspective(float fov, float n, float f) {
  Matrix4 p;
  p.m[2][2] = f / (f - n);
  p.m[2][3] = -f * n / (f - n);
  p.m[3][2] = 1;
  p.m[3][3] = 0;
  float inv_tan = 1 / std::tan(radians(fov) / 2);
  return scale(inv_tan, inv_tan, 1) * Transform(p);
}

}  // namespace rt
