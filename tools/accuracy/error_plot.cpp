#include "tools/accuracy/error_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace accuracy {

namespace {

const Colour kWhite = {1, 1, 1}, kBlack = {0, 0, 0}, kGrid = {0.87f, 0.87f, 0.87f},
             kGuide = {0.55f, 0.55f, 0.55f};

// The ten-colour "category10" palette (D3 / matplotlib), as sRGB.
const Colour kPalette[] = {{0.122f, 0.467f, 0.706f}, {1.000f, 0.498f, 0.055f},
                           {0.173f, 0.627f, 0.173f}, {0.839f, 0.153f, 0.157f},
                           {0.580f, 0.404f, 0.741f}, {0.549f, 0.337f, 0.294f},
                           {0.890f, 0.467f, 0.761f}, {0.498f, 0.498f, 0.498f},
                           {0.737f, 0.741f, 0.133f}, {0.090f, 0.745f, 0.812f}};

double error_of(const SweepRow& r) {
  return std::sqrt(std::max(r.errors.relmse, 0.0));
}
bool plottable(const SweepRow& r) {
  return r.seconds > 0 && error_of(r) > 0;
}

// 10^k as a short label: plain between 0.001 and 1000, else "1e-4".
std::string decade_label(int k) {
  static const char* kPlain[] = {"0.001", "0.01", "0.1", "1", "10", "100", "1000"};
  if (k >= -3 && k <= 3) return kPlain[k + 3];
  return "1e" + std::to_string(k);
}

}  // namespace

double PlotFrame::px(double seconds) const {
  double t = (std::log10(seconds) - x_decade_min) / double(x_decade_max - x_decade_min);
  return left + t * (right - left);
}

double PlotFrame::py(double error) const {
  double t = (std::log10(error) - y_decade_min) / double(y_decade_max - y_decade_min);
  return bottom - t * (bottom - top);
}

PlotFrame plot_frame(const std::vector<SweepRow>& rows) {
  PlotFrame f;
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const SweepRow& r : rows) {
    if (!plottable(r)) continue;
    x0 = std::min(x0, r.seconds), x1 = std::max(x1, r.seconds);
    y0 = std::min(y0, error_of(r)), y1 = std::max(y1, error_of(r));
  }
  if (!(x0 <= x1)) return f;
  // Whole decades; clamped so absurd values cannot make thousands of ticks.
  auto lo = [](double v) { return std::clamp(int(std::floor(std::log10(v))), -12, 12); };
  auto hi = [](double v) { return std::clamp(int(std::ceil(std::log10(v))), -12, 12); };
  f.x_decade_min = lo(x0), f.x_decade_max = std::max(hi(x1), f.x_decade_min + 1);
  f.y_decade_min = lo(y0), f.y_decade_max = std::max(hi(y1), f.y_decade_min + 1);
  return f;
}

Colour curve_colour(size_t i) {
  return kPalette[i % (sizeof kPalette / sizeof kPalette[0])];
}

rt::ImageRgb plot_error_curves(const std::vector<SweepRow>& rows, const std::string& title) {
  const PlotFrame f = plot_frame(rows);
  Canvas c(f.width, f.height, kWhite);
  const int th = Canvas::text_height(2);

  // Decade grid, minor ticks (2..9) and labels on both axes.
  for (int k = f.x_decade_min; k <= f.x_decade_max; ++k) {
    int x = int(std::lround(f.px(std::pow(10.0, k))));
    if (k > f.x_decade_min && k < f.x_decade_max) c.line(x, f.top, x, f.bottom, kGrid);
    c.line(x, f.bottom, x, f.bottom + 8, kBlack, 2);
    std::string label = decade_label(k);
    c.text(x - Canvas::text_width(label, 2) / 2, f.bottom + 14, label, kBlack, 2);
    for (int m = 2; m <= 9 && k < f.x_decade_max; ++m) {
      int xm = int(std::lround(f.px(m * std::pow(10.0, k))));
      c.line(xm, f.bottom, xm, f.bottom + 4, kBlack);
    }
  }
  for (int k = f.y_decade_min; k <= f.y_decade_max; ++k) {
    int y = int(std::lround(f.py(std::pow(10.0, k))));
    if (k > f.y_decade_min && k < f.y_decade_max) c.line(f.left, y, f.right, y, kGrid);
    c.line(f.left - 8, y, f.left, y, kBlack, 2);
    std::string label = decade_label(k);
    c.text(f.left - 14 - Canvas::text_width(label, 2), y - th / 2, label, kBlack, 2);
    for (int m = 2; m <= 9 && k < f.y_decade_max; ++m) {
      int ym = int(std::lround(f.py(m * std::pow(10.0, k))));
      c.line(f.left - 4, ym, f.left, ym, kBlack);
    }
  }
  // Dotted guides at the error targets the README's table reads off.
  for (double target : {0.05, 0.02, 0.01}) {
    double y = f.py(target);
    if (y <= f.top || y >= f.bottom) continue;
    for (int x = f.left; x < f.right; x += 6) c.line(x, y, x + 2, y, kGuide);
    char label[16];
    std::snprintf(label, sizeof label, "%g%%", target * 100);
    c.text(f.right - 4 - Canvas::text_width(label), int(y) - Canvas::text_height() - 2, label,
           kGuide);
  }

  // The curves, in the order configurations first appear.
  std::vector<std::string> configs;
  for (const SweepRow& r : rows)
    if (std::find(configs.begin(), configs.end(), r.config) == configs.end())
      configs.push_back(r.config);
  for (size_t i = 0; i < configs.size(); ++i) {
    Colour col = curve_colour(i);
    const SweepRow* prev = nullptr;
    for (const SweepRow& r : rows) {
      if (r.config != configs[i] || !plottable(r)) continue;
      double x = f.px(r.seconds), y = f.py(error_of(r));
      if (prev) c.line(f.px(prev->seconds), f.py(error_of(*prev)), x, y, col, 2);
      c.fill_rect(int(x) - 3, int(y) - 3, int(x) + 3, int(y) + 3, col);
      prev = &r;
    }
    // Legend: a swatch and the name, shrunk to the small font when long.
    int ly = f.top + 4 + int(i) * (th + 10);
    c.fill_rect(f.right + 24, ly + 2, f.right + 44, ly + th - 3, col);
    int scale = Canvas::text_width(configs[i], 2) <= f.width - f.right - 60 ? 2 : 1;
    c.text(f.right + 52, ly + (th - Canvas::text_height(scale)) / 2, configs[i], kBlack, scale);
  }

  // Frame and titles last, so curves never hide them.
  c.line(f.left, f.top, f.right, f.top, kBlack, 2);
  c.line(f.left, f.bottom, f.right, f.bottom, kBlack, 2);
  c.line(f.left, f.top, f.left, f.bottom, kBlack, 2);
  c.line(f.right, f.top, f.right, f.bottom, kBlack, 2);
  c.text(f.left, 8, title, kBlack, 2);
  std::string xlabel = "wall seconds per render (log)";
  c.text((f.left + f.right - Canvas::text_width(xlabel, 2)) / 2, f.bottom + 44, xlabel, kBlack, 2);
  std::string ylabel = "relative error sqrt(relmse) (log)";
  c.text(12, f.top - 6 - th, ylabel, kBlack, 2);
  return c.image();
}

}  // namespace accuracy
