// format/texel_format.h — the stored texel formats of ImageRecord (ARCHIVE.md, images).
//
// One definition of each format's bytes, shared by the writer (pbrtc
// --texture-precision), the dump and the runtime, so that all three agree
// bit for bit:
//   f32    the float's bytes;
//   f16    IEEE binary16, rounded to nearest, ties to even; infinities and
//          NaNs kept (a NaN keeps its sign and top mantissa bits, quiet);
//   unorm8 linear: byte q stands for q / 255 (division, not a multiply by
//          1/255, so every reader gets the same float); writing rounds
//          v * 255 to nearest, ties away from zero.
// The encoders never fail: callers check representability first with
// texel_representable() (pbrtc refuses an image that does not fit).
#pragma once

#include <cstddef>
#include <cstdint>

#include "format/archive.h"

namespace pbrta {

// Bytes per channel value of a PixelFormat (0 for an unknown format).
uint32_t texel_bytes(uint32_t format);

// "f32", "f16", "unorm8", or "format N".
const char* texel_format_name(uint32_t format);

// The largest finite half, and the smallest magnitude that rounds to infinity.
inline constexpr float kHalfMax = 65504.f;
inline constexpr float kHalfOverflow = 65520.f;

uint16_t float_to_half(float v);
float half_to_float(uint16_t h);
uint8_t float_to_unorm8(float v);  // v in [0, 1]
inline float unorm8_to_float(uint8_t q) {
  return float(q) / 255.f;
}

// Whether v survives encoding in format as the format promises: f32 always; f16 unless v is
// finite with |v| >= kHalfOverflow (it would become infinite); unorm8 when 0 <= v <= 1 (not
// NaN).
bool texel_representable(uint32_t format, float v);

// count values to format's bytes at out (count * texel_bytes(format) bytes), and back.
void encode_texels(uint32_t format, const float* in, size_t count, uint8_t* out);
void decode_texels(uint32_t format, const uint8_t* in, size_t count, float* out);

}  // namespace pbrta
