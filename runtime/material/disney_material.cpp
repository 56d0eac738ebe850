// runtime/material/disney_material.cpp — see disney_material.h.
#include "runtime/material/disney_material.h"

namespace rt {

namespace {

bool may_be_positive(const FloatInput& in) {
  return in.texture != kNone || in.value > 0;
}

// (1 - metallic)(1 - spectrans) > 0 somewhere: the diffuse lobes may appear.
bool may_have_diffuse(const DisneyInputs& in) {
  if (in.metallic.texture != kNone || in.spec_trans.texture != kNone) return true;
  return (1 - in.metallic.value) * (1 - in.spec_trans.value) > 0;
}

}  // namespace

void read_disney_inputs(const pbrta::SceneArchive& a, uint32_t e, DisneyInputs* in) {
  in->color = rgb_input(a, e, "color");
  in->scatter_distance = rgb_input(a, e, "scatterdistance");
  in->metallic = float_input(a, e, "metallic");
  in->eta = float_input(a, e, "eta");
  in->roughness = float_input(a, e, "roughness");
  in->specular_tint = float_input(a, e, "speculartint");
  in->anisotropic = float_input(a, e, "anisotropic");
  in->sheen = float_input(a, e, "sheen");
  in->sheen_tint = float_input(a, e, "sheentint");
  in->clearcoat = float_input(a, e, "clearcoat");
  in->clearcoat_gloss = float_input(a, e, "clearcoatgloss");
  in->spec_trans = float_input(a, e, "spectrans");
  in->flatness = float_input(a, e, "flatness");
  in->diff_trans = float_input(a, e, "difftrans");
  in->thin = a.get_int(e, "thin", 0) != 0;
}

int max_disney_lobes(const DisneyInputs& in) {
  int n = 0;
  if (may_have_diffuse(in)) {
    n += in.thin ? 2 : 1;  // diffuse (thin: and fake subsurface)
    n += 1;                // retro-reflection
    if (may_be_positive(in.sheen)) ++n;
  }
  ++n;  // specular, always
  if (may_be_positive(in.clearcoat)) ++n;
  if (may_be_positive(in.spec_trans)) ++n;
  if (in.thin) ++n;  // diffuse transmission
  return n;
}

DisneyParams evaluate_disney(const DisneyInputs& in, const TextureSet& t,
                             const SurfaceInteraction& si) {
  DisneyParams p;
  p.color = t.eval(in.color, si);
  p.scatter_distance = t.eval(in.scatter_distance, si);
  p.metallic = t.eval(in.metallic, si);
  p.eta = t.eval(in.eta, si);
  p.roughness = t.eval(in.roughness, si);
  p.specular_tint = t.eval(in.specular_tint, si);
  p.anisotropic = t.eval(in.anisotropic, si);
  p.sheen = t.eval(in.sheen, si);
  p.sheen_tint = t.eval(in.sheen_tint, si);
  p.clearcoat = t.eval(in.clearcoat, si);
  p.clearcoat_gloss = t.eval(in.clearcoat_gloss, si);
  p.spec_trans = t.eval(in.spec_trans, si);
  p.flatness = t.eval(in.flatness, si);
  p.diff_trans = t.eval(in.diff_trans, si);
  p.thin = in.thin;
  return p;
}

}  // namespace rt
