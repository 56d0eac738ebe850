// runtime/film/film_tile.cpp — pbrt-v3's FilmTile: filter-weighted sample splatting.
#include <algorithm>
#include <cmath>

#include "runtime/film/film.h"

namespace rt {
namespace {

// ceil(v) and floor(v) + 1 clamped to [lo, hi], for finite v: v is clamped into int range
// first, then rounded with an integer conversion (SSE2 has no float ceil or floor; the
// emulation GCC emits costs a dozen instructions a call and this runs per sample).
int ceil_in(float v, int lo, int hi) {
  v = std::max(std::min(v, float(hi)), float(lo));
  int i = int(v);
  return i + (float(i) < v);
}
int floor_plus_one_in(float v, int lo, int hi) {
  v = std::max(std::min(v, float(hi)), float(lo) - 1);
  int i = int(v);
  return std::min(i - (float(i) > v) + 1, hi);
}

}  // namespace

FilmTile::FilmTile(const Bounds2i& pixel_bounds, Vec2 radius, const float* table,
                   float max_luminance)
    : pixel_bounds_(pixel_bounds),
      radius_(radius),
      inv_radius_{1 / radius.x, 1 / radius.y},
      table_(table),
      max_luminance_(max_luminance) {
  if (pixel_bounds_.empty()) pixel_bounds_.max = pixel_bounds_.min;  // no pixels, no negative sizes
  for (auto& h : pixels_) h.resize(size_t(pixel_bounds_.area()));
}

FilmPixelSum FilmTile::sum(Point2i p) const {
  const size_t i = size_t(p.y - pixel_bounds_.min.y) * size_t(pixel_bounds_.width()) +
                   size_t(p.x - pixel_bounds_.min.x);
  FilmPixelSum s;
  for (const auto& h : pixels_) {
    for (int c = 0; c < 3; ++c) s.rgb[c] += h[i].rgb[c];
    s.weight += h[i].weight;
  }
  return s;
}

// Not vectorised: a filter covers one to a few pixels a row, fewer than GCC's vector loop's
// setup pays for (pbrt-v3's default box filter covers one). Clang does not know the attribute.
#if defined(__GNUC__) && !defined(__clang__)
__attribute__((optimize("no-tree-vectorize")))
#endif
void FilmTile::add_sample(Vec2 p_film, Rgb L, float sample_weight, int half) {
  float lum = L.luminance();
  if (lum > max_luminance_) L *= max_luminance_ / lum;
  // Pixel (x, y) has its centre at (x + 0.5, y + 0.5): work in discrete
  // coordinates, where centres are integers.
  float dx = p_film.x - 0.5f, dy = p_film.y - 0.5f;
  if (!std::isfinite(dx) || !std::isfinite(dy)) return;
  int x0 = ceil_in(dx - radius_.x, pixel_bounds_.min.x, pixel_bounds_.max.x);
  int x1 = floor_plus_one_in(dx + radius_.x, pixel_bounds_.min.x, pixel_bounds_.max.x);
  int y0 = ceil_in(dy - radius_.y, pixel_bounds_.min.y, pixel_bounds_.max.y);
  int y1 = floor_plus_one_in(dy + radius_.y, pixel_bounds_.min.y, pixel_bounds_.max.y);
  if (x0 >= x1 || y0 >= y1) return;

  // Table rows and columns of the covered pixels. The filter reaches at most
  // ceil(2 radius) + 1 pixels per axis; wider filters than kMaxReach are
  // handled by recomputing per pixel (not worth a heap allocation).
  constexpr int kMaxReach = 64;
  int ifx[kMaxReach], ify[kMaxReach];
  auto table_index = [](float f) {
    // f >= 0, so the conversion is its floor; NaN (never from finite input) falls on the
    // last entry.
    return f < float(kTableSize - 1) ? int(f) : kTableSize - 1;
  };
  auto column = [&](int x) {
    return table_index(std::fabs((x - dx) * inv_radius_.x * kTableSize));
  };
  auto row = [&](int y) { return table_index(std::fabs((y - dy) * inv_radius_.y * kTableSize)); };
  bool cached = x1 - x0 <= kMaxReach && y1 - y0 <= kMaxReach;
  if (cached) {
    for (int x = x0; x < x1; ++x) ifx[x - x0] = column(x);
    for (int y = y0; y < y1; ++y) ify[y - y0] = row(y);
  }

  double lr = L.r, lg = L.g, lb = L.b, sw = sample_weight;
  size_t stride = size_t(pixel_bounds_.width());
  for (int y = y0; y < y1; ++y) {
    int ty = cached ? ify[y - y0] : row(y);
    FilmPixelSum* line = &pixels_[half & 1][size_t(y - pixel_bounds_.min.y) * stride];
    for (int x = x0; x < x1; ++x) {
      int tx = cached ? ifx[x - x0] : column(x);
      float fw = table_[ty * kTableSize + tx];
      FilmPixelSum& px = line[x - pixel_bounds_.min.x];
      double w = sw * fw;
      px.rgb[0] += lr * w;
      px.rgb[1] += lg * w;
      px.rgb[2] += lb * w;
      px.weight += fw;
    }
  }
}

}  // namespace rt
