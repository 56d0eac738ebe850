// runtime/geometry/watertight4.cpp — see watertight4.h. Line for line watertight_triangle's
// arithmetic (watertight.cpp), each operation in the same order.
#include "runtime/geometry/watertight4.h"

#include <xmmintrin.h>

#include "runtime/core/math.h"
#include "runtime/geometry/watertight.h"

namespace rt {

WatertightRay watertight_ray(Vec3 o, Vec3 d) {
  WatertightRay r;
  r.o = o;
  r.d = d;
  r.kz = max_dimension(abs(d));
  r.kx = (r.kz + 1) % 3;
  r.ky = (r.kx + 1) % 3;
  const Vec3 pd = permute(d, r.kx, r.ky, r.kz);
  r.po[0] = o[r.kx];
  r.po[1] = o[r.ky];
  r.po[2] = o[r.kz];
  r.valid = pd.z != 0;
  r.sx = -pd.x / pd.z;
  r.sy = -pd.y / pd.z;
  r.sz = 1 / pd.z;
  return r;
}

void TriangleLanes::set(int lane, Vec3 p0, Vec3 p1, Vec3 p2) {
  const Vec3 v[3] = {p0, p1, p2};
  for (int i = 0; i < 3; ++i)
    for (int a = 0; a < 3; ++a) p[i][a][lane] = v[i][a];
}

namespace {

__m128 abs4(__m128 a) {
  return _mm_andnot_ps(_mm_set1_ps(-0.f), a);
}
__m128 max3(__m128 a, __m128 b, __m128 c) {
  return _mm_max_ps(_mm_max_ps(a, b), c);
}

}  // namespace

int watertight_triangles4(const WatertightRay& r, const TriangleLanes& tri, int lanes, float tmax,
                          float t[4], float b1[4], float b2[4]) {
  if (!r.valid || !lanes) return 0;
  // Each vertex in ray space, sheared: x, y, and z (scaled below).
  const __m128 ox = _mm_set1_ps(r.po[0]), oy = _mm_set1_ps(r.po[1]), oz = _mm_set1_ps(r.po[2]);
  const __m128 sx = _mm_set1_ps(r.sx), sy = _mm_set1_ps(r.sy), sz = _mm_set1_ps(r.sz);
  __m128 x[3], y[3], z[3];
  for (int v = 0; v < 3; ++v) {
    z[v] = _mm_sub_ps(_mm_load_ps(tri.p[v][r.kz]), oz);
    x[v] = _mm_add_ps(_mm_sub_ps(_mm_load_ps(tri.p[v][r.kx]), ox), _mm_mul_ps(sx, z[v]));
    y[v] = _mm_add_ps(_mm_sub_ps(_mm_load_ps(tri.p[v][r.ky]), oy), _mm_mul_ps(sy, z[v]));
  }
  const __m128 e0 = _mm_sub_ps(_mm_mul_ps(x[1], y[2]), _mm_mul_ps(y[1], x[2]));
  const __m128 e1 = _mm_sub_ps(_mm_mul_ps(x[2], y[0]), _mm_mul_ps(y[2], x[0]));
  const __m128 e2 = _mm_sub_ps(_mm_mul_ps(x[0], y[1]), _mm_mul_ps(y[0], x[1]));
  const __m128 zero = _mm_setzero_ps();
  const int on_edge =
      _mm_movemask_ps(_mm_or_ps(_mm_or_ps(_mm_cmpeq_ps(e0, zero), _mm_cmpeq_ps(e1, zero)),
                                _mm_cmpeq_ps(e2, zero))) &
      lanes;
  const __m128 neg =
      _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(e0, zero), _mm_cmplt_ps(e1, zero)), _mm_cmplt_ps(e2, zero));
  const __m128 pos =
      _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(e0, zero), _mm_cmpgt_ps(e1, zero)), _mm_cmpgt_ps(e2, zero));
  const __m128 det = _mm_add_ps(_mm_add_ps(e0, e1), e2);
  for (int v = 0; v < 3; ++v) z[v] = _mm_mul_ps(z[v], sz);
  const __m128 t_scaled =
      _mm_add_ps(_mm_add_ps(_mm_mul_ps(e0, z[0]), _mm_mul_ps(e1, z[1])), _mm_mul_ps(e2, z[2]));
  const __m128 tmax_det = _mm_mul_ps(_mm_set1_ps(tmax), det);
  // Hit sides agree with det's sign, and t_scaled lies between 0 and tmax det (NaNs fail here
  // where the scalar test fails them later).
  const __m128 in_neg =
      _mm_and_ps(_mm_and_ps(_mm_cmplt_ps(det, zero), _mm_cmplt_ps(t_scaled, zero)),
                 _mm_cmpge_ps(t_scaled, tmax_det));
  const __m128 in_pos =
      _mm_and_ps(_mm_and_ps(_mm_cmpgt_ps(det, zero), _mm_cmpgt_ps(t_scaled, zero)),
                 _mm_cmple_ps(t_scaled, tmax_det));
  __m128 ok = _mm_andnot_ps(_mm_and_ps(neg, pos), _mm_or_ps(in_neg, in_pos));
  const __m128 inv_det = _mm_div_ps(_mm_set1_ps(1), det);
  const __m128 t_hit = _mm_mul_ps(t_scaled, inv_det);
  // t must exceed its own rounding error (book 3.9.6).
  const __m128 max_zt = max3(abs4(z[0]), abs4(z[1]), abs4(z[2]));
  const __m128 max_xt = max3(abs4(x[0]), abs4(x[1]), abs4(x[2]));
  const __m128 max_yt = max3(abs4(y[0]), abs4(y[1]), abs4(y[2]));
  const __m128 g2 = _mm_set1_ps(gamma_bound(2)), g3 = _mm_set1_ps(gamma_bound(3)),
               g5 = _mm_set1_ps(gamma_bound(5));
  const __m128 delta_z = _mm_mul_ps(g3, max_zt);
  const __m128 delta_x = _mm_mul_ps(g5, _mm_add_ps(max_xt, max_zt));
  const __m128 delta_y = _mm_mul_ps(g5, _mm_add_ps(max_yt, max_zt));
  const __m128 delta_e =
      _mm_mul_ps(_mm_set1_ps(2), _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_mul_ps(g2, max_xt), max_yt),
                                                       _mm_mul_ps(delta_y, max_xt)),
                                            _mm_mul_ps(delta_x, max_yt)));
  const __m128 max_e = max3(abs4(e0), abs4(e1), abs4(e2));
  const __m128 delta_t = _mm_mul_ps(
      _mm_mul_ps(_mm_set1_ps(3), _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_mul_ps(g3, max_e), max_zt),
                                                       _mm_mul_ps(delta_e, max_zt)),
                                            _mm_mul_ps(delta_z, max_e))),
      abs4(inv_det));
  ok = _mm_and_ps(ok, _mm_cmpgt_ps(t_hit, delta_t));
  _mm_storeu_ps(t, t_hit);
  _mm_storeu_ps(b1, _mm_mul_ps(e1, inv_det));
  _mm_storeu_ps(b2, _mm_mul_ps(e2, inv_det));
  int hits = _mm_movemask_ps(ok) & lanes & ~on_edge;
  for (int k = 0; k < 4; ++k)
    if (on_edge >> k & 1 && watertight_triangle(r.o, r.d, tmax, tri.vertex(0, k), tri.vertex(1, k),
                                                tri.vertex(2, k), &t[k], &b1[k], &b2[k]))
      hits |= 1 << k;
  return hits;
}

}  // namespace rt
