// runtime/material/bxdf_flags.h — the vocabulary every lobe type shares:
// pbrt-v3's BxDFType bits and the transport direction.
//
// Kept apart from bxdf.h so lobe payloads that Bxdf carries (DisneyLobe,
// disney_bxdf.h) can use it without including Bxdf itself.
#pragma once

#include <cstdint>

namespace rt {

enum BxdfFlags : uint8_t {
  kReflection = 1,
  kTransmission = 2,
  kDiffuse = 4,
  kGlossy = 8,
  kSpecular = 16,
  kAllBxdf = 31
};

// Radiance: paths traced from the camera (non-symmetric refraction scaling
// applies); importance: paths from lights.
enum class TransportMode : uint8_t { kRadiance, kImportance };

}  // namespace rt
