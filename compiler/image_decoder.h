// compiler/image_decoder.h — images decoded at compile time, exactly as pbrt-v3 prepares them.
//
// pbrt-v3 reads every image a scene names (imagemap textures; infinite, projection and
// goniometric light maps) with ReadImage, converts the texels for their use, and builds a MIPMap:
// an image whose sides are not powers of two is first resampled up to the next powers of two
// with Lanczos weights (negative results clamped to 0), then each level is the 2x2 box average
// of the one before, boundary texels looked up with the wrap mode. pbrtc does all of that here,
// with pbrt-v3's float arithmetic in pbrt-v3's order, so the runtime only looks texels up and a
// texture filters to the same values. Files are read through compiler/image_reader.h.
//
// What pbrt-v3 does per use (textures/imagemap.cpp, lights/*.cpp, core/imageio.cpp):
//   - ReadImage gives RGB: 8-bit PNG/TGA values v / 255 (alpha dropped, grey replicated), EXR
//     R, G, B rounded to half floats (it reads through Imf::RgbaInputFile), PFM floats. pbrt-v3
//     refuses every other format (it renders the texture as a constant); pbrtc reads what
//     OpenImageIO reads (.hdr, .jpg, .tif, .bmp, .gif, .webp, ...) as image_reader.h says, and
//     applies pbrt-v3's 8-bit rule to those whose samples are integers: the sRGB curve is undone
//     unless "bool gamma" is "false" (see /work/shared/PBRT-V3-NOTES.md).
//   - imagemap: rows flipped (t = 0 is the bottom row), then per texel
//     scale * (gamma ? sRGB-to-linear(v) : v); a float texture keeps one channel, computed from
//     the RGB luminance y() *before* the sRGB curve. pbrt-v3 has no "invert". One deliberate
//     difference: a one-channel PFM ("Pf") gives a float texture its floats unchanged, where
//     pbrt-v3 takes y() of the grey replicated to RGB, which rounds the weights' sum and is off
//     by up to 2 ulps for about a fifth of all values. pbrtc --dump writes float textures as
//     such files, and they must read back bit for bit. 8-bit and EXR grey keep pbrt-v3's y().
//   - lights: the RGB as read (no gamma, no flip), wrap repeat. The light's L, I and scale are
//     not baked in (the runtime multiplies them, as pbrt-v3's Sample_Li does for I).
//
// Stored levels are rows top to bottom as in the file: for an imagemap, pbrt-v3's texel (s, t)
// of a level h rows high is row h - 1 - t; for lights, row t.
//
// Ownership: DecodedImage owns its texels. Thread safety: the functions are reentrant (one
// OpenImageIO reader per call) and may run in parallel on different images. Failure:
// decode_image returns false with *error set to the reason alone (the caller names the file).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pbrtc {

// pbrt-v3's ImageWrap; the values are ImageRecord::wrap's.
enum class ImageWrap : uint32_t { kRepeat = 0, kBlack = 1, kClamp = 2 };

// "repeat", "black" or "clamp"; pbrt-v3 takes any other word as repeat.
ImageWrap parse_image_wrap(const std::string& word);

// How one image is prepared; equal options on the same file give the same image.
struct ImageOptions {
  uint32_t channels = 3;  // 3: RGB; 1: a float texture (pbrt-v3 keeps the luminance)
  bool gamma = false;     // undo the sRGB curve (imagemap "gamma")
  // Undo it if the file stores integers (known once it is read): the default for formats
  // pbrt-v3 does not read, since their 8-bit files are sRGB as its PNGs are.
  bool gamma_if_integer = false;
  float scale = 1;  // imagemap "scale", multiplied after the curve
  ImageWrap wrap = ImageWrap::kRepeat;
  bool flip = false;  // imagemap: pbrt-v3 flips rows before building its MIPMap

  // The options an imagemap texture's parameters ask for (channels 1 for a float texture).
  // gamma_given false: pbrt-v3's default, true for .png and .tga files, false for .exr and
  // .pfm; for any other format, gamma_if_integer.
  static ImageOptions for_texture(const std::string& path, bool float_texture,
                                  const std::string& wrap, float scale, bool gamma_given,
                                  bool gamma);
};

struct DecodedImage {
  uint32_t width = 0, height = 0;  // level 0, powers of two
  uint32_t channels = 3;
  uint32_t source_width = 0, source_height = 0;  // as the file stores it
  ImageWrap wrap = ImageWrap::kRepeat;
  // Level k is max(1, width >> k) x max(1, height >> k) texels, channels interleaved, rows top
  // to bottom; 1 + log2(max(width, height)) levels, as pbrt-v3 builds.
  std::vector<std::vector<float>> levels;
  // When the file was resampled (its size is not level 0's): the converted texels exactly as
  // they entered resampling, source_width x source_height, rows top to bottom as in the file.
  // Empty otherwise (level 0 is the source). The archive keeps it so that pbrtc --dump can
  // write a file that decodes to this same pyramid.
  std::vector<float> source;
};

// Decodes path (any format read_image_rgb reads, by its extension, any case) and builds the
// pyramid. False with *error set if the file cannot be read or is not such an image.
bool decode_image(const std::string& path, const ImageOptions& options, DecodedImage* out,
                  std::string* error);

// pbrt-v3's MIPMap construction on texels already converted (width x height x channels, rows
// in pbrt-v3's order): resampled up to powers of two if needed, then the box-filtered pyramid.
// Rows stay in the order given.
std::vector<std::vector<float>> build_mip_pyramid(std::vector<float> texels, uint32_t width,
                                                  uint32_t height, uint32_t channels,
                                                  ImageWrap wrap, uint32_t* pow2_width,
                                                  uint32_t* pow2_height);

// The image pbrt-v3's InfiniteAreaLight builds its Distribution2D from, for an environment map
// decoded with default options (RGB, repeat, rows as pbrt-v3 reads them) lit by L (the light's
// L times scale): 2 * width by 2 * height, one channel; texel (u, v) is the luminance of L times
// the trilinear lookup of the map at ((u + .5) / 2w, (v + .5) / 2h) with filter width
// 0.5 / min(2w, 2h), times sin(pi (v + .5) / 2h). One level.
DecodedImage environment_distribution(const DecodedImage& map, const float L[3]);

}  // namespace pbrtc
