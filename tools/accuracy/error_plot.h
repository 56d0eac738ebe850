// tools/accuracy/error_plot.h — the log-log plot of a sweep: relative error
// (sqrt(relmse), time_to_error.h) against seconds, one coloured curve with a
// marker per rung for each configuration, decade ticks and labels on both
// axes, dotted guides at 5%, 2% and 1%, and a legend right of the plot.
//
// The axes span whole decades around the data (at least one decade each).
// Rows with non-positive seconds or error (nothing to place on a log axis)
// are left out. PlotFrame is exposed so tests can find where a point lands.
#pragma once

#include <string>
#include <vector>

#include "runtime/film/image_io.h"
#include "tools/accuracy/canvas.h"
#include "tools/accuracy/sweep.h"

namespace accuracy {

struct PlotFrame {
  int width = 960, height = 600;
  int left = 100, top = 50, right = 690, bottom = 520;  // the plot rectangle, inclusive
  int x_decade_min = -2, x_decade_max = 1;              // log10 of the axis ends
  int y_decade_min = -3, y_decade_max = 0;
  double px(double seconds) const;  // pixel column of a time
  double py(double error) const;    // pixel row of an error
};

// The frame that fits rows (the default frame when none has a positive value).
PlotFrame plot_frame(const std::vector<SweepRow>& rows);

// Curve colour of the i-th configuration (a fixed palette, repeating).
Colour curve_colour(size_t i);

rt::ImageRgb plot_error_curves(const std::vector<SweepRow>& rows, const std::string& title);

}  // namespace accuracy
