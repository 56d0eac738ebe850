// tests/compiler/image_decoder_test.cpp — images decoded at compile time as pbrt-v3 does.
//
// Small images are written with OpenImageIO into a scratch directory and decoded: the sRGB curve
// and scale on 8-bit files, half rounding of EXR, resampling of a non-power-of-two image, the box
// pyramid, deduplication and error locations in scenes; then the shared corpus's textured scenes
// and environment maps compile into archives that load as pbrtrun loads them.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <xxhash.h>

#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "compiler/archive_builder.h"
#include "compiler/archive_dump.h"
#include "compiler/diagnostics.h"
#include "compiler/image_decoder.h"
#include "compiler/parser.h"
#include "compiler/scene_builder.h"
#include "format/scene_archive.h"
#include "reseal_and_load.h"
#include "test_support.h"

namespace pbrtc {
namespace {

void write_image(const std::string& path, int w, int h, int channels, OIIO::TypeDesc format,
                 const void* pixels) {
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out) << OIIO::geterror();
  OIIO::ImageSpec spec(w, h, channels, format);
  spec.attribute("oiio:UnassociatedAlpha", 1);  // write the bytes given, not unpremultiplied
  ASSERT_TRUE(out->open(path, spec)) << out->geterror();
  ASSERT_TRUE(out->write_image(format, pixels)) << out->geterror();
  ASSERT_TRUE(out->close());
}

// The sRGB curve as the standard states it, in double.
double srgb_to_linear(double v) {
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

ImageOptions texture_options(const std::string& path, bool float_texture = false) {
  return ImageOptions::for_texture(path, float_texture, "repeat", 1.f, false, false);
}

TEST(ImageDecoder, PngUndoesTheSrgbCurveByDefault) {
  const std::string dir = testing_support::scratch_dir("image_png_gamma");
  // 4 x 2 RGB, already powers of two: level 0 is the converted file.
  const uint8_t px[2][4][3] = {{{0, 10, 128}, {255, 64, 200}, {1, 2, 3}, {90, 90, 90}},
                               {{128, 128, 128}, {0, 0, 255}, {40, 41, 42}, {250, 5, 100}}};
  const std::string png = dir + "/t.png";
  write_image(png, 4, 2, 3, OIIO::TypeDesc::UINT8, px);

  DecodedImage im;
  std::string error;
  ASSERT_TRUE(decode_image(png, texture_options(png), &im, &error)) << error;
  EXPECT_EQ(im.width, 4u);
  EXPECT_EQ(im.height, 2u);
  EXPECT_EQ(im.channels, 3u);
  ASSERT_EQ(im.levels.size(), 3u);  // 4x2, 2x1, 1x1
  // Rows are stored top to bottom as in the file (pbrt-v3's flip is undone for storage).
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x)
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(im.levels[0][size_t((y * 4 + x) * 3 + k)], srgb_to_linear(px[y][x][k] / 255.0),
                    2e-6)
            << x << "," << y << "," << k;
  EXPECT_NEAR(im.levels[0][2], 0.2158605, 1e-6);           // 128 -> 0.21586
  EXPECT_NEAR(im.levels[0][1], 10 / 255.0 / 12.92, 1e-8);  // the linear toe

  // gamma false: v / 255, times scale.
  ImageOptions raw = ImageOptions::for_texture(png, false, "repeat", 2.f, true, false);
  ASSERT_TRUE(decode_image(png, raw, &im, &error)) << error;
  EXPECT_FLOAT_EQ(im.levels[0][2], 2 * (128 / 255.f));
  EXPECT_FLOAT_EQ(im.levels[0][3], 2.f);

  // A float texture keeps pbrt-v3's one channel: the curve applied to the luminance.
  ASSERT_TRUE(decode_image(png, texture_options(png, true), &im, &error)) << error;
  EXPECT_EQ(im.channels, 1u);
  ASSERT_EQ(im.levels[0].size(), 8u);
  double y = 0.212671 * 255 / 255 + 0.715160 * 64 / 255 + 0.072169 * 200 / 255;
  EXPECT_NEAR(im.levels[0][1], srgb_to_linear(y), 2e-6);
}

TEST(ImageDecoder, EightBitFilesAreReadAsLodepngAndTargaRead) {
  const std::string dir = testing_support::scratch_dir("image_8bit");
  DecodedImage im;
  std::string error;
  // Alpha is dropped, not multiplied in.
  const uint8_t rgba[1][2][4] = {{{200, 100, 50, 0}, {10, 20, 30, 128}}};
  write_image(dir + "/a.png", 2, 1, 4, OIIO::TypeDesc::UINT8, rgba);
  ASSERT_TRUE(decode_image(dir + "/a.png", ImageOptions{}, &im, &error)) << error;
  EXPECT_EQ(im.levels[0], (std::vector<float>{200 / 255.f, 100 / 255.f, 50 / 255.f, 10 / 255.f,
                                              20 / 255.f, 30 / 255.f}));
  // 16-bit PNG samples keep their high byte (lodepng's 24-bit decode).
  const uint16_t wide[1][1][3] = {{{0x80FF, 0xFFFF, 0x0100}}};
  write_image(dir + "/w.png", 1, 1, 3, OIIO::TypeDesc::UINT16, wide);
  ASSERT_TRUE(decode_image(dir + "/w.png", ImageOptions{}, &im, &error)) << error;
  EXPECT_EQ(im.levels[0], (std::vector<float>{128 / 255.f, 1.f, 1 / 255.f}));
  // TGA: gamma by default too; rows top first whatever the file's origin.
  const uint8_t rgb[2][1][3] = {{{255, 0, 128}}, {{0, 255, 0}}};
  write_image(dir + "/t.tga", 1, 2, 3, OIIO::TypeDesc::UINT8, rgb);
  ImageOptions o = texture_options(dir + "/T.TGA");  // extensions in any case
  EXPECT_TRUE(o.gamma);
  ASSERT_TRUE(decode_image(dir + "/t.tga", o, &im, &error)) << error;
  ASSERT_EQ(im.levels[0].size(), 6u);
  EXPECT_EQ(im.levels[0][0], 1.f);
  EXPECT_NEAR(im.levels[0][2], 0.2158605, 1e-6);
  EXPECT_EQ(im.levels[0][4], 1.f);
}

// The resampling written out from its description, in double: four taps of Lanczos (tau 2) at
// the old texel centres around each new centre, normalized; out-of-range taps wrapped, clamped,
// or dropped (black); s first, then t; negative results clamped to 0.
std::vector<double> reference_resample(const std::vector<float>& in, int w, int h, int W, int H,
                                       ImageWrap wrap) {
  auto lanczos = [](double x) {
    x = std::abs(x);
    if (x < 1e-5) return 1.0;
    if (x > 1) return 0.0;
    return std::sin(2 * M_PI * x) / (2 * M_PI * x) * std::sin(M_PI * x) / (M_PI * x);
  };
  auto tap = [&](int i, int n) {
    if (wrap == ImageWrap::kRepeat) return ((i % n) + n) % n;
    if (wrap == ImageWrap::kClamp) return std::clamp(i, 0, n - 1);
    return i >= 0 && i < n ? i : -1;
  };
  auto resample_1d = [&](const std::vector<double>& src, int n, int N, int count, bool rows) {
    std::vector<double> out(size_t(N) * size_t(count));
    for (int i = 0; i < N; ++i) {
      double center = (i + .5) * n / N;
      int first = int(std::floor(center - 2 + .5));
      double wt[4], sum = 0;
      for (int j = 0; j < 4; ++j) sum += wt[j] = lanczos((first + j + .5 - center) / 2);
      for (int c = 0; c < count; ++c) {
        double acc = 0;
        for (int j = 0; j < 4; ++j) {
          int k = tap(first + j, n);
          if (k >= 0) acc += wt[j] / sum * src[rows ? size_t(c * n + k) : size_t(k * count + c)];
        }
        out[rows ? size_t(c * N + i) : size_t(i * count + c)] = acc;
      }
    }
    return out;
  };
  std::vector<double> src(in.begin(), in.end());
  std::vector<double> s = resample_1d(src, w, W, h, true);  // each of the h rows to W wide
  std::vector<double> t = resample_1d(s, h, H, W, false);   // each of the W columns to H high
  for (double& v : t) v = std::max(v, 0.0);
  return t;
}

TEST(ImageDecoder, ResamplingMatchesItsDescription) {
  std::vector<float> in(15);
  for (int i = 0; i < 15; ++i) in[size_t(i)] = float((i * 7) % 5) + (i == 7 ? 10.f : 0.f);
  for (ImageWrap wrap : {ImageWrap::kRepeat, ImageWrap::kBlack, ImageWrap::kClamp}) {
    uint32_t W = 0, H = 0;
    auto levels = build_mip_pyramid(in, 3, 5, 1, wrap, &W, &H);
    ASSERT_EQ(W, 4u);
    ASSERT_EQ(H, 8u);
    std::vector<double> ref = reference_resample(in, 3, 5, 4, 8, wrap);
    ASSERT_EQ(levels[0].size(), ref.size());
    for (size_t i = 0; i < ref.size(); ++i)
      EXPECT_NEAR(levels[0][i], ref[i], 2e-5) << "wrap " << int(wrap) << " texel " << i;
  }
}

TEST(ImageDecoder, ExrIsReadAsPbrtV3ReadsIt) {
  const std::string dir = testing_support::scratch_dir("image_exr");
  const float px[2][2][3] = {{{0.1f, 1000.5f, -2.f}, {1e-3f, 0.5f, 3.25f}},
                             {{7.f, 8.f, 9.f}, {0.33333f, 65000.f, 2.f}}};
  const std::string exr = dir + "/t.exr";
  write_image(exr, 2, 2, 3, OIIO::TypeDesc::FLOAT, px);
  DecodedImage im;
  std::string error;
  ImageOptions o = texture_options(exr);
  EXPECT_FALSE(o.gamma);  // gamma defaults to true only for .png and .tga
  ASSERT_TRUE(decode_image(exr, o, &im, &error)) << error;
  ASSERT_EQ(im.levels[0].size(), 12u);
  // Imf::RgbaInputFile hands pbrt-v3 half floats.
  EXPECT_EQ(im.levels[0][0], 0.0999755859375f);
  EXPECT_EQ(im.levels[0][1], 1000.5f);
  EXPECT_EQ(im.levels[0][2], -2.f);  // powers of two: no resampling, so no clamp either
  EXPECT_EQ(im.levels[0][9], 0.333251953125f);
  EXPECT_EQ(im.levels[0][10], 64992.f);
  // The 1x1 top level is the box average of the four texels.
  ASSERT_EQ(im.levels.size(), 2u);
  EXPECT_FLOAT_EQ(im.levels[1][2], .25f * (-2.f + 3.25f + 9.f + 2.f));
}

TEST(ImageDecoder, NonPowerOfTwoIsResampledUpWithoutNegatives) {
  const std::string dir = testing_support::scratch_dir("image_npot");
  // 3 x 5 with hard edges, so Lanczos rings below zero before the clamp.
  uint8_t px[5][3];
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 3; ++x) px[y][x] = ((x + y) % 2) ? 255 : 0;
  const std::string png = dir + "/t.png";
  write_image(png, 3, 5, 1, OIIO::TypeDesc::UINT8, px);
  for (const char* wrap : {"repeat", "black", "clamp"}) {
    DecodedImage im;
    std::string error;
    ImageOptions o = ImageOptions::for_texture(png, true, wrap, 1.f, true, false);
    ASSERT_TRUE(decode_image(png, o, &im, &error)) << error;
    EXPECT_EQ(im.source_width, 3u);
    EXPECT_EQ(im.source_height, 5u);
    EXPECT_EQ(im.width, 4u);
    EXPECT_EQ(im.height, 8u);
    ASSERT_EQ(im.levels.size(), 4u) << wrap;  // 4x8, 2x4, 1x2, 1x1
    const uint32_t sizes[4][2] = {{4, 8}, {2, 4}, {1, 2}, {1, 1}};
    for (size_t l = 0; l < 4; ++l) EXPECT_EQ(im.levels[l].size(), sizes[l][0] * sizes[l][1]);
    double in_mean = 0, out_mean = 0;
    for (int y = 0; y < 5; ++y)
      for (int x = 0; x < 3; ++x) in_mean += px[y][x] / 255.0 / 15;
    for (float v : im.levels[0]) {
      EXPECT_GE(v, 0.f) << wrap;
      out_mean += v / 32.0;
    }
    // The windowed sinc keeps the mean (up to its ringing and, for black, the dark border).
    EXPECT_NEAR(out_mean, in_mean, std::string(wrap) == "black" ? 0.15 : 0.05) << wrap;
  }
}

