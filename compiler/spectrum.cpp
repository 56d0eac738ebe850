// compiler/spectrum.cpp — spectra to pbrt-v3 RGB; .spd text to samples. See spectrum.h.
#include "compiler/spectrum.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <utility>

namespace pbrtc {

namespace {

// ---- Resampling and integration ----

// Orders samples by wavelength, then value. NaN sorts after every number so the order is a strict
// weak ordering even on garbage input (std::sort on a broken ordering is undefined behaviour).
bool less_total(float a, float b) {
  if (std::isnan(a)) return false;
  if (std::isnan(b)) return true;
  return a < b;
}

bool sample_less(const std::pair<float, float>& a, const std::pair<float, float>& b) {
  if (less_total(a.first, b.first)) return true;
  if (less_total(b.first, a.first)) return false;
  return less_total(a.second, b.second);
}

// The piecewise-linear function through the sorted samples, evaluated at l and held constant
// outside [lambda[0], lambda[n-1]]. Picks the last segment start <= l, so with repeated wavelengths
// the segment used never has zero width and there is no division by zero.
float interpolate_sorted(const float* lambda, const float* value, size_t n, float l) {
  if (l <= lambda[0]) return value[0];
  if (l >= lambda[n - 1]) return value[n - 1];
  // Here n >= 2 and lambda[0] < l < lambda[n-1], so the upper bound lies in [1, n-1].
  size_t hi = static_cast<size_t>(std::upper_bound(lambda, lambda + n, l) - lambda);
  size_t i = std::min(hi - 1, n - 2);
  float t = (l - lambda[i]) / (lambda[i + 1] - lambda[i]);
  return (1 - t) * value[i] + t * value[i + 1];
}

// XYZ of sorted samples. pbrt-v3 sums over the 471 CIE wavelengths and multiplies by
// (830 - 360) / (CIE_Y_integral * 471): a Riemann sum whose step is 470/471 nm rather than the
// table's 1 nm, so a flat spectrum of 1 has Y = 470/471, not 1. That quirk is reproduced on
// purpose.
void xyz_from_sorted(const float* lambda, const float* value, size_t n, float xyz[3]) {
  double sum[3] = {0, 0, 0};
  for (int i = 0; i < kCieSampleCount; ++i) {
    float v = interpolate_sorted(lambda, value, n, kCieLambdaFirst + static_cast<float>(i));
    sum[0] += static_cast<double>(v) * kCieX[i];
    sum[1] += static_cast<double>(v) * kCieY[i];
    sum[2] += static_cast<double>(v) * kCieZ[i];
  }
  const double scale =
      (kCieLambdaLast - kCieLambdaFirst) / (kCieYIntegral * static_cast<double>(kCieSampleCount));
  for (int c = 0; c < 3; ++c) xyz[c] = static_cast<float>(sum[c] * scale);
}

// ---- Blackbody ----

// Planck's law, W / (m^2 sr m), with the CODATA 2010 constants pbrt-v3 uses. expm1 keeps
// precision when hc / (lambda k T) is small (very hot bodies); pbrt-v3's exp() - 1 agrees wherever
// it is exact.
double planck(double lambda_nm, double temperature) {
  constexpr double kC = 299792458;       // speed of light, m/s
  constexpr double kH = 6.62606957e-34;  // Planck constant, J s
  constexpr double kKb = 1.3806488e-23;  // Boltzmann constant, J/K
  const double l = lambda_nm * 1e-9;
  const double l5 = (l * l) * (l * l) * l;
  return (2 * kH * kC * kC) / (l5 * std::expm1((kH * kC) / (l * kKb * temperature)));
}

// ---- .spd tokens ----

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

bool is_number_char(char c) {
  return (c >= '0' && c <= '9') || c == '.' || c == 'e' || c == 'E' || c == '+' || c == '-';
}

// Shown in messages; a long run of junk (a binary file) is cut so the message stays one line.
std::string quote_token(std::string_view token) {
  constexpr size_t kMaxShown = 32;
  std::string shown(token.substr(0, kMaxShown));
  if (token.size() > kMaxShown) shown += "...";
  return "'" + shown + "'";
}

enum class NumberStatus { kOk, kNotANumber, kOutOfRange };

// Plain decimal numbers only: an optional sign, digits with an optional '.', an optional exponent.
// from_chars takes no leading '+', so it is stripped first (but "+-1" stays invalid). Hex floats,
// "inf" and "nan" never get here: their letters fail is_number_char.
NumberStatus parse_number(std::string_view token, float* out) {
  for (char c : token) {
    if (!is_number_char(c)) return NumberStatus::kNotANumber;
  }
  std::string_view digits = token;
  if (!digits.empty() && digits[0] == '+') {
    digits.remove_prefix(1);
    if (!digits.empty() && (digits[0] == '+' || digits[0] == '-')) return NumberStatus::kNotANumber;
  }
  if (digits.empty()) return NumberStatus::kNotANumber;
  // Parse as double so that a value too small for float rounds to 0 (as pbrt-v3's atof does)
  // while one too large for float is caught below.
  double d = 0;
  const char* end = digits.data() + digits.size();
  std::from_chars_result r = std::from_chars(digits.data(), end, d, std::chars_format::general);
  if (r.ec == std::errc::result_out_of_range) return NumberStatus::kOutOfRange;
  if (r.ec != std::errc() || r.ptr != end) return NumberStatus::kNotANumber;
  if (!std::isfinite(d) || std::fabs(d) > std::numeric_limits<float>::max()) {
    return NumberStatus::kOutOfRange;
  }
  *out = static_cast<float>(d);
  return NumberStatus::kOk;
}

}  // namespace

// ---- Conversions ----

Rgb rgb_from_xyz(const float xyz[3]) {
  // pbrt-v3's XYZToRGB coefficients (sRGB primaries, D65 white), applied in float as pbrt-v3 does.
  Rgb rgb;
  rgb.r = 3.240479f * xyz[0] - 1.537150f * xyz[1] - 0.498535f * xyz[2];
  rgb.g = -0.969256f * xyz[0] + 1.875991f * xyz[1] + 0.041556f * xyz[2];
  rgb.b = 0.055648f * xyz[0] - 0.204043f * xyz[1] + 1.057311f * xyz[2];
  return rgb;
}

Rgb rgb_from_sampled(const float* lambda, const float* value, size_t n) {
  if (n == 0 || lambda == nullptr || value == nullptr) return Rgb{};
  float xyz[3];
  if (std::is_sorted(lambda, lambda + n, less_total)) {
    xyz_from_sorted(lambda, value, n, xyz);
  } else {
    // pbrt-v3 sorts (wavelength, value) pairs, so equal wavelengths end up ordered by value; that
    // decides which side of a jump a CIE wavelength falling exactly on it sees.
    std::vector<std::pair<float, float>> samples(n);
    for (size_t i = 0; i < n; ++i) samples[i] = {lambda[i], value[i]};
    std::sort(samples.begin(), samples.end(), sample_less);
    std::vector<float> sorted_lambda(n), sorted_value(n);
    for (size_t i = 0; i < n; ++i) {
      sorted_lambda[i] = samples[i].first;
      sorted_value[i] = samples[i].second;
    }
    xyz_from_sorted(sorted_lambda.data(), sorted_value.data(), n, xyz);
  }
  return rgb_from_xyz(xyz);
}

Rgb rgb_from_blackbody(float temperature_kelvin, float scale) {
  // pbrt-v3 turns T <= 0 into 0 / 0 = NaN; black is the sane reading of "no emission".
  if (!(temperature_kelvin > 0) || !std::isfinite(temperature_kelvin)) return Rgb{};
  const double t = temperature_kelvin;
  // Wien's displacement law gives the peak wavelength; dividing by the radiance there makes the
  // spectrum's maximum 1, so "blackbody [T 1]" has roughly unit brightness at any temperature.
  constexpr double kWienB = 2.8977721e-3;  // m K, the value pbrt-v3 uses
  const double peak = planck(kWienB / t * 1e9, t);
  float lambda[kCieSampleCount];
  float value[kCieSampleCount];
  for (int i = 0; i < kCieSampleCount; ++i) {
    lambda[i] = kCieLambdaFirst + static_cast<float>(i);
    value[i] = static_cast<float>(planck(lambda[i], t) / peak);
  }
  Rgb rgb = rgb_from_sampled(lambda, value, kCieSampleCount);
  rgb.r *= scale;
  rgb.g *= scale;
  rgb.b *= scale;
  return rgb;
}

// ---- Spectral data files ----

bool parse_float_file(std::string_view text, std::vector<float>* out, SpdError* error,
                      int* end_line, int* end_column, int* last_number_line,
                      int* last_number_column) {
  std::vector<float>& numbers = *out;
  numbers.clear();
  int line = 1, column = 1;
  int last_line = 0, last_column = 0;  // where the most recent number started
  auto fail = [&](int at_line, int at_column, std::string message) {
    if (error != nullptr) *error = SpdError{at_line, at_column, std::move(message)};
    return false;
  };

  size_t i = 0;
  // A UTF-8 byte order mark is an editor's artefact, not text; pbrt-v3 only warns about it.
  if (text.substr(0, 3) == "\xEF\xBB\xBF") {
    i = 3;
    column = 4;
  }
  while (i < text.size()) {
    char c = text[i];
    if (c == '\n' || c == '\r') {
      // LF, CRLF and a lone CR each end one line.
      if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
      ++i;
      ++line;
      column = 1;
    } else if (is_space(c)) {
      ++i;
      ++column;
    } else if (c == '#') {
      while (i < text.size() && text[i] != '\n' && text[i] != '\r') {
        ++i;
        ++column;
      }
    } else {
      // A token runs to the next space or comment, so "1.5x" is one bad token rather than a
      // number followed by junk (pbrt-v3 would read 1.5 and warn about the 'x').
      size_t start = i;
      while (i < text.size() && !is_space(text[i]) && text[i] != '#') ++i;
      std::string_view token = text.substr(start, i - start);
      float v = 0;
      switch (parse_number(token, &v)) {
        case NumberStatus::kNotANumber:
          return fail(line, column, quote_token(token) + " is not a number");
        case NumberStatus::kOutOfRange:
          return fail(line, column, quote_token(token) + " is out of range for a float");
        case NumberStatus::kOk:
          break;
      }
      numbers.push_back(v);
      last_line = line;
      last_column = column;
      column += static_cast<int>(token.size());
    }
  }

  *end_line = line;
  *end_column = column;
  *last_number_line = last_line;
  *last_number_column = last_column;
  return true;
}

bool parse_spd(std::string_view text, std::vector<float>* lambda, std::vector<float>* value,
               SpdError* error) {
  lambda->clear();
  value->clear();
  std::vector<float> numbers;
  int line, column, last_line, last_column;
  if (!parse_float_file(text, &numbers, error, &line, &column, &last_line, &last_column))
    return false;
  auto fail = [&](int at_line, int at_column, std::string message) {
    if (error != nullptr) *error = SpdError{at_line, at_column, std::move(message)};
    return false;
  };
  if (numbers.empty()) {
    return fail(line, column, "no values: expected (wavelength, value) pairs");
  }
  if (numbers.size() % 2 != 0) {
    return fail(last_line, last_column,
                "odd number of values (" + std::to_string(numbers.size()) +
                    "): the last wavelength has no value");
  }
  lambda->reserve(numbers.size() / 2);
  value->reserve(numbers.size() / 2);
  for (size_t k = 0; k < numbers.size(); k += 2) {
    lambda->push_back(numbers[k]);
    value->push_back(numbers[k + 1]);
  }
  return true;
}

// ---- Metal's default ----

Rgb copper_eta_rgb() {
  return rgb_from_sampled(kCopperLambda, kCopperEta, static_cast<size_t>(kCopperSampleCount));
}

Rgb copper_k_rgb() {
  return rgb_from_sampled(kCopperLambda, kCopperK, static_cast<size_t>(kCopperSampleCount));
}

}  // namespace pbrtc
