// The plot: its size, its axes' decades, and curve pixels where the data says.
#include "tools/accuracy/error_plot.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "test_support.h"

namespace {

accuracy::SweepRow row(const std::string& config, int spp, double seconds, double error) {
  accuracy::SweepRow r;
  r.scene = "tiny";
  r.config = config;
  r.spp = spp;
  r.seconds = seconds;
  r.errors.relmse = error * error;
  return r;
}

// The 8-bit value a PNG viewer sees for a linear pixel value.
int seen(const rt::ImageRgb& im, int x, int y, int c) {
  return rt::to_srgb8(im.rgb[3 * (size_t(y) * size_t(im.width()) + size_t(x)) + size_t(c)]);
}

bool is_colour(const rt::ImageRgb& im, int x, int y, accuracy::Colour col) {
  return std::abs(seen(im, x, y, 0) - int(std::lround(col.r * 255))) <= 1 &&
         std::abs(seen(im, x, y, 1) - int(std::lround(col.g * 255))) <= 1 &&
         std::abs(seen(im, x, y, 2) - int(std::lround(col.b * 255))) <= 1;
}

const std::vector<accuracy::SweepRow> kRows = {
    row("halton", 1, 0.05, 0.2), row("halton", 2, 0.1, 0.12), row("halton", 4, 0.2, 0.06),
    row("halton", 8, 0.4, 0.03), row("random", 1, 0.05, 0.3), row("random", 2, 0.1, 0.21),
    row("random", 4, 0.2, 0.15), row("random", 8, 0.4, 0.1)};

TEST(ErrorPlot, FrameSpansWholeDecadesAroundTheData) {
  accuracy::PlotFrame f = accuracy::plot_frame(kRows);
  EXPECT_EQ(f.x_decade_min, -2);  // 0.05 s
  EXPECT_EQ(f.x_decade_max, 0);   // 0.4 s
  EXPECT_EQ(f.y_decade_min, -2);  // 0.03
  EXPECT_EQ(f.y_decade_max, 0);   // 0.3
  EXPECT_NEAR(f.px(0.01), f.left, 1e-9);
  EXPECT_NEAR(f.px(1), f.right, 1e-9);
  EXPECT_NEAR(f.px(0.1), (f.left + f.right) / 2.0, 1e-9);
  EXPECT_NEAR(f.py(1), f.top, 1e-9);
  EXPECT_NEAR(f.py(0.01), f.bottom, 1e-9);
}

TEST(ErrorPlot, CurvesPassThroughTheirPointsInTheirColours) {
  rt::ImageRgb im = accuracy::plot_error_curves(kRows, "tiny");
  accuracy::PlotFrame f = accuracy::plot_frame(kRows);
  ASSERT_EQ(im.width(), f.width);
  ASSERT_EQ(im.height(), f.height);
  // Each configuration's markers and the middles of its segments.
  for (size_t c = 0; c < 2; ++c) {
    accuracy::Colour col = accuracy::curve_colour(c);
    for (size_t i = 4 * c; i < 4 * c + 4; ++i) {
      double x = f.px(kRows[i].seconds), y = f.py(std::sqrt(kRows[i].errors.relmse));
      EXPECT_TRUE(is_colour(im, int(x), int(y), col)) << kRows[i].config << " " << i;
      if (i + 1 < 4 * c + 4) {
        double x2 = f.px(kRows[i + 1].seconds), y2 = f.py(std::sqrt(kRows[i + 1].errors.relmse));
        int mx = int(std::lround((x + x2) / 2)), my = int(std::lround((y + y2) / 2));
        EXPECT_TRUE(is_colour(im, mx, my, col)) << "segment " << i << " at " << mx << "," << my;
      }
    }
  }
  // Background in an empty part of the plot (far above both curves at the right).
  EXPECT_TRUE(is_colour(im, int(f.px(0.6)), int(f.py(0.7)), {1, 1, 1}));
  // The frame's left edge is black.
  EXPECT_TRUE(is_colour(im, f.left, (f.top + f.bottom) / 2, {0, 0, 0}));
}

TEST(ErrorPlot, WritesAPngOfThatSize) {
  std::string path = testing_support::scratch_dir("ErrorPlotPng") + "/plot.png";
  std::string error;
  ASSERT_TRUE(rt::write_png(path, accuracy::plot_error_curves(kRows, "tiny"), &error)) << error;
  std::ifstream in(path, std::ios::binary);
  unsigned char h[24] = {};
  in.read(reinterpret_cast<char*>(h), 24);
  ASSERT_TRUE(in);
  EXPECT_EQ(h[1], 'P');
  EXPECT_EQ(h[2], 'N');
  EXPECT_EQ(h[3], 'G');
  // IHDR: big-endian width and height at bytes 16 and 20.
  EXPECT_EQ((h[16] << 24) | (h[17] << 16) | (h[18] << 8) | h[19], 960);
  EXPECT_EQ((h[20] << 24) | (h[21] << 16) | (h[22] << 8) | h[23], 600);
}

TEST(ErrorPlot, NothingPlottableStillDrawsAxes) {
  rt::ImageRgb im = accuracy::plot_error_curves({row("a", 1, 0, 0)}, "empty");
  accuracy::PlotFrame f;
  ASSERT_EQ(im.width(), f.width);
  EXPECT_TRUE(is_colour(im, f.left, (f.top + f.bottom) / 2, {0, 0, 0}));
}

}  // namespace
