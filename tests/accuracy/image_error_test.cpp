// The error metrics against values worked out by hand.
#include "tools/accuracy/image_error.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

rt::ImageRgb image(int w, int h, std::vector<float> rgb) {
  rt::ImageRgb im;
  im.data_window = im.display_window = {{0, 0}, {w, h}};
  im.rgb = std::move(rgb);
  return im;
}

TEST(ImageError, OnePixelByHand) {
  // d = (0, 1, -0.1); r^2 + 0.01 = (1.01, 1.01, 0.02).
  accuracy::ImageErrors e;
  std::string error;
  ASSERT_TRUE(accuracy::image_errors(image(1, 1, {1, 2, 0}), image(1, 1, {1, 1, 0.1f}), &e, &error))
      << error;
  EXPECT_NEAR(e.relmse, (1 / 1.01 + 0.01 / 0.02) / 3, 1e-6);                     // 0.49670
  EXPECT_NEAR(e.rmse, std::sqrt(1.01 / 3), 1e-6);                                // 0.58023
  EXPECT_NEAR(e.mare, (1 / std::sqrt(1.01) + 0.1 / std::sqrt(0.02)) / 3, 1e-6);  // 0.56738
}

TEST(ImageError, ExactPixelsHalveTheMeans) {
  accuracy::ImageErrors one, two;
  std::string error;
  ASSERT_TRUE(
      accuracy::image_errors(image(1, 1, {1, 2, 0}), image(1, 1, {1, 1, 0.1f}), &one, &error));
  ASSERT_TRUE(accuracy::image_errors(image(2, 1, {1, 2, 0, 3, 4, 5}),
                                     image(2, 1, {1, 1, 0.1f, 3, 4, 5}), &two, &error));
  EXPECT_NEAR(two.relmse, one.relmse / 2, 1e-7);
  EXPECT_NEAR(two.mare, one.mare / 2, 1e-7);
  EXPECT_NEAR(two.rmse, one.rmse / std::sqrt(2.0), 1e-7);
}

TEST(ImageError, IdenticalImagesHaveNoError) {
  accuracy::ImageErrors e;
  std::string error;
  rt::ImageRgb a = image(2, 2, std::vector<float>(12, 0.25f));
  ASSERT_TRUE(accuracy::image_errors(a, a, &e, &error));
  EXPECT_EQ(e.relmse, 0);
  EXPECT_EQ(e.rmse, 0);
  EXPECT_EQ(e.mare, 0);
}

TEST(ImageError, DifferentSizesAreRefusedWithBothSizes) {
  accuracy::ImageErrors e;
  std::string error;
  EXPECT_FALSE(accuracy::image_errors(image(2, 1, std::vector<float>(6, 1)),
                                      image(1, 2, std::vector<float>(6, 1)), &e, &error));
  EXPECT_NE(error.find("2x1"), std::string::npos) << error;
  EXPECT_NE(error.find("1x2"), std::string::npos) << error;
}

}  // namespace