TEST(ImageDecoder, ResamplingAConstantImageKeepsItConstant) {
  // The weights are normalized, so with repeat or clamp a constant stays (nearly) constant, and
  // the dimension that already is a power of two is left (nearly) alone.
  std::vector<float> texels(size_t(4 * 3 * 3), 0.75f);
  uint32_t w = 0, h = 0;
  for (ImageWrap wrap : {ImageWrap::kRepeat, ImageWrap::kClamp}) {
    auto levels = build_mip_pyramid(texels, 4, 3, 3, wrap, &w, &h);
    EXPECT_EQ(w, 4u);
    EXPECT_EQ(h, 4u);
    for (const auto& level : levels)
      for (float v : level) EXPECT_NEAR(v, 0.75f, 1e-6f);
  }
}

TEST(ImageDecoder, PyramidLevelsAreBoxAverages) {
  std::vector<float> texels(16);
  for (int i = 0; i < 16; ++i) texels[size_t(i)] = float(i * i);
  uint32_t w = 0, h = 0;
  auto levels = build_mip_pyramid(texels, 4, 4, 1, ImageWrap::kRepeat, &w, &h);
  ASSERT_EQ(levels.size(), 3u);
  EXPECT_EQ(levels[0], texels);
  ASSERT_EQ(levels[1].size(), 4u);
  auto at = [&](int x, int y) { return float((y * 4 + x) * (y * 4 + x)); };
  for (int t = 0; t < 2; ++t)
    for (int s = 0; s < 2; ++s)
      EXPECT_FLOAT_EQ(levels[1][size_t(t * 2 + s)],
                      .25f * (at(2 * s, 2 * t) + at(2 * s + 1, 2 * t) + at(2 * s, 2 * t + 1) +
                              at(2 * s + 1, 2 * t + 1)));
  ASSERT_EQ(levels[2].size(), 1u);
  float mean = 0;
  for (float v : texels) mean += v / 16;
  EXPECT_FLOAT_EQ(levels[2][0], mean);

  // A level one texel thin averages four lookups: pbrt-v3's wrap mode supplies the neighbour
  // (repeat: the same row again; black: zeros).
  const std::vector<float> row = {1, 2, 3, 4};
  auto rep = build_mip_pyramid(row, 4, 1, 1, ImageWrap::kRepeat, &w, &h);
  ASSERT_EQ(rep.size(), 3u);
  EXPECT_EQ(rep[1], (std::vector<float>{1.5f, 3.5f}));
  EXPECT_EQ(rep[2], (std::vector<float>{2.5f}));
  auto black = build_mip_pyramid(row, 4, 1, 1, ImageWrap::kBlack, &w, &h);
  EXPECT_EQ(black[1], (std::vector<float>{0.75f, 1.75f}));
  EXPECT_EQ(black[2], (std::vector<float>{0.625f}));
}

