// runtime/material/disney_material.h — the "disney" material's inputs.
//
// read_disney_inputs() reads a disney material entity's parameters (each a
// constant or a texture; format/SCHEMA.md's names and defaults);
// evaluate_disney() looks them up at a shading point into the DisneyParams
// make_disney_lobes() turns into lobes (disney_bxdf.h). Bump mapping is the
// caller's, as for every material. A solid (not thin) surface with a
// non-black scatterdistance at a point scatters under its surface there
// (MaterialSet::compute_bssrdf, pbrt-v3's DisneyBSSRDF). max_disney_lobes()
// bounds the lobes make_disney_lobes() can make over all points (for mixes
// against Bsdf::kMaxLobes).
#pragma once

#include <string>

#include "format/scene_archive.h"
#include "runtime/core/interaction.h"
#include "runtime/material/disney_bxdf.h"
#include "runtime/texture/textures.h"

namespace rt {

struct DisneyInputs {
  RgbInput color, scatter_distance;
  FloatInput metallic, eta, roughness, specular_tint, anisotropic, sheen, sheen_tint, clearcoat,
      clearcoat_gloss, spec_trans, flatness, diff_trans;
  bool thin = false;
};

void read_disney_inputs(const pbrta::SceneArchive& archive, uint32_t entity, DisneyInputs* out);
int max_disney_lobes(const DisneyInputs& in);
DisneyParams evaluate_disney(const DisneyInputs& in, const TextureSet& textures,
                             const SurfaceInteraction& si);

}  // namespace rt
