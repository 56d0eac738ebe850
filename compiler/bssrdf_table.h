// compiler/bssrdf_table.h — pbrt-v3's tabulated photon-beam-diffusion BSSRDF profile.
//
// The subsurface and kdsubsurface materials scatter light under the surface
// by a radial profile Sr(r) that depends on the albedo rho and the optical
// radius only, for a given phase asymmetry g and relative index eta. pbrt-v3
// tabulates it (book section 15.5) at 100 albedos and 64 radii; pbrtc does
// the same once per material and stores the arrays as the material's derived
// parameters (format/bssrdf_table.h), so the runtime computes nothing.
#pragma once

#include <vector>

#include "compiler/diagnostics.h"
#include "compiler/scene_desc.h"

namespace pbrtc {

struct BssrdfTable {
  std::vector<float> rho;      // albedo samples, increasing in [0, 1]
  std::vector<float> radius;   // optical radius samples, increasing from 0
  std::vector<float> profile;  // rho.size() rows of radius.size(): 2 pi r Sr(r)
  std::vector<float> rho_eff;  // per albedo: the profile's integral over r
  std::vector<float> cdf;      // per row: the running integral of the profile over r
};

void compute_bssrdf_table(float g, float eta, BssrdfTable* table);

// For a subsurface or kdsubsurface material: resolves the subsurface
// material's measured preset "name" (its coefficients into sigma_a/sigma_s
// unless given, and g = 0, as pbrt-v3 does since the presets are reduced
// coefficients), then stores the table for the material's g and eta. False
// (after an error at the name) for an unknown preset.
bool derive_subsurface(Entity* material, Loc name_loc, Diagnostics* diag);

}  // namespace pbrtc
