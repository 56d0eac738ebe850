// compiler/transform.h — 4x4 matrices for the scene's transform stack.
//
// The compiler composes transforms in double precision, so a scene far from
// the origin loses nothing before the archive stores float32 (the renderer
// works in float). Matrices are row-major and act on column vectors, as in
// pbrt: p' = M p. pbrt-v3's Transform/ConcatTransform numbers are column-major
// and are transposed on entry (see from_pbrt_columns).
#pragma once

#include <array>
#include <cstddef>

namespace pbrtc {

struct Matrix4 {
  std::array<double, 16> m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  double at(int r, int c) const { return m[std::size_t(r * 4 + c)]; }
  double& at(int r, int c) { return m[std::size_t(r * 4 + c)]; }
  bool operator==(const Matrix4& o) const { return m == o.m; }
  bool operator!=(const Matrix4& o) const { return m != o.m; }
};

Matrix4 mul(const Matrix4& a, const Matrix4& b);
Matrix4 transpose(const Matrix4& a);
// False if the matrix is singular (within a relative tolerance).
bool invert(const Matrix4& a, Matrix4* inv);
bool is_identity(const Matrix4& a);
// True if the upper 3x3 has a negative determinant (mirrors orientation).
bool swaps_handedness(const Matrix4& a);
// True if the bottom row is not (0 0 0 1).
bool is_projective(const Matrix4& a);

Matrix4 translate(double x, double y, double z);
Matrix4 scale(double x, double y, double z);
// Rotation by angle (degrees) around the axis (normalized here); the axis must
// be non-zero.
Matrix4 rotate(double angle_degrees, double x, double y, double z);
// pbrt's LookAt: camera-from-world. False if degenerate (eye == look, or up
// parallel to the view direction).
bool look_at(const double eye[3], const double look[3], const double up[3], Matrix4* out);
// pbrt-v3 scene files list matrices column by column.
Matrix4 from_pbrt_columns(const std::array<double, 16>& v);

}  // namespace pbrtc
