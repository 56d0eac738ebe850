// format/bssrdf_table.h — the subsurface materials' BSSRDF profile table as the archive holds it.
//
// pbrt-v3's subsurface and kdsubsurface materials scatter under the surface by
// a tabulated photon-beam-diffusion profile (book section 15.5) that depends
// only on the material's g and eta. pbrtc computes it (compiler/bssrdf_table.h)
// and stores it as derived parameters of the material entity (ARCHIVE.md,
// "Derived parameters"; archive version 2.1):
//   bssrdfrho      float[n]    albedo samples, increasing, in [0, 1]
//   bssrdfradius   float[m]    optical radius samples, increasing, the first 0
//   bssrdfprofile  float[n*m]  row i (albedo i), column j: 2 pi r Sr(r) at unit extinction
//   bssrdfrhoeff   float[n]    per albedo, the profile's integral over the radius
//   bssrdfcdf      float[n*m]  per row, the running integral over the radius (0 first)
// BssrdfTableView is those arrays in place. check_bssrdf_table() is the check
// SceneArchive::load applies, so the renderer can index and interpolate them
// without checks.
#pragma once

#include <cstdint>
#include <string>

namespace pbrta {

class SceneArchive;

struct BssrdfTableView {
  const float* rho = nullptr;
  const float* radius = nullptr;
  const float* profile = nullptr;
  const float* rho_eff = nullptr;
  const float* cdf = nullptr;
  uint32_t n_rho = 0, n_radius = 0, n_profile = 0, n_rho_eff = 0, n_cdf = 0;
};

// Largest sample counts accepted (pbrt-v3 uses 100 and 64).
inline constexpr uint32_t kMaxBssrdfSamples = 4096;

// True if the table is consistent: 4 to kMaxBssrdfSamples samples of each
// kind, profile and cdf n*m long and rho_eff n, samples strictly increasing
// (albedos in [0, 1], radii from 0), every number finite, profile and
// rho_eff not negative. Otherwise false with *error saying what is wrong.
bool check_bssrdf_table(const BssrdfTableView& t, std::string* error);

// The first two moments of the Fresnel reflectance of a boundary of relative
// index eta: the profile's boundary condition (pbrtc) and the normalisation
// of the lobe light leaves the surface by (the renderer) use them.
double fresnel_moment1(double eta);
double fresnel_moment2(double eta);

// The table of a subsurface or kdsubsurface material entity, in the
// archive's words; false with *error when it has none. Not checked here.
bool bssrdf_table_of(const SceneArchive& archive, uint32_t entity, BssrdfTableView* t,
                     std::string* error);

}  // namespace pbrta