TEST(ImageDecoder, EnvironmentDistributionIsLuminanceTimesSinTheta) {
  DecodedImage map;
  map.width = 4;
  map.height = 2;
  uint32_t w = 0, h = 0;
  map.levels =
      build_mip_pyramid(std::vector<float>(4 * 2 * 3, 2.f), 4, 2, 3, ImageWrap::kRepeat, &w, &h);
  const float L[3] = {1.f, 0.5f, 0.f};
  DecodedImage d = environment_distribution(map, L);
  ASSERT_EQ(d.width, 8u);
  ASSERT_EQ(d.height, 4u);
  ASSERT_EQ(d.channels, 1u);
  ASSERT_EQ(d.levels.size(), 1u);
  const double y = 2 * (0.212671 * 1 + 0.715160 * 0.5);
  for (int v = 0; v < 4; ++v)
    for (int u = 0; u < 8; ++u)
      EXPECT_NEAR(d.levels[0][size_t(v * 8 + u)], y * std::sin(M_PI * (v + .5) / 4), 1e-5);
}

TEST(ImageDecoder, UnsupportedAndBrokenFilesSayWhy) {
  const std::string dir = testing_support::scratch_dir("image_broken");
  DecodedImage im;
  std::string error;
  const std::string doc = testing_support::write_file(dir + "/t.docx", "x");
  EXPECT_FALSE(decode_image(doc, texture_options(doc), &im, &error));
  EXPECT_EQ(error,
            "unsupported image format \".docx\" (pbrtc reads what OpenImageIO reads: .exr, .png, "
            ".tga, .pfm, .hdr, .jpg, .tif, .bmp, .gif, .webp, ...)");
  for (const char* name : {"/t.png", "/t.jpg", "/t.tif"}) {
    const std::string bad = testing_support::write_file(dir + name, "not an image at all");
    error.clear();
    EXPECT_FALSE(decode_image(bad, texture_options(bad), &im, &error)) << name;
    EXPECT_FALSE(error.empty()) << name;
    EXPECT_EQ(error.find("unsupported"), std::string::npos) << error;
  }
}

