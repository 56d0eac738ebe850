// runtime/material/bump.h — bump mapping (book section 9.3).
//
// Displaces the surface along the shading normal by a float texture and
// replaces si's shading frame with that of the displaced surface, estimating
// the displacement's derivatives by forward differences in u and v (steps of
// half the screen-space uv footprint, or 0.0005 without differentials), as
// pbrt-v3's Material::Bump does. The new shading normal is flipped to the
// geometric normal's side.
#pragma once

#include "runtime/core/interaction.h"
#include "runtime/texture/textures.h"

namespace rt {

void apply_bump(const TextureSet& textures, const FloatInput& displacement, SurfaceInteraction* si);

}  // namespace rt
