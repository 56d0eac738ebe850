// compiler/spectrum.h — pbrt-v3 spectra resolved to the RGB its default build renders with.
//
// pbrt-v3 is built with RGBSpectrum by default, so every spectral value in a scene (a "spectrum"
// parameter given as wavelength/value pairs or as an .spd file, a "blackbody" parameter, metal's
// measured copper default) becomes a linear RGB triple when the scene is loaded. This module
// reproduces that conversion: the samples are sorted, linearly interpolated onto the CIE 1931
// 2-degree observer's 1 nm grid from 360 to 830 nm (held constant beyond the first and last
// sample), summed against xbar, ybar, zbar, scaled as pbrt-v3 scales them, and taken from XYZ to
// RGB with pbrt-v3's matrix. Results match pbrt-v3 up to float rounding (sums here run in double,
// pbrt-v3's in float).
//
// Failure: the conversions never fail and never throw; input pbrt-v3 would crash on or turn into
// NaN (no samples, a non-positive or non-finite temperature) gives black instead, and callers that
// want to report such input check it before calling. parse_spd is the only function that can
// reject input: it returns false and fills an SpdError with a message and the 1-based line and
// column of the offending token. Everything here is pure and thread-safe; the tables are constant.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace pbrtc {

// ---- Conversions ----

// Linear RGB with pbrt-v3's primaries and white point (sRGB primaries, D65 white).
struct Rgb {
  float r = 0, g = 0, b = 0;
};

// pbrt-v3's XYZToRGB: a fixed 3x3 matrix, no clamping (out-of-gamut colours give negative
// channels).
Rgb rgb_from_xyz(const float xyz[3]);

// pbrt-v3's RGBSpectrum::FromSampled. lambda (nm) and value are n parallel samples in any order;
// equal wavelengths are allowed and ordered by value, as pbrt-v3's sort does. n == 0 gives black.
Rgb rgb_from_sampled(const float* lambda, const float* value, size_t n);

// pbrt-v3's "blackbody" parameter [temperature scale]: Planck's law at the CIE wavelengths,
// divided by its value at the Wien peak so the spectrum's maximum is 1, converted with
// rgb_from_sampled, times scale. A temperature that is not a positive finite number gives black.
Rgb rgb_from_blackbody(float temperature_kelvin, float scale);

// ---- Spectral data files ----

struct SpdError {
  int line = 0, column = 0;  // 1-based; column counts bytes
  std::string message;
};

// Reads an .spd file's text: whitespace-separated numbers, '#' starting a comment to the end of
// the line, read as (wavelength, value) pairs. Line ends may be LF, CRLF or CR. Like pbrt-v3, any
// finite pairs are accepted: wavelengths need not be increasing or positive (rgb_from_sampled
// sorts them). Stricter than pbrt-v3 (which warns and goes on, or silently drops a trailing
// value), this rejects a token that is not a plain decimal number (including "nan" and "inf"), a
// number that overflows float, an odd count of numbers (the error points at the unpaired last
// one) and a file with no numbers at all (the error points at the end of the text). On failure
// lambda and value are left empty and *error is filled (if not null).
bool parse_spd(std::string_view text, std::vector<float>* lambda, std::vector<float>* value,
               SpdError* error);

// The number reading under parse_spd (pbrt-v3's ReadFloatFile rules, with the strictness above),
// for other float files such as the realistic camera's lens files. On success also reports where
// the text ended and where the last number started, for messages about the count.
bool parse_float_file(std::string_view text, std::vector<float>* numbers, SpdError* error,
                      int* end_line, int* end_column, int* last_number_line,
                      int* last_number_column);

// ---- Metal's default ----

// pbrt-v3's metal material default: the measured copper eta and k tables through rgb_from_sampled.
Rgb copper_eta_rgb();
Rgb copper_k_rgb();

// ---- Tables (compiler/spectrum_tables.cpp) ----
// Exposed for tests and for other modules that need the same data. Sizes are checked where the
// arrays are defined; here the bounds are omitted on purpose, so that a definition with too few
// entries fails to compile instead of being zero-filled.

constexpr int kCieSampleCount = 471;    // 360..830 nm at 1 nm
constexpr float kCieLambdaFirst = 360;  // nm
constexpr float kCieLambdaLast = 830;   // nm
// pbrt-v3's CIE_Y_integral: the sum of ybar over the table (its integral at 1 nm spacing).
constexpr double kCieYIntegral = 106.856895;
extern const float kCieX[];  // xbar, kCieSampleCount entries
extern const float kCieY[];  // ybar
extern const float kCieZ[];  // zbar

constexpr int kCopperSampleCount = 56;
extern const float kCopperLambda[];  // nm, increasing
extern const float kCopperEta[];     // n
extern const float kCopperK[];       // k

}  // namespace pbrtc
