// Image files: EXR round trips keep both windows and float32 values, the real
// pbrt-v3 references (half float) read with their windows, PNG previews are
// real PNGs of the right size, and failed writes leave nothing behind.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "runtime/film/image_io.h"
#include "runtime/runtime_test_support.h"
#include "test_support.h"

namespace rt {
namespace {

namespace fs = std::filesystem;

ImageRgb sample_image() {
  ImageRgb img;
  img.display_window = {{0, 0}, {64, 48}};
  img.data_window = {{10, 7}, {30, 19}};  // 20x12 inside
  for (int i = 0; i < img.width() * img.height() * 3; ++i)
    img.rgb.push_back(i % 7 == 0 ? 1e6f + i : (i % 5 == 0 ? -0.125f : 0.001f * i));
  img.rgb[3] = 70000.5f;  // above half's largest finite value (65504)
  return img;
}

TEST(ImageIo, ExrRoundTripKeepsWindowsAndFloat32) {
  std::string dir = testing_support::scratch_dir("image_io_exr");
  ImageRgb img = sample_image(), back;
  std::string error;
  ASSERT_TRUE(write_exr(dir + "/a.exr", img, &error)) << error;
  ASSERT_TRUE(read_exr(dir + "/a.exr", &back, &error)) << error;
  EXPECT_EQ(back.data_window.min, img.data_window.min);
  EXPECT_EQ(back.data_window.max, img.data_window.max);
  EXPECT_EQ(back.display_window.min, img.display_window.min);
  EXPECT_EQ(back.display_window.max, img.display_window.max);
  ASSERT_EQ(back.rgb.size(), img.rgb.size());
  for (size_t i = 0; i < img.rgb.size(); ++i) ASSERT_EQ(back.rgb[i], img.rgb[i]) << i;
  // No temporary file left beside it.
  int files = 0;
  for (auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
  EXPECT_EQ(files, 1);
}

TEST(ImageIo, ReadsRealReferencesWithTheirWindows) {
  std::string error;
  ImageRgb full, crop;
  ASSERT_TRUE(read_exr(
      testing_support::shared_dir() + "/refs/hm-textures__pbrt-v3-rs_scenes_textures_uv.exr", &full,
      &error))
      << error;
  EXPECT_EQ(full.width(), 400);
  EXPECT_EQ(full.height(), 400);
  EXPECT_EQ(full.data_window.min, (Point2i{0, 0}));
  EXPECT_EQ(full.display_window.max, (Point2i{400, 400}));
  double mean = 0;
  bool finite = true;
  for (float v : full.rgb) {
    mean += v;
    finite = finite && std::isfinite(v) && v >= 0;
  }
  EXPECT_TRUE(finite);
  EXPECT_GT(mean / full.rgb.size(), 0.01);  // no reference renders black

  ASSERT_TRUE(read_exr(testing_support::shared_dir() + "/refs/v3-cloud__f15-4a.exr", &crop, &error))
      << error;
  EXPECT_EQ(crop.data_window.min, (Point2i{0, 0}));
  EXPECT_EQ(crop.data_window.max, (Point2i{270, 240}));
  EXPECT_EQ(crop.display_window.max, (Point2i{300, 300}));
  EXPECT_EQ(crop.rgb.size(), size_t(270 * 240 * 3));
}

TEST(ImageIo, ReadErrorsNameTheFile) {
  std::string dir = testing_support::scratch_dir("image_io_bad");
  testing_support::write_file(dir + "/bad.exr", "not an exr file at all");
  ImageRgb img;
  std::string error;
  EXPECT_FALSE(read_exr(dir + "/bad.exr", &img, &error));
  EXPECT_NE(error.find("bad.exr"), std::string::npos) << error;
  EXPECT_FALSE(read_exr(dir + "/missing.exr", &img, &error));
  EXPECT_NE(error.find("missing.exr"), std::string::npos) << error;
}

TEST(ImageIo, PngIsARealPngOfTheDataWindow) {
  std::string dir = testing_support::scratch_dir("image_io_png");
  ImageRgb img = sample_image();
  std::string error;
  ASSERT_TRUE(write_image(dir + "/a.PNG", img, &error)) << error;
  std::string bytes = testing_support::read_file(dir + "/a.PNG");
  ASSERT_GT(bytes.size(), 33u);
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(bytes.substr(12, 4), "IHDR");
  auto be32 = [&](size_t o) {
    return (uint32_t(uint8_t(bytes[o])) << 24) | (uint32_t(uint8_t(bytes[o + 1])) << 16) |
           (uint32_t(uint8_t(bytes[o + 2])) << 8) | uint32_t(uint8_t(bytes[o + 3]));
  };
  EXPECT_EQ(be32(16), 20u);          // width
  EXPECT_EQ(be32(20), 12u);          // height
  EXPECT_EQ(uint8_t(bytes[24]), 8);  // bit depth
  EXPECT_EQ(uint8_t(bytes[25]), 2);  // colour type: RGB
}

TEST(ImageIo, SrgbCurve) {
  EXPECT_EQ(to_srgb8(0), 0);
  EXPECT_EQ(to_srgb8(-3), 0);
  EXPECT_EQ(to_srgb8(std::nanf("")), 0);
  EXPECT_EQ(to_srgb8(1), 255);
  EXPECT_EQ(to_srgb8(40), 255);
  EXPECT_EQ(to_srgb8(0.5f), 188);   // 1.055 * 0.5^(1/2.4) - 0.055 = 0.7354
  EXPECT_EQ(to_srgb8(0.002f), 7);   // linear segment: 12.92 * 0.002 * 255 = 6.6
  EXPECT_EQ(to_srgb8(0.18f), 118);  // 0.4614 * 255 = 117.65
}

TEST(ImageIo, WritingIntoAMissingFolderFailsAndLeavesNothing) {
  std::string dir = testing_support::scratch_dir("image_io_missing");
  ImageRgb img = sample_image();
  std::string error;
  for (const char* name : {"/nope/a.exr", "/nope/a.png"}) {
    error.clear();
    EXPECT_FALSE(write_image(dir + name, img, &error)) << name;
    EXPECT_NE(error.find("a."), std::string::npos) << error;
    EXPECT_FALSE(check_output_path(dir + name, &error));
    EXPECT_NE(error.find("does not exist"), std::string::npos) << error;
  }
  EXPECT_FALSE(fs::exists(dir + "/nope"));
  EXPECT_TRUE(fs::is_empty(dir));

  EXPECT_TRUE(check_output_path(dir + "/ok.exr", &error)) << error;
  EXPECT_TRUE(check_output_path(dir + "/ok.png", &error)) << error;
  EXPECT_TRUE(fs::is_empty(dir));  // the probe file is gone
  EXPECT_FALSE(check_output_path(dir + "/ok.jpg", &error));
  EXPECT_NE(error.find(".jpg"), std::string::npos) << error;
  EXPECT_FALSE(check_output_path(dir + "/noext", &error));

  // A failed overwrite keeps the old file whole.
  ASSERT_TRUE(write_exr(dir + "/keep.exr", img, &error)) << error;
  ImageRgb bad = img;
  bad.rgb.pop_back();
  EXPECT_FALSE(write_exr(dir + "/keep.exr", bad, &error));
  ImageRgb back;
  ASSERT_TRUE(read_exr(dir + "/keep.exr", &back, &error)) << error;
  EXPECT_EQ(back.rgb, img.rgb);
}

}  // namespace
}  // namespace rt
