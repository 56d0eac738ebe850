// format/fourier_table.h — the fourier material's tabulated BSDF as the archive holds it.
//
// pbrt-v3's "fourier" material (book section 8.6; Jakob et al. 2014, "A Comprehensive
// Framework for Rendering Layered Materials") reads a .bsdf file of Fourier series in the
// azimuth difference, tabulated over pairs of zenith cosines. pbrtc reads that file and stores
// its arrays as derived parameters of the material entity (ARCHIVE.md, "Derived parameters"):
//   bsdfeta       float     relative index of refraction (1: reflection only)
//   bsdfmmax      int       the largest series length of any node pair
//   bsdfchannels  int       1 (luminance) or 3 (luminance, red, blue)
//   bsdfmu        float[n]  the zenith cosine nodes, non-decreasing in [-1, 1]
//   bsdfcdf       float[n*n] per outgoing node o, the running integral over incoming nodes i
//                            of the series' constant term (row o, column i)
//   bsdfoffsets   int[2*n*n] per (o, i): first coefficient and series length m; the pair's
//                            coefficients are coeffs[offset + c*m + k] for channel c, k < m
//   bsdfcoeffs    float[]    all series coefficients
// FourierTableView is those arrays in place (no copy). check_fourier_table() is the one
// consistency check both pbrtc (after reading a file) and SceneArchive::load (before anyone
// reads an archive's table) apply, so the renderer can index the arrays without checks.
#pragma once

#include <cstdint>
#include <string>

namespace pbrta {

class SceneArchive;

struct FourierTableView {
  float eta = 1;
  int32_t m_max = 0;
  int32_t channels = 0;
  const float* mu = nullptr;
  const float* cdf = nullptr;
  const int32_t* offsets = nullptr;
  const float* coeffs = nullptr;
  // Element counts as stored; the check ties them together.
  uint32_t n_mu = 0, n_cdf = 0, n_offsets = 0, n_coeffs = 0;
};

// Largest node count and series length accepted: far above any published table
// (58 nodes and 172 terms for pbrt-v3's roughgold), small enough that a
// renderer's per-lookup scratch arrays stay bounded.
inline constexpr uint32_t kMaxFourierNodes = 1024;
inline constexpr int32_t kMaxFourierOrder = 2048;

// True if the table is consistent: counts match n_mu, channels 1 or 3, nodes
// non-decreasing in [-1, 1] with the last two distinct, every (offset, length) pair inside the
// coefficients with length <= m_max, all numbers finite, eta positive. Otherwise
// false with *error saying what is wrong.
bool check_fourier_table(const FourierTableView& t, std::string* error);

// The derived table of a fourier material entity, viewed in the archive's words.
// False with *error when the entity is not a fourier material or the table is
// missing; the view is not checked here.
bool fourier_table_of(const SceneArchive& archive, uint32_t entity, FourierTableView* t,
                      std::string* error);

}  // namespace pbrta
