// runtime/film/filter.h — pbrt-v3's pixel reconstruction filters.
//
// A Filter is plain data (a type tag and its parameters) evaluated by a
// switch, so the film's hot loop makes no virtual call. evaluate(p) is the
// exact filter value at offset p (in pixels) from the filter centre and 0
// outside [-radius, radius]^2. The film itself, like pbrt-v3, samples the
// filter once into a 16x16 table over one quadrant (Film::kFilterTableSize)
// and splats with table lookups, so images match pbrt-v3's bit for bit in
// their weights. make_filter reads the scene's filter entity with pbrt-v3's
// defaults (box 0.5, the others 2, sinc 4) and fails with a message for a
// type or radius it cannot use.
#pragma once

#include <cstdint>
#include <string>

#include "format/scene_archive.h"
#include "runtime/core/vec.h"

namespace rt {

struct Filter {
  enum class Type : uint8_t { kBox, kTriangle, kGaussian, kMitchell, kSinc };
  Type type = Type::kBox;
  Vec2 radius{0.5f, 0.5f};
  float alpha = 2, exp_x = 0, exp_y = 0;  // gaussian: exp_* = exp(-alpha radius^2)
  float b = 1.f / 3, c = 1.f / 3;         // mitchell
  float tau = 3;                          // sinc (lanczos window)
  float evaluate(Vec2 p) const;           // p relative to the filter centre, in pixels
};

// Fills exp_x / exp_y of a gaussian from alpha and radius (make_filter does it;
// tests that build a Filter by hand call it too).
void finish_gaussian(Filter* filter);

// The archive's scene().filter entity as a Filter.
bool make_filter(const pbrta::SceneArchive& archive, Filter* out, std::string* error);

}  // namespace rt