// Formats pbrt-v3 refuses, read as users expect: 8-bit samples as v / 255 and, unless "gamma" is
// given false, through the sRGB curve (pbrt-v3's rule for its own 8-bit PNG and TGA); 16-bit
// samples as v / 65535, also curved; floats as they are, not curved.
TEST(ImageDecoder, OtherFormatsFollowPbrtV3sEightBitRule) {
  const std::string dir = testing_support::scratch_dir("image_other_formats");
  DecodedImage im;
  std::string error;
  const uint8_t px[2][2][3] = {{{0, 10, 128}, {255, 64, 200}}, {{1, 2, 3}, {90, 91, 250}}};
  for (const char* name : {"/t.bmp", "/T.TIF"}) {
    const std::string path = dir + name;
    write_image(path, 2, 2, 3, OIIO::TypeDesc::UINT8, px);
    ASSERT_TRUE(decode_image(path, texture_options(path), &im, &error)) << name << error;
    ASSERT_EQ(im.levels[0].size(), 12u) << name;
    for (size_t i = 0; i < 12; ++i)
      EXPECT_NEAR(im.levels[0][i], srgb_to_linear((&px[0][0][0])[i] / 255.0), 2e-6) << name << i;
    const ImageOptions raw = ImageOptions::for_texture(path, false, "repeat", 1.f, true, false);
    ASSERT_TRUE(decode_image(path, raw, &im, &error)) << name << error;
    for (size_t i = 0; i < 12; ++i)
      EXPECT_EQ(im.levels[0][i], float((&px[0][0][0])[i]) / 255.f) << name << i;
  }
  // JPEG is lossy: whatever it decodes to, the default is the curve applied to it. A smooth grey
  // ramp survives it closely.
  uint8_t ramp[2][2][3];
  for (int k = 0; k < 12; ++k) (&ramp[0][0][0])[k] = uint8_t(100 + 10 * (k / 3));
  const std::string jpg = dir + "/t.jpg";
  write_image(jpg, 2, 2, 3, OIIO::TypeDesc::UINT8, ramp);
  DecodedImage curved;
  ASSERT_TRUE(decode_image(jpg, texture_options(jpg), &curved, &error)) << error;
  ASSERT_TRUE(decode_image(jpg, ImageOptions::for_texture(jpg, false, "repeat", 1.f, true, false),
                           &im, &error))
      << error;
  ASSERT_EQ(curved.levels[0].size(), 12u);
  for (size_t i = 0; i < 12; ++i) {
    const float v = im.levels[0][i];
    EXPECT_EQ(v * 255.f, std::round(v * 255.f)) << i;  // an 8-bit value
    EXPECT_NEAR(curved.levels[0][i], srgb_to_linear(v), 2e-6) << i;
    EXPECT_NEAR(v, (&ramp[0][0][0])[i] / 255.0, 0.05) << i;  // and near what was written
  }
  // 16-bit TIFF: v / 65535, curved.
  const uint16_t wide[1][2][3] = {{{0, 32768, 65535}, {1000, 20000, 60000}}};
  const std::string tif16 = dir + "/w.tiff";
  write_image(tif16, 2, 1, 3, OIIO::TypeDesc::UINT16, wide);
  ASSERT_TRUE(decode_image(tif16, texture_options(tif16), &im, &error)) << error;
  for (size_t i = 0; i < 6; ++i)
    EXPECT_NEAR(im.levels[0][i], srgb_to_linear((&wide[0][0][0])[i] / 65535.0), 2e-6) << i;
  // Float TIFF: as stored, no curve.
  const float linear[1][2][3] = {{{0.25f, 3.5f, 0.f}, {1e-3f, 0.5f, 12.f}}};
  const std::string tiff = dir + "/f.tif";
  write_image(tiff, 2, 1, 3, OIIO::TypeDesc::FLOAT, linear);
  ASSERT_TRUE(decode_image(tiff, texture_options(tiff), &im, &error)) << error;
  for (size_t i = 0; i < 6; ++i) EXPECT_EQ(im.levels[0][i], (&linear[0][0][0])[i]) << i;
  // Asked for, the curve applies to floats too, as pbrt-v3's gamma does to an EXR.
  ASSERT_TRUE(decode_image(tiff, ImageOptions::for_texture(tiff, false, "repeat", 1.f, true, true),
                           &im, &error))
      << error;
  EXPECT_NEAR(im.levels[0][0], srgb_to_linear(0.25), 2e-6);
}

// A scene in dir naming files there; returns the diagnostics' messages.
struct Built {
  SourceFiles files;
  Diagnostics diag{&files};
  SceneDesc scene;
  bool ok = false;
};

void build(const std::string& dir, const std::string& world, Built* b) {
  const std::string path = testing_support::write_file(
      dir + "/scene.pbrt", "Camera \"perspective\"\nWorldBegin\n" + world + "WorldEnd\n");
  b->ok = build_scene(path, &b->files, &b->diag, &b->scene);
}

TEST(SceneImages, SameFileAndOptionsDecodeOnce) {
  const std::string dir = testing_support::scratch_dir("image_dedup");
  const uint8_t px[2][2][3] = {{{0, 10, 128}, {255, 64, 200}}, {{1, 2, 3}, {90, 90, 90}}};
  write_image(dir + "/a.png", 2, 2, 3, OIIO::TypeDesc::UINT8, px);
  Built b;
  build(dir,
        "Texture \"t1\" \"spectrum\" \"imagemap\" \"string filename\" \"a.png\"\n"
        "Texture \"t2\" \"spectrum\" \"imagemap\" \"string filename\" \"a.png\" "
        "\"float maxanisotropy\" 4\n"
        "Texture \"t3\" \"spectrum\" \"imagemap\" \"string filename\" \"a.png\" \"float scale\" 2\n"
        "Texture \"t4\" \"float\" \"imagemap\" \"string filename\" \"a.png\"\n"
        "LightSource \"projection\" \"string mapname\" \"a.png\"\n"
        "LightSource \"goniometric\" \"string mapname\" \"a.png\"\n",
        &b);
  ASSERT_TRUE(b.ok) << (b.diag.all().empty() ? "" : b.diag.all()[0].text);
  ASSERT_EQ(b.scene.textures.size(), 4u);
  EXPECT_EQ(b.scene.textures[0].image, 0);
  EXPECT_EQ(b.scene.textures[1].image, 0);  // filtering options do not change the texels
  EXPECT_EQ(b.scene.textures[2].image, 1);  // scale does
  EXPECT_EQ(b.scene.textures[3].image, 2);  // so does the float conversion
  ASSERT_EQ(b.scene.lights.size(), 2u);
  EXPECT_EQ(b.scene.lights[0].image, 3);  // lights: no gamma, no flip
  EXPECT_EQ(b.scene.lights[1].image, 3);
  ASSERT_EQ(b.scene.images.size(), 4u);
  EXPECT_EQ(b.scene.images[3].image.levels[0][0], 0.f);
  EXPECT_EQ(b.scene.images[3].image.levels[0][2], 128 / 255.f);
  for (const ImageDesc& im : b.scene.images) EXPECT_EQ(im.distribution, kNone);
}

