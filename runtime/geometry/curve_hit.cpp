// runtime/geometry/curve_hit.cpp — see curve_hit.h.
#include "runtime/geometry/curve_hit.h"

namespace rt {

bool world_curve_hit(const ShapeInfo& s, const Transform& to_world,
                     const Transform& world_to_object, uint32_t piece, const Ray& rw, float* t_hit,
                     SurfaceInteraction* si) {
  const Ray r{world_to_object.point(rw.o), world_to_object.vector(rw.d), rw.tmax, rw.time};
  if (!si) return intersect_curve_piece(*s.curve, piece, r, nullptr);
  CurveHit h;
  if (!intersect_curve_piece(*s.curve, piece, r, &h)) return false;
  Vec3 n = normalize(cross(h.dpdu, h.dpdv));
  if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z)) return false;
  if (s.flip_normals()) n = -n;
  *t_hit = h.t;
  si->p = to_world.point(h.p, h.p_error, &si->p_error);
  si->n = normalize(to_world.normal(n));
  si->wo = normalize(-rw.d);
  si->time = rw.time;
  si->uv = h.uv;
  si->dpdu = to_world.vector(h.dpdu);
  si->dpdv = to_world.vector(h.dpdv);
  si->dndu = si->dndv = Vec3{};
  si->shading = ShadingFrame{si->n, si->dpdu, si->dpdv, Vec3{}, Vec3{}};
  si->dpdx = si->dpdy = Vec3{};
  si->dudx = si->dvdx = si->dudy = si->dvdy = 0;
  si->prim = piece;
  si->face_index = 0;
  return true;
}

}  // namespace rt
