// runtime/material/catmull_rom.cpp — see catmull_rom.h.
#include "runtime/material/catmull_rom.h"

#include <algorithm>
#include <cmath>

namespace rt {

namespace {

// Solves F(t) = u on [0, 1] for an increasing F (eval gives F and its derivative f at t), from
// the guess t: Newton steps, bisecting whenever a step leaves the bracket that shrinks around
// the root. *f gets the derivative at the answer.
template <class Eval>
float newton_bisection(float t, float u, float* f, const Eval& eval) {
  float a = 0, b = 1, big_f = 0;
  for (int iteration = 0; iteration < 100; ++iteration) {
    if (!(t >= a && t <= b)) t = 0.5f * (a + b);
    eval(t, &big_f, f);
    if (std::fabs(big_f - u) < 1e-6f || b - a < 1e-6f) break;
    if (big_f - u < 0)
      a = t;
    else
      b = t;
    t -= (big_f - u) / *f;
  }
  return t;
}

}  // namespace

bool catmull_rom_weights(int size, const float* nodes, float x, int* offset, float weights[4]) {
  if (!(x >= nodes[0] && x <= nodes[size - 1])) return false;
  int idx = find_interval(size, [&](int i) { return nodes[i] <= x; });
  *offset = idx - 1;
  float x0 = nodes[idx], x1 = nodes[idx + 1];
  float t = (x - x0) / (x1 - x0), t2 = t * t, t3 = t2 * t;
  // Cubic Hermite basis: h00 f0 + h10 d0 + h01 f1 + h11 d1, with the tangents d0, d1
  // (scaled to the unit interval) written as differences of node values.
  float h10 = t3 - 2 * t2 + t, h11 = t3 - t2;
  weights[1] = 2 * t3 - 3 * t2 + 1;
  weights[2] = -2 * t3 + 3 * t2;
  if (idx > 0) {
    // d0 = (f1 - f_-1) (x1 - x0) / (x1 - x_-1)
    float w0 = h10 * (x1 - x0) / (x1 - nodes[idx - 1]);
    weights[0] = -w0;
    weights[2] += w0;
  } else {
    // At the first interval the tangent is one-sided: d0 = f1 - f0.
    weights[0] = 0;
    weights[1] -= h10;
    weights[2] += h10;
  }
  if (idx + 2 < size) {
    // d1 = (f2 - f0) (x1 - x0) / (x2 - x0)
    float w3 = h11 * (x1 - x0) / (nodes[idx + 2] - x0);
    weights[1] -= w3;
    weights[3] = w3;
  } else {
    weights[1] -= h11;
    weights[2] += h11;
    weights[3] = 0;
  }
  return true;
}

float sample_catmull_rom_2d(int size1, int size2, const float* nodes1, const float* nodes2,
                            const float* values, const float* cdf, float alpha, float u,
                            float* fval, float* pdf) {
  *pdf = 0;
  if (fval) *fval = 0;
  int offset;
  float w[4];
  if (!catmull_rom_weights(size1, nodes1, alpha, &offset, w)) return 0;
  // Row alpha of a table, at column idx.
  auto row = [&](const float* table, int idx) {
    float v = 0;
    for (int k = 0; k < 4; ++k)
      if (w[k] != 0) v += table[(offset + k) * size2 + idx] * w[k];
    return v;
  };
  float total = row(cdf, size2 - 1);
  if (!(total > 0)) return 0;
  u *= total;
  int idx = find_interval(size2, [&](int i) { return row(cdf, i) <= u; });
  float f0 = row(values, idx), f1 = row(values, idx + 1);
  float x0 = nodes2[idx], x1 = nodes2[idx + 1], width = x1 - x0;
  // Tangents on the unit interval of the segment, as the spline above has them.
  float d0 = idx > 0 ? width * (f1 - row(values, idx - 1)) / (x1 - nodes2[idx - 1]) : f1 - f0;
  float d1 =
      idx + 2 < size2 ? width * (row(values, idx + 2) - f0) / (nodes2[idx + 2] - x0) : f1 - f0;
  // The segment's integral in t is width times smaller than in x.
  u = (u - row(cdf, idx)) / width;
  // Start from the inverse of the linear interpolant's integral, then Newton steps on the
  // cubic's integral F(t) = u, falling back to bisection when a step leaves [a, b].
  float t =
      f0 != f1 ? (f0 - std::sqrt(std::max(0.f, f0 * f0 + 2 * u * (f1 - f0)))) / (f0 - f1) : u / f0;
  float small_f = 0;
  t = newton_bisection(t, u, &small_f, [&](float x, float* big, float* small) {
    *big = x * (f0 + x * (.5f * d0 + x * ((1.f / 3.f) * (-2 * d0 - d1) + f1 - f0 +
                                          x * (.25f * (d0 + d1) + .5f * (f0 - f1)))));
    *small = f0 + x * (d0 + x * (-2 * d0 - d1 + 3 * (f1 - f0) + x * (d0 + d1 + 2 * (f0 - f1))));
  });
  if (fval) *fval = small_f;
  *pdf = small_f / total;
  return x0 + width * t;
}

float invert_catmull_rom(int n, const float* x, const float* values, float u) {
  if (!(u > values[0])) return x[0];
  if (!(u < values[n - 1])) return x[n - 1];
  const int i = find_interval(n, [&](int k) { return values[k] <= u; });
  const float x0 = x[i], x1 = x[i + 1], width = x1 - x0, f0 = values[i], f1 = values[i + 1];
  const float d0 = i > 0 ? width * (f1 - values[i - 1]) / (x1 - x[i - 1]) : f1 - f0;
  const float d1 = i + 2 < n ? width * (values[i + 2] - f0) / (x[i + 2] - x0) : f1 - f0;
  // The Hermite cubic through the segment, solved for F(t) = u.
  float slope = 0;
  float t = newton_bisection(.5f, u, &slope, [&](float x, float* big, float* small) {
    float x2 = x * x, x3 = x2 * x;
    *big = (2 * x3 - 3 * x2 + 1) * f0 + (-2 * x3 + 3 * x2) * f1 + (x3 - 2 * x2 + x) * d0 +
           (x3 - x2) * d1;
    *small = (6 * x2 - 6 * x) * f0 + (-6 * x2 + 6 * x) * f1 + (3 * x2 - 4 * x + 1) * d0 +
             (3 * x2 - 2 * x) * d1;
  });
  return x0 + t * width;
}

}  // namespace rt
