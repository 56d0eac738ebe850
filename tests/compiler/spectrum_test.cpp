// tests/compiler/spectrum_test.cpp — spectra to pbrt-v3 RGB, .spd parsing, and the data tables.
//
// Expected RGB values were computed from pbrt-v3's rules (RGBSpectrum::FromSampled,
// BlackbodyNormalized, XYZToRGB) by an independent double-precision script over the same tables;
// the tolerances cover float rounding, not a different method.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "compiler/spectrum.h"

namespace pbrtc {
namespace {

std::vector<float> cie_lambdas() {
  std::vector<float> l;
  for (int i = 0; i < kCieSampleCount; ++i) l.push_back(kCieLambdaFirst + static_cast<float>(i));
  return l;
}

double table_sum(const float* table) {
  double sum = 0;
  for (int i = 0; i < kCieSampleCount; ++i) sum += table[i];
  return sum;
}

int cie_index(int lambda_nm) {
  return lambda_nm - 360;
}

void expect_rgb_near(Rgb actual, float r, float g, float b, float tolerance) {
  EXPECT_NEAR(actual.r, r, tolerance);
  EXPECT_NEAR(actual.g, g, tolerance);
  EXPECT_NEAR(actual.b, b, tolerance);
}

void expect_rgb_eq(Rgb actual, Rgb expected) {
  EXPECT_FLOAT_EQ(actual.r, expected.r);
  EXPECT_FLOAT_EQ(actual.g, expected.g);
  EXPECT_FLOAT_EQ(actual.b, expected.b);
}

// pbrt-v3's RGBToXYZ, the inverse of XYZToRGB, to read XYZ back out of an RGB result.
void xyz_from_rgb(Rgb c, double xyz[3]) {
  xyz[0] = 0.412453 * c.r + 0.357580 * c.g + 0.180423 * c.b;
  xyz[1] = 0.212671 * c.r + 0.715160 * c.g + 0.072169 * c.b;
  xyz[2] = 0.019334 * c.r + 0.119193 * c.g + 0.950227 * c.b;
}

// ---- Tables ----

TEST(SpectrumTables, YbarSumsToPbrtV3YIntegral) {
  // pbrt-v3's CIE_Y_integral is this sum; a dropped or mistyped ybar entry would move it.
  EXPECT_NEAR(table_sum(kCieY), kCieYIntegral, 1e-3 * kCieYIntegral);
  EXPECT_NEAR(table_sum(kCieY), kCieYIntegral, 1e-4);  // in fact it agrees to float precision
}

TEST(SpectrumTables, XbarAndZbarSumToYbarsSum) {
  // The CIE 1931 functions are scaled so that equal-energy white has X = Y = Z; with the 1 nm
  // table the sums agree to about 0.03%. A mistyped leading digit anywhere would break this.
  const double y = table_sum(kCieY);
  EXPECT_NEAR(table_sum(kCieX) / y, 1.0, 1e-3);
  EXPECT_NEAR(table_sum(kCieZ) / y, 1.0, 1e-3);
}

TEST(SpectrumTables, CieValuesMatchPublishedFiveNanometrePoints) {
  // Values of the CIE 1931 2-degree observer at 5 nm points, which the 1 nm table must contain.
  EXPECT_FLOAT_EQ(kCieX[cie_index(360)], 0.0001299f);
  EXPECT_FLOAT_EQ(kCieY[cie_index(360)], 0.000003917f);
  EXPECT_FLOAT_EQ(kCieZ[cie_index(360)], 0.0006061f);
  EXPECT_FLOAT_EQ(kCieZ[cie_index(445)], 1.7826f);
  EXPECT_FLOAT_EQ(kCieZ[cie_index(450)], 1.77211f);
  EXPECT_FLOAT_EQ(kCieX[cie_index(555)], 0.5120501f);
  EXPECT_FLOAT_EQ(kCieY[cie_index(555)], 1.0f);
  EXPECT_FLOAT_EQ(kCieX[cie_index(600)], 1.0622f);
  EXPECT_FLOAT_EQ(kCieY[cie_index(600)], 0.631f);
  EXPECT_FLOAT_EQ(kCieZ[cie_index(600)], 0.0008f);
  EXPECT_FLOAT_EQ(kCieY[cie_index(700)], 0.004102f);
  EXPECT_FLOAT_EQ(kCieZ[cie_index(650)], 0.0f);
  EXPECT_FLOAT_EQ(kCieX[cie_index(830)], 0.000001251141f);
  EXPECT_FLOAT_EQ(kCieY[cie_index(830)], 0.00000045181f);
  EXPECT_FLOAT_EQ(kCieZ[cie_index(830)], 0.0f);
}

TEST(SpectrumTables, CieTablesAreSmooth) {
  // Each interior value should lie close to a cubic through its four neighbours; a mistyped digit
  // in the first three significant places shows up as a spike. zbar's drop to exactly 0 at
  // 650 nm is the one real kink, so its tail is skipped.
  const float* tables[] = {kCieX, kCieY, kCieZ};
  const int ends[] = {kCieSampleCount - 2, kCieSampleCount - 2, cie_index(648)};
  for (int t = 0; t < 3; ++t) {
    const float* a = tables[t];
    for (int i = 2; i < ends[t]; ++i) {
      double predicted = (-a[i - 2] + 4.0 * a[i - 1] + 4.0 * a[i + 1] - a[i + 2]) / 6.0;
      double scale = std::max(std::fabs(a[i - 1]), std::fabs(a[i + 1]));
      EXPECT_LT(std::fabs(a[i] - predicted), 0.01 * scale) << "table " << t << " at " << 360 + i;
    }
  }
}

TEST(SpectrumTables, CopperWavelengthsStepByFiveHundredthsOfAnElectronVolt) {
  // The copper data is sampled at photon energies 4.15 eV down to 1.40 eV in 0.05 eV steps; this
  // checks every transcribed wavelength against that grid (hc = 1239.84193 eV nm).
  for (int i = 0; i < kCopperSampleCount; ++i) {
    double ev = 1239.84193 / kCopperLambda[i];
    EXPECT_NEAR(ev, 4.15 - 0.05 * i, 1e-5) << "entry " << i;
  }
  EXPECT_FLOAT_EQ(kCopperEta[0], 1.400313f);
  EXPECT_FLOAT_EQ(kCopperEta[kCopperSampleCount - 1], 0.3f);
  EXPECT_FLOAT_EQ(kCopperK[0], 1.662125f);
  EXPECT_FLOAT_EQ(kCopperK[kCopperSampleCount - 1], 5.717f);
}

// ---- XYZ to RGB ----

TEST(RgbFromXyz, UnitVectorsGiveMatrixColumns) {
  const float x[3] = {1, 0, 0}, y[3] = {0, 1, 0}, z[3] = {0, 0, 1};
  expect_rgb_near(rgb_from_xyz(x), 3.240479f, -0.969256f, 0.055648f, 1e-6f);
  expect_rgb_near(rgb_from_xyz(y), -1.537150f, 1.875991f, -0.204043f, 1e-6f);
  expect_rgb_near(rgb_from_xyz(z), -0.498535f, 0.041556f, 1.057311f, 1e-6f);
}

TEST(RgbFromXyz, MixedVectorIsMatrixProduct) {
  // By hand: r = 3.240479*0.5 - 1.537150*0.25 - 0.498535*0.1 = 1.1860985
  //          g = -0.969256*0.5 + 1.875991*0.25 + 0.041556*0.1 = -0.01147465
  //          b = 0.055648*0.5 - 0.204043*0.25 + 1.057311*0.1 = 0.08254435
  const float xyz[3] = {0.5f, 0.25f, 0.1f};
  expect_rgb_near(rgb_from_xyz(xyz), 1.1860985f, -0.01147465f, 0.08254435f, 1e-6f);
}

TEST(RgbFromXyz, D65WhiteIsNeutral) {
  // The matrix's white point is D65 (X, Y, Z) = (0.950456, 1, 1.088754).
  const float d65[3] = {0.950456f, 1.0f, 1.088754f};
  expect_rgb_near(rgb_from_xyz(d65), 1, 1, 1, 1e-3f);
}

// ---- Sampled spectra ----

TEST(RgbFromSampled, XyzOfEqualEnergyWhite) {
  // A flat spectrum of 1 is CIE illuminant E, not the matrix's D65 white, so pbrt-v3 does NOT give
  // (1, 1, 1): its RGB is about (1.202, 0.946, 0.907). Its XYZ is the table sums times
  // 470 / (471 * CIE_Y_integral) -- pbrt-v3's 470/471 step quirk makes Y = 0.99788, not 1.
  const float lambda[2] = {400, 700};
  const float value[2] = {1, 1};
  Rgb rgb = rgb_from_sampled(lambda, value, 2);
  expect_rgb_near(rgb, 1.2023297f, 0.9462152f, 0.9073396f, 2e-5f);

  double xyz[3];
  xyz_from_rgb(rgb, xyz);
  const double scale = 470.0 / (471.0 * kCieYIntegral);
  EXPECT_NEAR(xyz[0], table_sum(kCieX) * scale, 2e-5);
  EXPECT_NEAR(xyz[1], table_sum(kCieY) * scale, 2e-5);
  EXPECT_NEAR(xyz[2], table_sum(kCieZ) * scale, 2e-5);
  EXPECT_NEAR(xyz[1], 470.0 / 471.0, 2e-5);
}

TEST(RgbFromSampled, ValuesAreHeldConstantBeyondTheSamples) {
  // pbrt-v3 clamps: outside the sampled range the nearest end value is used, so one sample, or a
  // flat pair covering only part of 360..830 nm, is the same as a flat spectrum everywhere.
  const float wide_lambda[2] = {300, 900}, wide_value[2] = {0.5f, 0.5f};
  const float narrow_lambda[2] = {500, 600}, narrow_value[2] = {0.5f, 0.5f};
  const float one_lambda[1] = {550}, one_value[1] = {0.5f};
  Rgb wide = rgb_from_sampled(wide_lambda, wide_value, 2);
  expect_rgb_eq(rgb_from_sampled(narrow_lambda, narrow_value, 2), wide);
  expect_rgb_eq(rgb_from_sampled(one_lambda, one_value, 1), wide);
}

TEST(RgbFromSampled, InterpolatesLinearlyBetweenSamples) {
  // A ramp given by its two end points equals the same ramp given at every CIE wavelength.
  const float ends_lambda[2] = {360, 830}, ends_value[2] = {0, 1};
  std::vector<float> lambda = cie_lambdas();
  std::vector<float> value(lambda.size());
  for (size_t i = 0; i < lambda.size(); ++i) value[i] = (lambda[i] - 360) / 470;
  Rgb from_ends = rgb_from_sampled(ends_lambda, ends_value, 2);
  Rgb from_all = rgb_from_sampled(lambda.data(), value.data(), lambda.size());
  expect_rgb_near(from_ends, from_all.r, from_all.g, from_all.b, 1e-5f);
}

TEST(RgbFromSampled, UnsortedSamplesGiveSameRgbAsSorted) {
  std::vector<float> lambda(kCopperLambda, kCopperLambda + kCopperSampleCount);
  std::vector<float> value(kCopperK, kCopperK + kCopperSampleCount);
  Rgb sorted = rgb_from_sampled(lambda.data(), value.data(), lambda.size());
  // A fixed shuffle: reverse, then rotate, keeping pairs together.
  std::reverse(lambda.begin(), lambda.end());
  std::reverse(value.begin(), value.end());
  std::rotate(lambda.begin(), lambda.begin() + 17, lambda.end());
  std::rotate(value.begin(), value.begin() + 17, value.end());
  expect_rgb_eq(rgb_from_sampled(lambda.data(), value.data(), lambda.size()), sorted);
}

TEST(RgbFromSampled, RepeatedWavelengthsAreOrderedByValue) {
  // A step at 500 nm written with a repeated wavelength. Unsorted input is sorted by (wavelength,
  // value), as pbrt-v3's pair sort does, so it equals the sorted spelling; neither divides by a
  // zero-width segment.
  const float unsorted_lambda[4] = {500, 700, 500, 400}, unsorted_value[4] = {2, 2, 1, 1};
  const float sorted_lambda[4] = {400, 500, 500, 700}, sorted_value[4] = {1, 1, 2, 2};
  Rgb sorted = rgb_from_sampled(sorted_lambda, sorted_value, 4);
  expect_rgb_eq(rgb_from_sampled(unsorted_lambda, unsorted_value, 4), sorted);
  EXPECT_TRUE(std::isfinite(sorted.r) && std::isfinite(sorted.g) && std::isfinite(sorted.b));
}

TEST(RgbFromSampled, NoSamplesGiveBlack) {
  expect_rgb_eq(rgb_from_sampled(nullptr, nullptr, 0), Rgb{});
}

// ---- Blackbody ----

TEST(RgbFromBlackbody, SixtyFiveHundredKelvinIsNearNeutral) {
  Rgb c = rgb_from_blackbody(6500, 1);
  expect_rgb_near(c, 0.9222190f, 0.8694962f, 0.9152171f, 2e-5f);
  float lo = std::min({c.r, c.g, c.b}), hi = std::max({c.r, c.g, c.b});
  EXPECT_GT(lo, 0.85f * hi);
}

TEST(RgbFromBlackbody, ScaleMultipliesLinearly) {
  Rgb one = rgb_from_blackbody(6500, 1);
  Rgb scaled = rgb_from_blackbody(6500, 3.5f);
  expect_rgb_eq(scaled, Rgb{one.r * 3.5f, one.g * 3.5f, one.b * 3.5f});
  expect_rgb_eq(rgb_from_blackbody(6500, 0), Rgb{});
}

TEST(RgbFromBlackbody, CoolerBodiesAreRedder) {
  Rgb c = rgb_from_blackbody(2700, 1);
  expect_rgb_near(c, 0.5334942f, 0.2215708f, 0.0529018f, 2e-5f);
  EXPECT_GT(c.r, c.g);
  EXPECT_GT(c.g, c.b);
}

TEST(RgbFromBlackbody, PeakIsNormalizedToOne) {
  // At 5000 K the Wien peak (579.6 nm) lies inside the CIE range, and no normalized value can
  // exceed 1, so Y cannot exceed that of a flat spectrum of 1 (470/471); near the peak it is close.
  double xyz[3];
  xyz_from_rgb(rgb_from_blackbody(5000, 1), xyz);
  EXPECT_LT(xyz[1], 470.0 / 471.0);
  EXPECT_GT(xyz[1], 0.8);
}

TEST(RgbFromBlackbody, NonPositiveOrNonFiniteTemperatureIsBlack) {
  expect_rgb_eq(rgb_from_blackbody(0, 1), Rgb{});
  expect_rgb_eq(rgb_from_blackbody(-100, 1), Rgb{});
  expect_rgb_eq(rgb_from_blackbody(std::nanf(""), 1), Rgb{});
  expect_rgb_eq(rgb_from_blackbody(INFINITY, 1), Rgb{});
}

// ---- .spd files ----

TEST(ParseSpd, AcceptsCommentsAndCrlf) {
  std::vector<float> lambda, value;
  SpdError error;
  const char* text = "# measured\r\n400 0.5 # first\r\n500\t.75\r\n\r\n+600 1e0#tight comment\r\n";
  ASSERT_TRUE(parse_spd(text, &lambda, &value, &error)) << error.message;
  EXPECT_EQ(lambda, (std::vector<float>{400, 500, 600}));
  EXPECT_EQ(value, (std::vector<float>{0.5f, 0.75f, 1.0f}));
}

TEST(ParseSpd, AcceptsAnyOrderAndSignAsPbrtV3Does) {
  std::vector<float> lambda, value;
  // Also starts with a UTF-8 byte order mark, which is skipped as pbrt-v3 (with a warning) does.
  const std::string text = std::string("\xEF\xBB\xBF") + "700 -0.5\n-1 2\n1e-60 3";
  ASSERT_TRUE(parse_spd(text, &lambda, &value, nullptr));
  EXPECT_EQ(lambda, (std::vector<float>{700, -1, 0}));  // 1e-60 underflows float to 0, like atof
  EXPECT_EQ(value, (std::vector<float>{-0.5f, 2, 3}));
}

TEST(ParseSpd, RejectsOddCountAtTheUnpairedValue) {
  std::vector<float> lambda, value;
  SpdError error;
  EXPECT_FALSE(parse_spd("400 0.5\n500 0.7\n  600   # no value\n", &lambda, &value, &error));
  EXPECT_EQ(error.line, 3);
  EXPECT_EQ(error.column, 3);
  EXPECT_EQ(error.message, "odd number of values (5): the last wavelength has no value");
  EXPECT_TRUE(lambda.empty());
  EXPECT_TRUE(value.empty());
}

TEST(ParseSpd, RejectsNonNumberAtItsLineAndColumn) {
  std::vector<float> lambda, value;
  SpdError error;
  EXPECT_FALSE(parse_spd("400 0.5\n500 abc 600 1\n", &lambda, &value, &error));
  EXPECT_EQ(error.line, 2);
  EXPECT_EQ(error.column, 5);
  EXPECT_EQ(error.message, "'abc' is not a number");
  EXPECT_TRUE(lambda.empty());
}

TEST(ParseSpd, ColumnsRestartAfterCrlfAndLoneCr) {
  std::vector<float> lambda, value;
  SpdError error;
  EXPECT_FALSE(parse_spd("400 0.5\r\n500\t1.5x", &lambda, &value, &error));
  EXPECT_EQ(error.line, 2);
  EXPECT_EQ(error.column, 5);
  EXPECT_EQ(error.message, "'1.5x' is not a number");
  EXPECT_FALSE(parse_spd("400 0.5\r500 1\r\r 0x10 2", &lambda, &value, &error));
  EXPECT_EQ(error.line, 4);
  EXPECT_EQ(error.column, 2);
}

TEST(ParseSpd, RejectsNanInfAndMalformedNumbers) {
  std::vector<float> lambda, value;
  SpdError error;
  for (const char* bad : {"nan", "inf", "-inf", "1e", "1.2.3", "+-1", "-", ".", "e5", "1,5"}) {
    std::string text = std::string("400 ") + bad;
    EXPECT_FALSE(parse_spd(text, &lambda, &value, &error)) << bad;
    EXPECT_EQ(error.line, 1) << bad;
    EXPECT_EQ(error.column, 5) << bad;
  }
}

TEST(ParseSpd, RejectsNumbersBeyondFloatRange) {
  std::vector<float> lambda, value;
  SpdError error;
  EXPECT_FALSE(parse_spd("400 1e39", &lambda, &value, &error));
  EXPECT_EQ(error.message, "'1e39' is out of range for a float");
  EXPECT_FALSE(parse_spd("400 -1e400", &lambda, &value, &error));
  EXPECT_EQ(error.column, 5);
}

TEST(ParseSpd, RejectsFileWithoutNumbersAtItsEnd) {
  std::vector<float> lambda, value;
  SpdError error;
  EXPECT_FALSE(parse_spd("", &lambda, &value, &error));
  EXPECT_EQ(error.line, 1);
  EXPECT_EQ(error.column, 1);
  EXPECT_FALSE(parse_spd("# only a comment\n  ", &lambda, &value, &error));
  EXPECT_EQ(error.line, 2);
  EXPECT_EQ(error.column, 3);
  EXPECT_EQ(error.message, "no values: expected (wavelength, value) pairs");
}

TEST(ParseSpd, ParsedSamplesFeedRgbFromSampled) {
  std::vector<float> lambda, value;
  ASSERT_TRUE(parse_spd("300 0.5\n900 0.5\n", &lambda, &value, nullptr));
  const float flat_lambda[1] = {550}, flat_value[1] = {0.5f};
  expect_rgb_eq(rgb_from_sampled(lambda.data(), value.data(), lambda.size()),
                rgb_from_sampled(flat_lambda, flat_value, 1));
}

// ---- Copper ----

TEST(Copper, EtaMatchesPbrtV3MetalDefault) {
  Rgb eta = copper_eta_rgb();
  expect_rgb_near(eta, 0.2f, 0.92f, 1.1f, 0.01f);  // the figures usually quoted
  expect_rgb_near(eta, 0.1999897f, 0.9220858f, 1.0998763f, 2e-5f);
}

TEST(Copper, KMatchesPbrtV3MetalDefault) {
  Rgb k = copper_k_rgb();
  expect_rgb_near(k, 3.9f, 2.45f, 2.14f, 0.01f);
  expect_rgb_near(k, 3.9046382f, 2.4476332f, 2.1376510f, 5e-5f);
}

}  // namespace
}  // namespace pbrtc
