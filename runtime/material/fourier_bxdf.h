// runtime/material/fourier_bxdf.h — pbrt-v3's FourierBSDF (book section 8.6): a measured or
// layered BSDF tabulated as Fourier series in the azimuth difference.
//
// FourierTable views the table pbrtc stored in a fourier material's derived parameters
// (format/fourier_table.h) in the archive's words, without copying; SceneArchive::load has
// already checked its arrays agree, so lookups index them unchecked. The only copies are two
// small arrays the book derives: each node pair's constant term a0 (what zenith sampling
// integrates) and 1/k. The archive must outlive the table.
//
// FourierLobe is the lobe in the local shading frame (+z = shading normal). As in pbrt-v3,
// mu_i = cos theta of -wi and mu_o = cos theta of wo, so reflection has mu_i mu_o < 0; the
// table's coefficients are Catmull-Rom weighted over the four nearest nodes in each cosine,
// summed as a series in cos(phi) of -wi against wo, and divided by |mu_i|. Three-channel
// tables hold luminance, red and blue; green follows from the luminance weights. In radiance
// mode, light crossing the surface (mu_i mu_o > 0) is scaled by 1/eta^2 when mu_i > 0 and by
// eta^2 otherwise, as pbrt-v3 does; importance is not scaled. Sampling draws mu_i by inverting the
// spline of a0 over mu_i (at mu_o), then phi from the luminance series; pdf() is luminance over its
// total integral, which is the product of those two densities. Flags: reflection, transmission,
// glossy. No heap, no virtual call; the series scratch lives on the stack.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "format/fourier_table.h"
#include "format/scene_archive.h"
#include "runtime/core/rgb.h"
#include "runtime/core/vec.h"
#include "runtime/material/bxdf.h"

namespace rt {

// The archive's checked table (FourierTableView: eta, m_max, channels, mu, cdf
// ([o][i]: running integral of a0 over mu_i at node o), offsets ([o][i]:
// first coefficient and series length), coeffs, counts), in place, plus what
// lookups derive from it once.
struct FourierTable : pbrta::FourierTableView {
  std::vector<float> a0;     // [o][i]: the luminance series' constant term
  std::vector<float> recip;  // 1 / k for k < m_max (recip[0] unused)

  // Node pair (i: mu_i node, o: mu_o node): *m terms per channel, channel c at c * *m.
  const float* series(int i, int o, int* m) const {
    const int32_t* p = offsets + 2 * (o * int(n_mu) + i);
    *m = p[1];
    return coeffs + p[0];
  }
};

// Views a checked table (tests build tables by hand with this).
void make_fourier_table(const pbrta::FourierTableView& view, FourierTable* table);

// The table of fourier material entity `entity`. False with *error (naming the material's
// location) when the archive holds none.
bool build_fourier_table(const pbrta::SceneArchive& archive, uint32_t entity, FourierTable* table,
                         std::string* error);

struct FourierLobe {
  const FourierTable* table = nullptr;
  TransportMode mode = TransportMode::kRadiance;
  uint8_t flags = kReflection | kTransmission | kGlossy;

  bool matches(uint8_t mask) const { return (flags & mask) == flags; }
  Rgb f(Vec3 wo, Vec3 wi) const;
  // *pdf is 0 when no direction was sampled.
  Rgb sample_f(Vec3 wo, Vec3* wi, Vec2 u, float* pdf) const;
  float pdf(Vec3 wo, Vec3 wi) const;
};

}  // namespace rt
