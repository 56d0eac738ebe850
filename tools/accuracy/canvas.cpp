#include "tools/accuracy/canvas.h"

#include <algorithm>
#include <cmath>

#include "tools/accuracy/bitmap_font.h"

namespace accuracy {

namespace {

// The inverse of the sRGB transfer curve (IEC 61966-2-1).
float srgb_to_linear(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

}  // namespace

Canvas::Canvas(int width, int height, Colour background)
    : width_(std::max(width, 1)),
      height_(std::max(height, 1)),
      background_(background),
      pixels_(size_t(width_) * size_t(height_), background) {}

void Canvas::set(int x, int y, Colour c) {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
  pixels_[size_t(y) * size_t(width_) + size_t(x)] = c;
}

Colour Canvas::get(int x, int y) const {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return background_;
  return pixels_[size_t(y) * size_t(width_) + size_t(x)];
}

void Canvas::fill_rect(int x0, int y0, int x1, int y1, Colour c) {
  if (x0 > x1) std::swap(x0, x1);
  if (y0 > y1) std::swap(y0, y1);
  x0 = std::max(x0, 0);
  y0 = std::max(y0, 0);
  x1 = std::min(x1, width_ - 1);
  y1 = std::min(y1, height_ - 1);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) set(x, y, c);
}

void Canvas::line(double x0, double y0, double x1, double y1, Colour c, int thickness) {
  if (!std::isfinite(x0) || !std::isfinite(y0) || !std::isfinite(x1) || !std::isfinite(y1)) return;
  // Far-off endpoints are clipped to a margin around the canvas so the step
  // count stays bounded whatever the data.
  double lim = 4.0 * (width_ + height_);
  auto clip = [lim](double v) { return std::clamp(v, -lim, lim); };
  x0 = clip(x0), y0 = clip(y0), x1 = clip(x1), y1 = clip(y1);
  // One stamp of thickness^2 pixels per unit step along the longer axis.
  int steps = int(std::ceil(std::max(std::fabs(x1 - x0), std::fabs(y1 - y0)))) + 1;
  int lo = -(thickness - 1) / 2, hi = thickness / 2;
  for (int i = 0; i <= steps; ++i) {
    double t = steps == 0 ? 0 : double(i) / steps;
    int x = int(std::lround(x0 + t * (x1 - x0))), y = int(std::lround(y0 + t * (y1 - y0)));
    fill_rect(x + lo, y + lo, x + hi, y + hi, c);
  }
}

void Canvas::text(int x, int y, const std::string& s, Colour c, int scale) {
  for (size_t i = 0; i < s.size(); ++i) {
    int gx = x + int(i) * kGlyphAdvance * scale;
    for (int r = 0; r < kGlyphHeight; ++r) {
      uint8_t bits = glyph_row(s[i], r);
      for (int col = 0; col < kGlyphWidth; ++col)
        if (bits & (1u << (kGlyphWidth - 1 - col)))
          fill_rect(gx + col * scale, y + r * scale, gx + (col + 1) * scale - 1,
                    y + (r + 1) * scale - 1, c);
    }
  }
}

int Canvas::text_width(const std::string& s, int scale) {
  return s.empty() ? 0 : (int(s.size()) * kGlyphAdvance - 1) * scale;
}

int Canvas::text_height(int scale) {
  return kGlyphHeight * scale;
}

rt::ImageRgb Canvas::image() const {
  rt::ImageRgb out;
  out.data_window = out.display_window = {{0, 0}, {width_, height_}};
  out.rgb.resize(pixels_.size() * 3);
  for (size_t i = 0; i < pixels_.size(); ++i) {
    out.rgb[3 * i + 0] = srgb_to_linear(pixels_[i].r);
    out.rgb[3 * i + 1] = srgb_to_linear(pixels_[i].g);
    out.rgb[3 * i + 2] = srgb_to_linear(pixels_[i].b);
  }
  return out;
}

}  // namespace accuracy
