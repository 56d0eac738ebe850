// runtime/core/transform.h — affine/projective 4x4 transforms with their inverses.
//
// Row-major, acting on column vectors (p' = M p), like the archive's
// TransformRecord, but in float: the runtime picks world space as render
// space. Points carry conservative error bounds through a transform the way
// the pbrt book derives them (gamma(3) per row), so intersection code can
// offset ray origins past the rounding error and never self-intersect.
#pragma once

#include "runtime/core/vec.h"

namespace rt {

struct Matrix4 {
  float m[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
  bool is_identity() const;
  bool operator==(const Matrix4& o) const;
};
Matrix4 mul(const Matrix4& a, const Matrix4& b);
Matrix4 transpose(const Matrix4& a);
// Gauss-Jordan inverse with full pivoting in double precision; false if singular.
bool inverse(const Matrix4& a, Matrix4* out);
// The same for a row-major 4x4 of doubles (the archive's transforms).
bool invert_doubles(const double* m, double* out);

class Transform {
 public:
  Transform() = default;
  // m must be invertible; a singular m yields a zero inverse (callers that
  // can meet user data check invertible() first).
  explicit Transform(const Matrix4& m);
  Transform(const Matrix4& m, const Matrix4& inv) : m_(m), inv_(inv) {}
  // From the archive's double row-major 16 values.
  static Transform from_doubles(const double* v);

  const Matrix4& matrix() const { return m_; }
  const Matrix4& inverse_matrix() const { return inv_; }
  Transform inverse() const { return Transform(inv_, m_); }
  bool invertible() const { return invertible_; }
  bool is_identity() const { return m_.is_identity(); }
  // The bottom row is not (0 0 0 1).
  bool is_projective() const;
  // The upper 3x3 has a negative determinant (mirrors orientation).
  bool swaps_handedness() const;
  // The upper 3x3 is not a rotation (lengths change).
  bool has_scale() const;

  // Defined inline below: they run several times per ray hit (and per quadric test).
  Vec3 point(Vec3 p) const;
  // p transformed, and the absolute error bound of the result in *err.
  Vec3 point(Vec3 p, Vec3* err) const;
  // p carrying its own error p_err in, result and its bound out.
  Vec3 point(Vec3 p, Vec3 p_err, Vec3* err) const;
  Vec3 vector(Vec3 v) const;
  Vec3 vector(Vec3 v, Vec3* err) const;
  // Normals transform by the inverse transpose (not normalised).
  Vec3 normal(Vec3 n) const;
  Bounds3 bounds(const Bounds3& b) const;

  friend Transform operator*(const Transform& a, const Transform& b);

 private:
  Matrix4 m_, inv_;
  bool invertible_ = true;
};

inline Vec3 Transform::point(Vec3 p) const {
  const auto& m = m_.m;
  float x = m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3];
  float y = m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3];
  float z = m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3];
  float w = m[3][0] * p.x + m[3][1] * p.y + m[3][2] * p.z + m[3][3];
  return w == 1 ? Vec3{x, y, z} : Vec3{x, y, z} / w;
}

inline Vec3 Transform::vector(Vec3 v) const {
  const auto& m = m_.m;
  return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
          m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
          m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
}

inline Vec3 Transform::point(Vec3 p, Vec3* err) const {
  const auto& m = m_.m;
  Vec3 r = point(p);
  *err = gamma_bound(3) * Vec3{std::fabs(m[0][0] * p.x) + std::fabs(m[0][1] * p.y) +
                                   std::fabs(m[0][2] * p.z) + std::fabs(m[0][3]),
                               std::fabs(m[1][0] * p.x) + std::fabs(m[1][1] * p.y) +
                                   std::fabs(m[1][2] * p.z) + std::fabs(m[1][3]),
                               std::fabs(m[2][0] * p.x) + std::fabs(m[2][1] * p.y) +
                                   std::fabs(m[2][2] * p.z) + std::fabs(m[2][3])};
  return r;
}

inline Vec3 Transform::point(Vec3 p, Vec3 pe, Vec3* err) const {
  const auto& m = m_.m;
  Vec3 r = point(p);
  for (int i = 0; i < 3; ++i) {
    (*err)[i] = (gamma_bound(3) + 1) * (std::fabs(m[i][0]) * pe.x + std::fabs(m[i][1]) * pe.y +
                                        std::fabs(m[i][2]) * pe.z) +
                gamma_bound(3) * (std::fabs(m[i][0] * p.x) + std::fabs(m[i][1] * p.y) +
                                  std::fabs(m[i][2] * p.z) + std::fabs(m[i][3]));
  }
  return r;
}

inline Vec3 Transform::vector(Vec3 v, Vec3* err) const {
  const auto& m = m_.m;
  for (int i = 0; i < 3; ++i)
    (*err)[i] = gamma_bound(3) *
                (std::fabs(m[i][0] * v.x) + std::fabs(m[i][1] * v.y) + std::fabs(m[i][2] * v.z));
  return vector(v);
}

inline Vec3 Transform::normal(Vec3 n) const {
  const auto& i = inv_.m;
  return {i[0][0] * n.x + i[1][0] * n.y + i[2][0] * n.z,
          i[0][1] * n.x + i[1][1] * n.y + i[2][1] * n.z,
          i[0][2] * n.x + i[1][2] * n.y + i[2][2] * n.z};
}

Transform translate(Vec3 d);
Transform scale(float x, float y, float z);
// Perspective projection as pbrt-v3's camera uses it (fov in degrees).
Transform perspective(float fov_deg, float znear, float zfar);

}  // namespace rt
