// compiler/image_reader.h — image files read as pbrt-v3's ReadImage reads them, through a module
// loaded only when a scene names an image.
//
// Files are read with OpenImageIO. Debian 12's OpenImageIO brings in 263 shared libraries
// (OpenCV, ffmpeg, GDAL, GStreamer, ...), and resolving them cost ~0.5 s at every start of a
// program that links it: pbrtc and pbrt took ~1 s to print --help (twice 0.5 s, with the
// huge-page re-exec they had then), though most scenes name no image. So the code that calls OpenImageIO is a
// module of its own (compiler/image_module/, built as libpbrtc_images.so beside the programs),
// and read_image_rgb loads it with dlopen on its first call. A process that reads no image never
// loads it, and one that does pays the cost once.
//
// Where the module is looked for, first found wins: the file $PBRTC_IMAGE_MODULE names, if set;
// beside the running program (/proc/self/exe); where the build wrote it (for test programs,
// which live elsewhere in the build tree).
//
// Thread safety: read_image_rgb may run on several threads at once; the module is loaded once.
// Failure: false with *error set to the reason alone (the caller names the image file), also when
// the module cannot be loaded (the reason then names the places tried).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pbrtc {

// An image as pbrt-v3's ReadImage gives it: RGB floats, rows top to bottom as in the file.
struct RgbImage {
  uint32_t width = 0, height = 0;
  std::vector<float> rgb;   // width x height x 3
  bool float_grey = false;  // a one-channel PFM, whose floats a float texture takes as they are
  bool integer_samples = false;  // the file stores integers (8- or 16-bit), not floats
};

// Images above these sizes (after resampling to powers of two) are refused rather than
// allocated: 32768 texels a side, 2^28 texels (3 GiB of RGB floats for level 0).
constexpr uint32_t kMaxImageSide = 32768;
constexpr uint64_t kMaxImageTexels = uint64_t(1) << 28;

// The extension of path's file name in lower case, with its dot ("" if none): what decides how
// an image file is read.
inline std::string image_file_extension(const std::string& path) {
  const size_t slash = path.find_last_of('/'), dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  for (char& c : ext) c = char(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
  return ext;
}

// The smallest power of two at least v (1 for 0), as pbrt-v3 resamples image sides.
inline uint32_t round_up_pow2(uint32_t v) {
  uint32_t p = 1;
  while (p < v) p <<= 1;
  return p;
}

// Reads path: pbrt-v3's formats (.png, .tga, .pfm, .exr) as pbrt-v3 reads them, and every other
// format OpenImageIO reads (.hdr, .jpg, .tif, .bmp, .gif, .webp, ...): 8-bit samples as v / 255,
// wider integers as v / (2^bits - 1), floats as they are. A file whose extension OpenImageIO
// knows no reader for fails with "unsupported image format ...".
bool read_image_rgb(const std::string& path, RgbImage* out, std::string* error);

// The module file read_image_rgb loads (the first of the places above that exists), or "" if
// there is none; this call does not load it. Caches of compiled output key on it: a rebuilt or
// different module may decode images differently.
std::string image_module_file();

// The module's one entry point, looked up by this name. pbrtc and the module are built from
// this tree by the same compiler, so C++ types may cross; the name's version changes with the
// signature, so a stale module is refused rather than called wrongly.
using ReadImageRgbFn = bool (*)(const std::string& path, RgbImage* out, std::string* error);
inline constexpr char kReadImageRgbSymbol[] = "pbrtc_read_image_rgb_v2";

}  // namespace pbrtc
