// runtime/core/approx_angles.h — a direction's spherical angles to within about 1e-4 radians,
// for hints only (which cache lines a lookup will read), never for a value anything renders:
// libm's acos and atan2 cost more than the rest of such a hint. Exact angles: vec.h's
// spherical_theta and spherical_phi.
#pragma once

#include <algorithm>
#include <cmath>

#include "runtime/core/math.h"
#include "runtime/core/vec.h"

namespace rt {

// theta = acos(w.z) in [0, pi] for a unit w: Abramowitz and Stegun, Handbook of Mathematical
// Functions, 4.4.45 (|error| <= 6.7e-5 on [0, 1]), mirrored for negative z.
inline float approx_spherical_theta(Vec3 w) {
  const float z = std::min(std::fabs(w.z), 1.f);
  const float t =
      std::sqrt(1 - z) * (1.5707288f + z * (-0.2121144f + z * (0.0742610f + z * -0.0187293f)));
  return w.z < 0 ? kPi - t : t;
}

// phi = atan2(w.y, w.x) in [0, 2 pi): atan on [0, 1] by the polynomial of NVIDIA's Cg
// reference implementation of atan2 (Cg Toolkit documentation; |error| about 1e-5), then
// unfolded by octant.
inline float approx_spherical_phi(Vec3 w) {
  const float ax = std::fabs(w.x), ay = std::fabs(w.y), hi = std::max(ax, ay);
  const float a = hi > 0 ? std::min(ax, ay) / hi : 0, a2 = a * a;
  float p = (((((-0.013480470f * a2 + 0.057477314f) * a2 - 0.121239071f) * a2 + 0.195635925f) * a2 -
              0.332994597f) *
                 a2 +
             0.999995630f) *
            a;
  if (ay > ax) p = kPiOver2 - p;
  if (w.x < 0) p = kPi - p;
  return w.y < 0 ? 2 * kPi - p : p;
}

}  // namespace rt