// A little-endian colour PFM; rows[0] is the top row (the file stores the bottom row first).
void write_colour_pfm(const std::string& path, int w, int h, const std::vector<float>& rows) {
  std::string bytes = "PF\n" + std::to_string(w) + " " + std::to_string(h) + "\n-1.0\n";
  for (int y = h - 1; y >= 0; --y)
    bytes.append(reinterpret_cast<const char*>(&rows[size_t(y * w * 3)]), size_t(w * 3 * 4));
  testing_support::write_file(path, bytes);
}

TEST(ImageDecoder, PfmRowsArePbrtV3s) {
  const std::string dir = testing_support::scratch_dir("image_pfm");
  std::vector<float> rows(4 * 2 * 3, 1.f);
  for (int i = 0; i < 12; ++i) rows[size_t(i)] = 2.f;  // the top row
  write_colour_pfm(dir + "/t.pfm", 4, 2, rows);
  DecodedImage im;
  std::string error;
  ASSERT_TRUE(decode_image(dir + "/t.pfm", ImageOptions{}, &im, &error)) << error;
  EXPECT_EQ(im.levels[0], rows);  // a light's map: pbrt-v3's rows are the file's, top first
  ASSERT_TRUE(decode_image(dir + "/t.pfm", texture_options(dir + "/t.pfm"), &im, &error));
  EXPECT_EQ(im.levels[0], rows);  // a texture's flip is undone for storage
}

// Floats that must survive a PFM round trip: signed zeros, a denormal, the extremes, values
// that are not 8-bit or half floats, infinity and a quiet NaN.
std::vector<float> awkward_floats(size_t n) {
  const float pool[] = {0.f,
                        -0.f,
                        1e-40f,
                        3.4e38f,
                        -2.5f,
                        1.f / 3,
                        0.1f,
                        65504.5f,
                        1e-30f,
                        7.f,
                        -1e-7f,
                        0.73f,
                        std::numeric_limits<float>::infinity(),
                        std::numeric_limits<float>::quiet_NaN()};
  std::vector<float> v(n);
  for (size_t i = 0; i < n; ++i) v[i] = pool[(i * 5 + i / 7) % (sizeof pool / sizeof pool[0])];
  return v;
}

::testing::AssertionResult same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  if (a.size() != b.size())
    return ::testing::AssertionFailure() << a.size() << " floats vs " << b.size();
  for (size_t i = 0; i < a.size(); ++i)
    if (std::memcmp(&a[i], &b[i], 4) != 0)
      return ::testing::AssertionFailure() << "float " << i << ": " << a[i] << " vs " << b[i];
  return ::testing::AssertionSuccess();
}

// pbrtc --dump writes images as PFM: the decoder must give back exactly the texels written,
// for a light's map, a spectrum texture and a float texture (one channel, "Pf").
TEST(ImageDecoder, DumpedPfmReadsBackBitForBit) {
  const std::string dir = testing_support::scratch_dir("image_pfm_exact");
  std::string error;
  for (uint32_t channels : {3u, 1u}) {
    const std::vector<float> texels = awkward_floats(size_t(8) * 4 * channels);
    const std::string pfm = dir + "/t" + std::to_string(channels) + ".pfm";
    ASSERT_TRUE(write_pfm(pfm, texels.data(), 8, 4, channels, &error)) << error;
    const std::string bytes = testing_support::read_file(pfm);
    EXPECT_EQ(bytes.substr(0, 10), channels == 3 ? "PF\n8 4\n-1\n" : "Pf\n8 4\n-1\n");
    EXPECT_EQ(bytes.size(), 10 + texels.size() * 4);
    // PFM's first row is the image's bottom row.
    EXPECT_EQ(std::memcmp(bytes.data() + 10, &texels[size_t(3) * 8 * channels], 4), 0);

    DecodedImage im;
    const ImageOptions texture =
        ImageOptions::for_texture(pfm, channels == 1, "clamp", 1.f, true, false);
    ASSERT_TRUE(decode_image(pfm, texture, &im, &error)) << error;
    ASSERT_EQ(im.channels, channels);
    EXPECT_TRUE(im.source.empty());  // powers of two: level 0 is the source
    EXPECT_TRUE(same_bits(im.levels[0], texels)) << channels << " channels, texture";
    if (channels == 3) {
      ASSERT_TRUE(decode_image(pfm, ImageOptions{}, &im, &error)) << error;
      EXPECT_TRUE(same_bits(im.levels[0], texels)) << "light map";
    }
  }
  // A one-channel PFM passes through unchanged where pbrt-v3's luminance of the replicated grey
  // would round: 2.875 is such a value.
  const float grey = 2.875f;
  EXPECT_NE(0.212671f * grey + 0.715160f * grey + 0.072169f * grey, grey);
  ASSERT_TRUE(write_pfm(dir + "/y.pfm", &grey, 1, 1, 1, &error)) << error;
  DecodedImage y;
  ASSERT_TRUE(decode_image(dir + "/y.pfm", texture_options(dir + "/y.pfm", true), &y, &error));
  EXPECT_EQ(y.levels[0], std::vector<float>{grey});
  // ... while an RGB file still gives a float texture its luminance, as pbrt-v3 computes it.
  const std::vector<float> rgb(3, grey);
  ASSERT_TRUE(write_pfm(dir + "/g.pfm", rgb.data(), 1, 1, 3, &error)) << error;
  DecodedImage im;
  ASSERT_TRUE(decode_image(dir + "/g.pfm", texture_options(dir + "/g.pfm", true), &im, &error));
  EXPECT_EQ(im.levels[0][0], 0.212671f * grey + 0.715160f * grey + 0.072169f * grey);
}

