// runtime/material/fresnel.h — Fresnel reflectance (book section 8.2.1).
//
// fr_dielectric is the unpolarised reflectance of a dielectric interface; a
// negative cos_theta_i means the ray arrives from the eta_t side, so the
// indices swap (and total internal reflection gives 1). fr_conductor is the
// general dielectric-conductor formula with complex index eta + i k, per RGB
// channel. Fresnel is a small tagged value a lobe carries by value: no-op
// (always 1, for mirrors), dielectric, or conductor.
#pragma once

#include <cstdint>

#include "runtime/core/rgb.h"

namespace rt {

float fr_dielectric(float cos_theta_i, float eta_i, float eta_t);
Rgb fr_conductor(float cos_theta_i, Rgb eta_i, Rgb eta_t, Rgb k);

enum class FresnelKind : uint8_t { kNoOp, kDielectric, kConductor };

struct Fresnel {
  FresnelKind kind = FresnelKind::kNoOp;
  float eta_i = 1, eta_t = 1;                   // dielectric
  Rgb cond_eta_i{1}, cond_eta_t{1}, cond_k{0};  // conductor

  static Fresnel no_op() { return Fresnel{}; }
  static Fresnel dielectric(float eta_i, float eta_t) {
    Fresnel f;
    f.kind = FresnelKind::kDielectric;
    f.eta_i = eta_i;
    f.eta_t = eta_t;
    return f;
  }
  static Fresnel conductor(Rgb eta_i, Rgb eta_t, Rgb k) {
    Fresnel f;
    f.kind = FresnelKind::kConductor;
    f.cond_eta_i = eta_i;
    f.cond_eta_t = eta_t;
    f.cond_k = k;
    return f;
  }

  Rgb evaluate(float cos_theta_i) const {
    switch (kind) {
      case FresnelKind::kDielectric:
        return Rgb(fr_dielectric(cos_theta_i, eta_i, eta_t));
      case FresnelKind::kConductor:
        // A conductor reflects the same from either side: pbrt-v3 passes |cos|.
        return fr_conductor(std::fabs(cos_theta_i), cond_eta_i, cond_eta_t, cond_k);
      case FresnelKind::kNoOp:
        break;
    }
    return Rgb(1);
  }
};

}  // namespace rt
