// runtime/material/catmull_rom.h — Catmull-Rom splines over non-uniform nodes, for tabulated
// functions (the fourier BSDF, the BSSRDF profile; book 3rd ed., 8.6.1 and 15.5).
//
// Tangents come from finite differences of the neighbouring nodes, one-sided at the ends.
// catmull_rom_weights() gives the four node weights at x; sample_catmull_rom_2d() inverts
// the spline's integral over the second dimension of a 2D table (the first interpolated at
// alpha) given that integral's running sums at the nodes; invert_catmull_rom() finds where a
// monotone spline reaches a value. Plain functions of arrays: no allocation, thread-safe.
#pragma once

namespace rt {

// Largest i in [0, size - 2] with pred(i) true, for a predicate that is true then false
// over [0, size); 0 if none (book section A.2's FindInterval).
template <class Pred>
int find_interval(int size, const Pred& pred) {
  // Bisection for the first index where pred is false (size if none).
  int lo = 0, hi = size;
  while (lo < hi) {
    int mid = lo + (hi - lo) / 2;
    if (pred(mid))
      lo = mid + 1;
    else
      hi = mid;
  }
  int i = lo - 1;
  return i < 0 ? 0 : (i > size - 2 ? size - 2 : i);
}

// The weights of nodes offset .. offset+3 for the spline through size sorted nodes at x.
// Weights of nodes outside the table are 0 (offset may then be -1 or reach size - 3 + 1).
// False when x lies outside [nodes[0], nodes[size - 1]].
bool catmull_rom_weights(int size, const float* nodes, float x, int* offset, float weights[4]);

// Samples x in the second dimension of values[size1][size2] (rows: nodes1, columns: nodes2),
// the row interpolated at alpha, proportionally to the spline; cdf[size1][size2] holds each
// row's integral from nodes2[0] to each node. *fval: the interpolated function at the sample;
// *pdf: it over the row's whole integral. Returns 0 with *pdf = 0 when alpha is out of range
// or the row integrates to 0. fval may be null.
float sample_catmull_rom_2d(int size1, int size2, const float* nodes1, const float* nodes2,
                            const float* values, const float* cdf, float alpha, float u,
                            float* fval, float* pdf);

// The x at which the spline through increasing values (at nodes x) equals u, clamped to the
// ends (the book's InvertCatmullRom).
float invert_catmull_rom(int n, const float* x, const float* values, float u);

}  // namespace rt