// A map that is resampled keeps the texels that entered resampling, rows as in the file; a PFM
// of them decodes to the same pyramid.
TEST(ImageDecoder, ResampledImageKeepsItsSourceTexels) {
  const std::string dir = testing_support::scratch_dir("image_source");
  std::vector<float> texels(size_t(3) * 5 * 3);
  for (size_t i = 0; i < texels.size(); ++i) texels[i] = float((i * 7) % 11) / 3.f;
  std::string error;
  ASSERT_TRUE(write_pfm(dir + "/a.pfm", texels.data(), 3, 5, 3, &error)) << error;
  for (bool texture : {false, true}) {
    ImageOptions o =
        texture ? ImageOptions::for_texture(dir + "/a.pfm", false, "black", 2.f, true, false)
                : ImageOptions{};
    DecodedImage im;
    ASSERT_TRUE(decode_image(dir + "/a.pfm", o, &im, &error)) << error;
    EXPECT_EQ(im.width, 4u);
    EXPECT_EQ(im.height, 8u);
    std::vector<float> expect = texels;
    for (float& v : expect) v *= o.scale;
    EXPECT_TRUE(same_bits(im.source, expect)) << (texture ? "texture" : "light");
    // Written out and read back with the parameters normalized, it gives the same pyramid.
    ASSERT_TRUE(write_pfm(dir + "/b.pfm", im.source.data(), 3, 5, 3, &error)) << error;
    ImageOptions again = o;
    again.scale = 1;
    DecodedImage im2;
    ASSERT_TRUE(decode_image(dir + "/b.pfm", again, &im2, &error)) << error;
    ASSERT_EQ(im2.levels.size(), im.levels.size());
    for (size_t l = 0; l < im.levels.size(); ++l)
      EXPECT_TRUE(same_bits(im2.levels[l], im.levels[l])) << "level " << l;
    EXPECT_TRUE(same_bits(im2.source, im.source));
  }
}

TEST(SceneImages, EnvironmentMapGetsItsDistribution) {
  const std::string dir = testing_support::scratch_dir("image_env");
  // 8 x 3: resampled to 8 x 4.
  write_colour_pfm(dir + "/sky.pfm", 8, 3, std::vector<float>(8 * 3 * 3, 1.f));
  Built b;
  build(dir, "LightSource \"infinite\" \"string mapname\" \"sky.pfm\" \"rgb L\" [2 2 2]\n", &b);
  ASSERT_TRUE(b.ok) << (b.diag.all().empty() ? "" : b.diag.all()[0].text);
  ASSERT_EQ(b.scene.images.size(), 3u);  // the map, its distribution, the map as decoded
  EXPECT_EQ(b.scene.lights[0].image, 0);
  EXPECT_EQ(b.scene.images[0].distribution, 1);
  EXPECT_EQ(b.scene.images[0].source_image, 2);
  EXPECT_EQ(b.scene.images[1].source_image, kNone);
  EXPECT_EQ(b.scene.images[2].image.width, 8u);
  EXPECT_EQ(b.scene.images[2].image.height, 3u);
  EXPECT_EQ(b.scene.images[0].image.width, 8u);
  EXPECT_EQ(b.scene.images[0].image.height, 4u);
  EXPECT_EQ(b.scene.images[1].image.width, 16u);
  EXPECT_EQ(b.scene.images[1].image.height, 8u);
  // The map itself does not carry L: the runtime multiplies it.
  EXPECT_NEAR(b.scene.images[0].image.levels[0][0], 1.f, 1e-5);
}

// a.png (3 x 5, resampled to a pyramid, so it keeps a source image) and p.png (2 x 2, its own
// level 0), 8-bit RGB with texel (x, y) channel k = 40 y + 10 x + 3 k.
void write_a_and_p(const std::string& dir) {
  uint8_t px[5][3][3];
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 3; ++x)
      for (int k = 0; k < 3; ++k) px[y][x][k] = uint8_t(40 * y + 10 * x + 3 * k);
  write_image(dir + "/a.png", 3, 5, 3, OIIO::TypeDesc::UINT8, px);
  write_image(dir + "/p.png", 2, 2, 3, OIIO::TypeDesc::UINT8, px);
}

