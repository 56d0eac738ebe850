// tools/accuracy/canvas.h — a tiny rasteriser for plots: pixels, thick lines,
// rectangles and 5x7 text, into an rt::ImageRgb for write_png.
//
// Colours are given in sRGB (what a PNG viewer shows); image() converts them
// to the linear values write_png expects, so a colour survives the round trip
// to within 8-bit rounding. Drawing outside the canvas is clipped, never an
// error. No antialiasing: plots are read, not admired.
#pragma once

#include <string>
#include <vector>

#include "runtime/film/image_io.h"

namespace accuracy {

struct Colour {
  float r = 0, g = 0, b = 0;  // sRGB in [0, 1]
  bool operator==(const Colour& o) const { return r == o.r && g == o.g && b == o.b; }
};

class Canvas {
 public:
  Canvas(int width, int height, Colour background);
  int width() const { return width_; }
  int height() const { return height_; }
  void set(int x, int y, Colour c);
  Colour get(int x, int y) const;  // the background outside the canvas
  // Inclusive corners, in any order.
  void fill_rect(int x0, int y0, int x1, int y1, Colour c);
  // A line `thickness` pixels wide between two real points.
  void line(double x0, double y0, double x1, double y1, Colour c, int thickness = 1);
  // Text with its top-left corner at (x, y), each font pixel scale x scale.
  void text(int x, int y, const std::string& s, Colour c, int scale = 1);
  static int text_width(const std::string& s, int scale = 1);
  static int text_height(int scale = 1);
  rt::ImageRgb image() const;

 private:
  int width_, height_;
  Colour background_;
  std::vector<Colour> pixels_;
};

}  // namespace accuracy
