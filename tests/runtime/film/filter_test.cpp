// Pixel filters: integrals over their support by quadrature against closed
// forms, shapes (positive lobes, zeros), and the scene's filter entity read
// with pbrt-v3's defaults.
#include <gtest/gtest.h>

#include <cmath>

#include "runtime/film/filter.h"
#include "runtime/runtime_test_support.h"
#include "test_support.h"

namespace rt {
namespace {

// Midpoint rule over [-rx, rx] x [-ry, ry] in double.
double integrate(const Filter& f, int n = 800) {
  double hx = 2.0 * f.radius.x / n, hy = 2.0 * f.radius.y / n, sum = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      sum += f.evaluate({float(-f.radius.x + (i + 0.5) * hx), float(-f.radius.y + (j + 0.5) * hy)});
  return sum * hx * hy;
}

Filter make(Filter::Type type, float rx, float ry) {
  Filter f;
  f.type = type;
  f.radius = {rx, ry};
  return f;
}

TEST(Filter, BoxIntegralIsItsArea) {
  Filter f = make(Filter::Type::kBox, 0.5f, 1.5f);
  EXPECT_NEAR(integrate(f), 4 * 0.5 * 1.5, 1e-3);
  EXPECT_EQ(f.evaluate({0.49f, -1.49f}), 1.f);
  EXPECT_EQ(f.evaluate({0.51f, 0}), 0.f);
}

TEST(Filter, TriangleIntegral) {
  Filter f = make(Filter::Type::kTriangle, 2, 1.5f);
  // Each axis integrates to r^2: the product of two tents.
  EXPECT_NEAR(integrate(f), 2.0 * 2 * 1.5 * 1.5, 1e-3);
  EXPECT_FLOAT_EQ(f.evaluate({0, 0}), 3.f);
  EXPECT_FLOAT_EQ(f.evaluate({1, 0.5f}), 1.f * 1.f);
}

TEST(Filter, GaussianIntegralMinusItsValueAtTheRadius) {
  for (float alpha : {2.f, 0.5f, 4.f}) {
    Filter f = make(Filter::Type::kGaussian, 2, 1.5f);
    f.alpha = alpha;
    finish_gaussian(&f);
    auto axis = [&](double r) {
      return std::sqrt(kPi / alpha) * std::erf(std::sqrt(alpha) * r) -
             2 * r * std::exp(-alpha * r * r);
    };
    double expected = axis(2) * axis(1.5);
    EXPECT_NEAR(integrate(f), expected, 1e-4 * expected) << alpha;
    // Goes to 0 at the radius, not below.
    EXPECT_EQ(f.evaluate({2, 0}), 0.f);
    EXPECT_NEAR(f.evaluate({1.999f, 0}), 0, 1e-3);
    EXPECT_GT(f.evaluate({1.999f, 0}), 0.f);
    EXPECT_GE(f.evaluate({1.9f, 1.4f}), 0.f);
  }
}

TEST(Filter, MitchellIntegratesToAQuarterOfTheRadiiProduct) {
  // Mitchell-Netravali's cubic integrates to 1 over [-2, 2] for every B, C;
  // the filter maps [-r, r] onto it, so each axis gives r / 2.
  for (auto bc : {std::pair<float, float>{1.f / 3, 1.f / 3}, {0, 0.5f}, {1, 0}, {0.2f, 0.7f}}) {
    Filter f = make(Filter::Type::kMitchell, 2, 3);
    f.b = bc.first;
    f.c = bc.second;
    EXPECT_NEAR(integrate(f), 2.0 / 2 * 3.0 / 2, 1e-4) << f.b << " " << f.c;
  }
  Filter f = make(Filter::Type::kMitchell, 2, 2);
  // Centre value (6 - 2B)/6 per axis; negative lobe beyond half the radius.
  float k0 = (6 - 2.f / 3) / 6;
  EXPECT_NEAR(f.evaluate({0, 0}), k0 * k0, 1e-6);
  EXPECT_LT(f.evaluate({1.5f, 0}), 0.f);
  EXPECT_NEAR(f.evaluate({1.9999f, 0}), 0, 1e-6);
}

TEST(Filter, LanczosSincIsPositiveNearlyNormalizedAndSeparable) {
  Filter f = make(Filter::Type::kSinc, 4, 4);
  f.tau = 3;
  // 1-D integral of the windowed sinc by quadrature, and the 2-D one is its square.
  double s = 0, h = 8.0 / 20000;
  for (int i = 0; i < 20000; ++i) {
    float x = float(-4 + (i + 0.5) * h);
    s += f.evaluate({x, 0}) * h;
  }
  EXPECT_NEAR(s, 1, 0.03);  // a Lanczos kernel integrates to about 1
  EXPECT_NEAR(integrate(f, 1000), s * s, 2e-3);
  EXPECT_FLOAT_EQ(f.evaluate({0, 0}), 1.f);
  EXPECT_NEAR(f.evaluate({1, 0}), 0, 1e-6);  // sinc's zeros at the integers
  EXPECT_NEAR(f.evaluate({2, 3}), 0, 1e-6);
  EXPECT_GT(f.evaluate({0.5f, 0.5f}), 0.f);
  EXPECT_LT(f.evaluate({1.5f, 0}), 0.f);  // the first negative lobe
  EXPECT_EQ(f.evaluate({4.5f, 0}), 0.f);
}

bool filter_of(const std::string& name, const std::string& line, Filter* f, std::string* error) {
  pbrta::SceneArchive a;
  if (!testing_support::compile_text(testing_support::scratch_dir("filter_" + name),
                                     line + "\nCamera \"perspective\"\nWorldBegin\nWorldEnd\n", &a))
    return false;
  return make_filter(a, f, error);
}

TEST(Filter, FromSceneWithPbrtDefaults) {
  Filter f;
  std::string error;
  ASSERT_TRUE(filter_of("default", "", &f, &error)) << error;  // no PixelFilter: box 0.5
  EXPECT_EQ(f.type, Filter::Type::kBox);
  EXPECT_EQ(f.radius.x, 0.5f);
  EXPECT_EQ(f.radius.y, 0.5f);

  ASSERT_TRUE(filter_of("gauss", "PixelFilter \"gaussian\" \"float alpha\" 3 \"float xwidth\" 1.5",
                        &f, &error))
      << error;
  EXPECT_EQ(f.type, Filter::Type::kGaussian);
  EXPECT_EQ(f.radius.x, 1.5f);
  EXPECT_EQ(f.radius.y, 2.f);
  EXPECT_EQ(f.alpha, 3.f);
  EXPECT_FLOAT_EQ(f.exp_x, std::exp(-3 * 1.5f * 1.5f));
  EXPECT_FLOAT_EQ(f.exp_y, std::exp(-3 * 2.f * 2.f));

  ASSERT_TRUE(filter_of("mitchell", "PixelFilter \"mitchell\" \"float B\" 0.5 \"float C\" 0.25", &f,
                        &error))
      << error;
  EXPECT_EQ(f.type, Filter::Type::kMitchell);
  EXPECT_EQ(f.b, 0.5f);
  EXPECT_EQ(f.c, 0.25f);
  EXPECT_EQ(f.radius.x, 2.f);

  ASSERT_TRUE(filter_of("sinc", "PixelFilter \"sinc\"", &f, &error)) << error;
  EXPECT_EQ(f.type, Filter::Type::kSinc);
  EXPECT_EQ(f.radius.x, 4.f);
  EXPECT_EQ(f.tau, 3.f);

  ASSERT_TRUE(filter_of("triangle", "PixelFilter \"triangle\" \"float ywidth\" 1", &f, &error))
      << error;
  EXPECT_EQ(f.type, Filter::Type::kTriangle);
  EXPECT_EQ(f.radius.x, 2.f);
  EXPECT_EQ(f.radius.y, 1.f);
}

TEST(Filter, ZeroWidthIsRefusedWithWhere) {
  Filter f;
  std::string error;
  EXPECT_FALSE(filter_of("zero", "PixelFilter \"box\" \"float xwidth\" 0", &f, &error));
  EXPECT_NE(error.find("xwidth"), std::string::npos) << error;
  EXPECT_NE(error.find("scene.pbrt:1"), std::string::npos) << error;
}

}  // namespace
}  // namespace rt