// Image parameters describe the stored texels: gamma and scale are applied, then stored as
// "no curve, scale 1"; lights keep their parameters. Resampled maps name their decoded texels.
TEST(SceneImages, DecodeParametersAreNormalizedAndSourcesKept) {
  const std::string dir = testing_support::scratch_dir("image_normalized");
  write_a_and_p(dir);
  Built b;
  build(dir,
        "Texture \"t1\" \"spectrum\" \"imagemap\" \"string filename\" \"a.png\" "
        "\"float scale\" 2\n"
        "Texture \"t2\" \"float\" \"imagemap\" \"string filename\" \"p.png\" "
        "\"bool gamma\" \"true\"\n"
        "LightSource \"projection\" \"string mapname\" \"a.png\" \"rgb scale\" [3 3 3]\n",
        &b);
  ASSERT_TRUE(b.ok) << (b.diag.all().empty() ? "" : b.diag.all()[0].text);
  for (const TextureDesc& t : b.scene.textures) {
    EXPECT_TRUE(t.params.given("gamma"));
    EXPECT_FALSE(t.params.get_bool("gamma"));
    EXPECT_TRUE(t.params.given("scale"));
    EXPECT_EQ(t.params.get_float("scale"), 1.f);
  }
  EXPECT_EQ(b.scene.lights[0].params.get_floats("scale")[0], 3.f);  // not applied to the map
  // Images: t1's pyramid, t2's, the light's; then t1's and the light's texels as decoded.
  ASSERT_EQ(b.scene.images.size(), 5u);
  EXPECT_EQ(b.scene.textures[0].image, 0);
  EXPECT_EQ(b.scene.textures[1].image, 1);
  EXPECT_EQ(b.scene.lights[0].image, 2);
  EXPECT_EQ(b.scene.images[0].source_image, 3);
  EXPECT_EQ(b.scene.images[1].source_image, kNone);  // 2 x 2: level 0 is the source
  EXPECT_EQ(b.scene.images[2].source_image, 4);
  const DecodedImage& src = b.scene.images[3].image;
  EXPECT_EQ(src.width, 3u);
  EXPECT_EQ(src.height, 5u);
  ASSERT_EQ(src.levels.size(), 1u);
  // Rows as in the file, the curve and the scale applied.
  ImageOptions o = ImageOptions::for_texture("a.png", false, "repeat", 2.f, false, false);
  DecodedImage direct;
  std::string error;
  ASSERT_TRUE(decode_image(dir + "/a.png", o, &direct, &error)) << error;
  EXPECT_EQ(src.levels[0], direct.source);
  EXPECT_NEAR(src.levels[0][(1 * 3 + 2) * 3 + 1], 2 * srgb_to_linear((40 + 20 + 3) / 255.0), 1e-6);
  EXPECT_EQ(b.scene.images[4].image.levels[0][(1 * 3 + 2) * 3 + 1], (40 + 20 + 3) / 255.f);

  // The archive records the sources; the reader checks them.
  const std::string path = dir + "/a.pbrta";
  ArchiveOptions opt;
  opt.compress = false;  // so the test can edit the records in place
  ASSERT_TRUE(write_archive(b.scene, b.files, dir, path, opt, nullptr, &error)) << error;
  pbrta::SceneArchive archive;
  ASSERT_TRUE(archive.load(path, 1, &error)) << error;
  ASSERT_EQ(archive.images.size, 5u);
  EXPECT_EQ(archive.images[0].source_image, 3u);
  EXPECT_EQ(archive.images[1].source_image, pbrta::kNoIndex);
  EXPECT_EQ(archive.images[3].levels, 1u);
  EXPECT_EQ(archive.images[3].width, 3u);
  EXPECT_EQ(archive.images[3].source_image, pbrta::kNoIndex);
  const uint32_t images_entry =
      testing_support::section_entry(archive, pbrta::SectionKind::kImages);
  ASSERT_NE(images_entry, pbrta::kNoIndex);
  const uint64_t images_at = archive.reader().entry(images_entry).offset;
  const std::string good = testing_support::read_file(path);
  // Edits image `image`'s field at byte `field` and reseals the checksums.
  auto edit = [&](uint32_t image, size_t field, uint32_t value) {
    std::string bytes = good;
    std::memcpy(&bytes[images_at + image * sizeof(pbrta::ImageRecord) + field], &value, 4);
    return testing_support::reseal_and_load(bytes, dir + "/bad.pbrta");
  };
  const size_t source_field = offsetof(pbrta::ImageRecord, source_image);
  const std::string prefix =
      dir + "/bad.pbrta: section 'images' (#" + std::to_string(images_entry) + "): image 0: ";
  const std::string not_source =
      "source image 1 is not 3 x 5 x 3 in the same format and wrap, "
      "with one level and no source of its own";
  EXPECT_EQ(edit(0, source_field, 1), prefix + not_source);  // 2 x 2, not the source's size
  EXPECT_EQ(edit(0, source_field, 5), prefix + "source image 5 out of range (5 images)");
  EXPECT_EQ(edit(0, source_field, 0),
            prefix +
                "source image 0 is not 3 x 5 x 3 in the same format and wrap, with one "
                "level and no source of its own");  // itself
  EXPECT_EQ(edit(3, source_field, 4),               // a chain: image 0's source names one
            prefix +
                "source image 3 is not 3 x 5 x 3 in the same format and wrap, with one "
                "level and no source of its own");
  EXPECT_EQ(edit(1, source_field, 3),
            dir + "/bad.pbrta: section 'images' (#" + std::to_string(images_entry) +
                "): image 1: level 0 is already the source size, 2 x 2, yet it names source "
                "image 3");
  EXPECT_EQ(edit(1, offsetof(pbrta::ImageRecord, reserved) + 8, 1),
            dir + "/bad.pbrta: section 'images' (#" + std::to_string(images_entry) +
                "): image 1: reserved field is not zero");
  // What a texture or a light looks up is the whole pyramid: t1's 4 x 8 has 4 levels, and the
  // light's map too; a level short (still inside the section) is refused.
  const size_t levels_field = offsetof(pbrta::ImageRecord, levels);
  ASSERT_EQ(archive.images[0].levels, 4u);
  ASSERT_EQ(archive.images[2].levels, 4u);
  const std::string images_prefix =
      dir + "/bad.pbrta: section 'images' (#" + std::to_string(images_entry) + "): ";
  EXPECT_EQ(edit(0, levels_field, 3),
            images_prefix + "image 0: 3 levels, but as texture 0's pyramid it has 4");
  EXPECT_EQ(edit(2, levels_field, 1),
            images_prefix + "image 2: 1 levels, but as light 0's pyramid it has 4");
  // A source image (one level) may not stand in for the pyramid either.
  EXPECT_EQ(edit(0, levels_field, 1),
            images_prefix + "image 0: 1 levels, but as texture 0's pyramid it has 4");
}

