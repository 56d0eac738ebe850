// compiler/medium_presets.h — the measured scattering coefficients pbrt-v3 accepts by name.
//
// A medium's "preset" and the subsurface material's "name" select one of
// these; pbrtc writes the coefficients into the archive, so the runtime has
// no table. Lookup is by exact name, as pbrt-v3's is ("Skin1", "Regular Milk").
#pragma once

#include <string>
#include <string_view>

namespace pbrtc {

struct MeasuredMedium {
  const char* name;
  float sigma_prime_s[3];  // reduced scattering coefficient, RGB, mm^-1
  float sigma_a[3];        // absorption coefficient, RGB, mm^-1
};

// The preset called `name`, or nullptr.
const MeasuredMedium* find_measured_medium(std::string_view name);

// "Apple, Chicken1, ..." for messages.
std::string measured_medium_names();

}  // namespace pbrtc
