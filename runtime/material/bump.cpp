// runtime/material/bump.cpp — displaced shading frame from a displacement texture.
#include "runtime/material/bump.h"

namespace rt {

void apply_bump(const TextureSet& textures, const FloatInput& displacement,
                SurfaceInteraction* si) {
  // The texture is evaluated at points shifted along dp/du and dp/dv, with
  // uv and normal shifted to match, so texture lookups see a consistent point.
  SurfaceInteraction shifted = *si;
  float du = .5f * (std::fabs(si->dudx) + std::fabs(si->dudy));
  if (du == 0) du = .0005f;
  shifted.p = si->p + du * si->shading.dpdu;
  shifted.uv = si->uv + Vec2{du, 0.f};
  shifted.n = normalize(cross(si->shading.dpdu, si->shading.dpdv) + du * si->dndu);
  float u_displace = textures.eval(displacement, shifted);

  float dv = .5f * (std::fabs(si->dvdx) + std::fabs(si->dvdy));
  if (dv == 0) dv = .0005f;
  shifted.p = si->p + dv * si->shading.dpdv;
  shifted.uv = si->uv + Vec2{0.f, dv};
  shifted.n = normalize(cross(si->shading.dpdu, si->shading.dpdv) + dv * si->dndv);
  float v_displace = textures.eval(displacement, shifted);
  float displace = textures.eval(displacement, *si);

  // Partial derivatives of p + d(u, v) n (book eq. 9.1 and its v twin; the
  // d dn/du term keeps curved surfaces' bumps correct).
  Vec3 dpdu =
      si->shading.dpdu + (u_displace - displace) / du * si->shading.n + displace * si->shading.dndu;
  Vec3 dpdv =
      si->shading.dpdv + (v_displace - displace) / dv * si->shading.n + displace * si->shading.dndv;
  si->set_shading_geometry(dpdu, dpdv, si->shading.dndu, si->shading.dndv, false);
}

}  // namespace rt