// Source images (ARCHIVE.md, ImageRecord) sit in texels sections of their own, which a renderer's
// load leaves undecoded: a damaged byte there fails pbrtc --verify's load, not pbrtrun's. Any
// other texels section is decoded and checked either way.
TEST(SceneImages, RenderersLeaveSourceTexelsUndecoded) {
  const std::string dir = testing_support::scratch_dir("image_sources_skipped");
  write_a_and_p(dir);
  Built b;
  build(dir,
        "Texture \"t1\" \"spectrum\" \"imagemap\" \"string filename\" \"a.png\"\n"
        "Texture \"t2\" \"float\" \"imagemap\" \"string filename\" \"p.png\"\n"
        "LightSource \"projection\" \"string mapname\" \"a.png\"\n",
        &b);
  ASSERT_TRUE(b.ok) << (b.diag.all().empty() ? "" : b.diag.all()[0].text);
  const std::string path = dir + "/a.pbrta";
  ArchiveOptions opt;
  opt.compress = false;  // raw sections: the test damages texels in place
  std::string error;
  ASSERT_TRUE(write_archive(b.scene, b.files, dir, path, opt, nullptr, &error)) << error;
  pbrta::SceneArchive full, renderer;
  renderer.skip_source_texels();
  ASSERT_TRUE(full.load(path, 1, &error)) << error;
  ASSERT_TRUE(renderer.load(path, 1, &error)) << error;
  // Images 0-2 are the pyramids, 3 and 4 the sources of 0 and 2.
  ASSERT_EQ(full.images.size, 5u);
  ASSERT_EQ(full.images[0].source_image, 3u);
  ASSERT_EQ(full.images[2].source_image, 4u);
  const uint32_t pyramids = full.images[0].section, sources = full.images[3].section;
  EXPECT_NE(pyramids, sources);
  for (uint32_t i = 0; i < 5; ++i)
    EXPECT_EQ(full.images[i].section, i < 3 ? pyramids : sources) << "image " << i;
  EXPECT_NE(full.reader().section_data(sources), nullptr);
  EXPECT_EQ(renderer.reader().section_data(sources), nullptr);
  ASSERT_NE(renderer.reader().section_data(pyramids), nullptr);
  EXPECT_EQ(std::memcmp(renderer.reader().section_data(pyramids),
                        full.reader().section_data(pyramids), full.reader().section_size(pyramids)),
            0);

  const std::string good = testing_support::read_file(path);
  auto damaged_in = [&](uint32_t section, bool skip) {
    std::string bytes = good;
    bytes[full.reader().entry(section).offset + 5] ^= 1;
    testing_support::write_file(dir + "/bad.pbrta", bytes);
    pbrta::SceneArchive a;
    if (skip) a.skip_source_texels();
    std::string why;
    return a.load(dir + "/bad.pbrta", 1, &why) ? std::string("loaded") : why;
  };
  auto mismatch = [&](uint32_t section) {
    return dir + "/bad.pbrta: section 'texels' (#" + std::to_string(section) +
           "): checksum mismatch";
  };
  EXPECT_EQ(damaged_in(sources, false), mismatch(sources));
  EXPECT_EQ(damaged_in(sources, true), "loaded");
  EXPECT_EQ(damaged_in(pyramids, false), mismatch(pyramids));
  EXPECT_EQ(damaged_in(pyramids, true), mismatch(pyramids));
}

TEST(SceneImages, UnreadableImageIsAnErrorAtItsDirective) {
  const std::string dir = testing_support::scratch_dir("image_unreadable");
  testing_support::write_file(dir + "/bad.png", "this is no PNG");
  Built b;
  build(dir,
        "Material \"matte\"\n"
        "  Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"bad.png\"\n",
        &b);
  EXPECT_FALSE(b.ok);
  ASSERT_EQ(b.diag.all().size(), 1u);
  const Diagnostic& d = b.diag.all()[0];
  EXPECT_EQ(d.severity, Severity::kError);
  const std::string prefix = "cannot read image \"" + dir + "/bad.png\": ";
  EXPECT_EQ(d.message.substr(0, prefix.size()), prefix) << d.message;
  EXPECT_GT(d.message.size(), prefix.size());
  EXPECT_EQ(b.files.line_col(d.loc).line, 4u);
  EXPECT_EQ(b.files.line_col(d.loc).column, 3u);
}

// The corpus scenes with images compile, and their archives load as pbrtrun loads them, with the
// image records pointing at the decoded texels.
TEST(SceneImages, SharedTexturedScenesCompileAndVerify) {
  const std::string scenes = testing_support::shared_dir() + "/scenes/";
  const std::string out = testing_support::scratch_dir("image_shared");
  const char* paths[] = {
      "hm-textures/pbrt-v3-rs/scenes/textures/ewa-filtering.pbrt",
      "hm-textures/pbrt-v3-rs/scenes/textures/trilinear-filtering.pbrt",
      "rs-anim-bluespheres/anim-bluespheres.pbrt",
      "v3-figures/f10-1ac.pbrt",
  };
  std::printf("%-64s %7s %9s %10s %10s\n", "scene", "images", "build ms", "raw MiB", "file MiB");
  for (size_t n = 0; n < sizeof paths / sizeof paths[0]; ++n) {
    const char* rel = paths[n];
    const std::string path = scenes + rel;
    SourceFiles files;
    Diagnostics diag(&files);
    SceneDesc scene;
    auto t0 = std::chrono::steady_clock::now();
    ASSERT_TRUE(build_scene(path, &files, &diag, &scene))
        << rel << ": " << (diag.all().empty() ? "" : diag.all()[0].text);
    double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_FALSE(scene.images.empty()) << rel;
    const std::string archive_path = out + "/" + std::to_string(n) + ".pbrta";
    ArchiveStats stats;
    std::string error;
    ASSERT_TRUE(write_archive(scene, files, directory_of(path), archive_path, ArchiveOptions{},
                              &stats, &error))
        << error;
    std::printf("%-64s %7zu %9.0f %10.2f %10.2f\n", rel, scene.images.size(), ms,
                stats.raw_size / 1048576.0, stats.file_size / 1048576.0);

    pbrta::SceneArchive archive;
    ASSERT_TRUE(archive.load(archive_path, 0, &error)) << error;
    ASSERT_EQ(archive.images.size, scene.images.size());
    for (uint32_t i = 0; i < archive.images.size; ++i) {
      const pbrta::ImageRecord& r = archive.images[i];
      const DecodedImage& im = scene.images[i].image;
      EXPECT_EQ(r.width, im.width);
      EXPECT_EQ(r.levels, im.levels.size());
      // Level 0's first and last texels are where the record says.
      const float* texels =
          reinterpret_cast<const float*>(archive.reader().section_data(r.section) + r.offset);
      EXPECT_EQ(texels[0], im.levels[0][0]);
      EXPECT_EQ(texels[im.levels[0].size() - 1], im.levels[0].back());
    }
    for (uint32_t t = 0; t < archive.textures.size; ++t) {
      if (archive.type_name(archive.textures[t].entity) == "imagemap") {
        EXPECT_NE(archive.textures[t].image, pbrta::kNoIndex) << rel;
      }
    }
    bool env = false;
    for (uint32_t l = 0; l < archive.lights.size; ++l)
      if (archive.type_name(archive.lights[l].entity) == "infinite" &&
          archive.lights[l].image != pbrta::kNoIndex) {
        env = true;
        EXPECT_NE(archive.images[archive.lights[l].image].distribution, pbrta::kNoIndex);
      }
    if (std::string(rel).find("textures/") == std::string::npos) {
      EXPECT_TRUE(env) << rel;
    }
  }
}

}  // namespace
}  // namespace pbrtc
