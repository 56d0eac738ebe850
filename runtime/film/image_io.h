// runtime/film/image_io.h — RGB images in and out: OpenEXR and PNG.
//
// ImageRgb is a float RGB image with OpenEXR's two windows (max exclusive
// here, as Bounds2i): the data window holds the pixels, the display window
// is the full frame (a crop render's data window sits inside it). Writers
// write to a temporary file beside the target and rename it over the target
// only when everything succeeded, so a failure never leaves a half-written or
// empty output. EXR output is float32 RGB (RLE), so values above half's 65504
// survive; the reader accepts half or float (and a luminance-only Y file as
// grey). PNG output is an 8-bit sRGB preview of the data window (clamped to
// [0,1], sRGB transfer curve). Every function returns false with a message
// naming the file instead of throwing.
#pragma once

#include <string>
#include <vector>

#include "runtime/core/vec.h"

namespace rt {

struct ImageRgb {
  Bounds2i data_window, display_window;
  std::vector<float> rgb;  // data-window pixels, row-major, 3 floats each
  // An optional second RGB layer, written to EXR as <layer>.R/G/B (the error estimate).
  std::string layer;
  std::vector<float> layer_rgb;  // empty, or as rgb
  int width() const { return data_window.width(); }
  int height() const { return data_window.height(); }
};

bool read_exr(const std::string& path, ImageRgb* image, std::string* error);
bool write_exr(const std::string& path, const ImageRgb& image, std::string* error);
bool write_png(const std::string& path, const ImageRgb& image, std::string* error);
// By extension (".exr" or ".png", any case); any other extension is an error.
bool write_image(const std::string& path, const ImageRgb& image, std::string* error);

// Before rendering: the extension is one write_image knows, and the folder
// exists and accepts a new file (checked by creating and removing one).
bool check_output_path(const std::string& path, std::string* error);

// 8-bit sRGB encoding of a linear value, clamped to [0, 1] (pbrt-v3's preview curve).
unsigned char to_srgb8(float v);

}  // namespace rt
