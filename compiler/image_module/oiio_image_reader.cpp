// compiler/image_module/oiio_image_reader.cpp — libpbrtc_images.so: pbrt-v3's ReadImage on
// OpenImageIO, the only code in pbrtc that calls it. Loaded on demand; see compiler/image_reader.h
// for why it is a module and how it is found.
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <memory>
#include <type_traits>

#include "compiler/image_reader.h"

namespace pbrtc {
namespace {

// Copies channels src[0..2] of count pixels of nch channels at in to RGB at out. out may be in
// itself when nch >= 3: each pixel is read whole before it is written, and its RGB slot never
// reaches a later pixel's texels.
void pack_rgb(const float* in, int nch, const int src[3], size_t count, float* out) {
  for (size_t i = 0; i < count; ++i) {
    const float* p = in + i * size_t(nch);
    const float r = p[src[0]], g = p[src[1]], b = p[src[2]];
    out[3 * i] = r;
    out[3 * i + 1] = g;
    out[3 * i + 2] = b;
  }
}

// True if OpenImageIO has a reader for files ending in ext (".jpg"); its "extension_list" reads
// "tiff:tif,tiff;jpeg:jpg,jpeg;...".
bool known_extension(const std::string& ext) {
  if (ext.size() < 2) return false;
  const std::string list = OIIO::get_string_attribute("extension_list");
  const std::string want = ext.substr(1);
  size_t at = 0;
  while (at < list.size()) {
    const size_t end = std::min(list.find(';', at), list.size());
    const size_t colon = list.find(':', at);
    for (size_t p = colon == std::string::npos || colon > end ? end : colon + 1; p < end;) {
      const size_t q = std::min(list.find(',', p), end);
      if (list.compare(p, q - p, want) == 0) return true;
      p = q + 1;
    }
    at = end + 1;
  }
  return false;
}

// The entry point's work.
bool read(const std::string& path, RgbImage* image, std::string* error) {
  const std::string ext = image_file_extension(path);
  if (!known_extension(ext)) {
    *error = "unsupported image format \"" + ext +
             "\" (pbrtc reads what OpenImageIO reads: .exr, .png, .tga, .pfm, .hdr, .jpg, .tif, "
             ".bmp, .gif, .webp, ...)";
    return false;
  }
  // pbrt-v3's own 8-bit formats are read exactly as pbrt-v3 reads them.
  const bool exr = ext == ".exr", pbrt_eight_bit = ext == ".png" || ext == ".tga";
  std::vector<float>* rgb = &image->rgb;
  // pbrt-v3's PNG and TGA readers drop alpha without premultiplying by it; OpenImageIO would
  // premultiply unless told not to.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path, &config);
  if (!in) {
    *error = OIIO::geterror();
    if (error->empty()) *error = "not a readable image";
    while (!error->empty() && error->back() == '\n') error->pop_back();
    return false;
  }
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth > 1) {
    *error = "not a 2D image";
    return false;
  }
  if (uint32_t(spec.width) > kMaxImageSide || uint32_t(spec.height) > kMaxImageSide ||
      uint64_t(round_up_pow2(uint32_t(spec.width))) * round_up_pow2(uint32_t(spec.height)) >
          kMaxImageTexels) {
    *error = "the image is " + std::to_string(spec.width) + " x " + std::to_string(spec.height) +
             "; pbrtc takes up to 32768 texels a side and 2^28 texels after resampling to "
             "powers of two";
    return false;
  }
  const int nch = spec.nchannels;
  // Which file channels make R, G and B: named R, G, B (EXR may order them otherwise), else a
  // luminance channel Y replicated (as Imf::RgbaInputFile and a grey PNG give), else the first
  // three, else the first one replicated.
  int src[3] = {0, 0, 0};
  {
    int r = spec.channelindex("R"), g = spec.channelindex("G"), b = spec.channelindex("B");
    int y = spec.channelindex("Y");
    if (r >= 0 && g >= 0 && b >= 0) {
      src[0] = r, src[1] = g, src[2] = b;
    } else if (y >= 0) {
      src[0] = src[1] = src[2] = y;
    } else if (nch >= 3) {
      src[0] = 0, src[1] = 1, src[2] = 2;
    }
  }
  const size_t n = size_t(spec.width) * size_t(spec.height);
  std::vector<float> all(exr ? 0 : n * size_t(nch));  // EXR halves are widened in chunks
  image->integer_samples = !spec.format.is_floating_point();
  bool ok;
  if (exr) {
    // pbrt-v3 reads EXR through Imf::RgbaInputFile, which hands out half floats. They are
    // widened a few thousand pixels at a time straight into RGB: no float copy of every channel
    // of the whole image (an environment map's decode peaked at 28 bytes a texel, now 20).
    std::vector<uint16_t> half(n * size_t(nch));
    ok = in->read_image(0, 0, 0, nch, OIIO::TypeDesc::HALF, half.data());
    rgb->assign(ok ? n * 3 : 0, 0.f);
    constexpr size_t kChunk = 4096;
    std::vector<float> wide(kChunk * size_t(nch));
    for (size_t at = 0; ok && at < n; at += kChunk) {
      const size_t m = std::min(kChunk, n - at);
      ok = OIIO::convert_pixel_values(OIIO::TypeDesc::HALF, &half[at * size_t(nch)],
                                      OIIO::TypeDesc::FLOAT, wide.data(), int(m * size_t(nch)));
      if (ok) pack_rgb(wide.data(), nch, src, m, rgb->data() + at * 3);
    }
  } else if (pbrt_eight_bit || spec.format == OIIO::TypeDesc::UINT8) {
    // lodepng's 24-bit decode keeps the high byte of 16-bit PNG samples.
    if (pbrt_eight_bit && spec.format == OIIO::TypeDesc::UINT16) {
      std::vector<uint16_t> raw(all.size());
      ok = in->read_image(0, 0, 0, nch, OIIO::TypeDesc::UINT16, raw.data());
      for (size_t i = 0; ok && i < raw.size(); ++i) all[i] = float(raw[i] >> 8) / 255.f;
    } else {
      std::vector<uint8_t> raw(all.size());
      ok = in->read_image(0, 0, 0, nch, OIIO::TypeDesc::UINT8, raw.data());
      for (size_t i = 0; ok && i < raw.size(); ++i) all[i] = float(raw[i]) / 255.f;
    }
  } else {
    // Floats as they are; other integers normalized by OpenImageIO to [0, 1].
    ok = in->read_image(0, 0, 0, nch, OIIO::TypeDesc::FLOAT, all.data());
  }
  if (!ok) {
    *error = in->geterror();
    if (error->empty()) *error = "cannot decode the pixels";
    while (!error->empty() && error->back() == '\n') error->pop_back();
    return false;
  }
  image->width = uint32_t(spec.width);
  image->height = uint32_t(spec.height);
  image->float_grey = ext == ".pfm" && nch == 1;
  if (exr) return true;
  if (nch < 3) {
    rgb->resize(n * 3);
    pack_rgb(all.data(), nch, src, n, rgb->data());
    return true;
  }
  // In place: one image-sized buffer fewer at the peak.
  pack_rgb(all.data(), nch, src, n, all.data());
  all.resize(n * 3);
  rgb->swap(all);
  return true;
}

}  // namespace
}  // namespace pbrtc

// Reads the file as pbrt-v3's ReadImage does: 8-bit PNG and TGA as v / 255 with alpha dropped,
// EXR through half floats, PFM as floats; grey replicated to RGB. Other formats as image_reader.h
// says.
extern "C" __attribute__((visibility("default"))) bool pbrtc_read_image_rgb_v2(
    const std::string& path, pbrtc::RgbImage* out, std::string* error) {
  static_assert(std::is_same_v<decltype(&pbrtc_read_image_rgb_v2), pbrtc::ReadImageRgbFn>,
                "the entry point's type is the one image_reader.h looks up");
  *out = {};
  return pbrtc::read(path, out, error);
}
