// runtime/core/interaction.h — what an intersection knows about the surface it hit.
//
// Interaction is a point with its error bound and normal: enough for lights
// to sample towards and for spawning rays. SurfaceInteraction adds the
// parameterisation (uv, dp/du, dn/du...), the shading frame (from mesh
// normals or bump mapping), screen-space differentials for texture
// filtering, and the indices that say what was hit: the archive's shape
// record, the primitive within it, and (for instances) the instance.
// Filled by runtime/geometry, read by materials, textures and lights.
#pragma once

#include <cstdint>

#include "runtime/core/ray.h"
#include "runtime/core/vec.h"

namespace rt {

struct Interaction {
  Vec3 p;        // world space
  Vec3 p_error;  // conservative absolute error bound of p
  Vec3 n;        // geometric normal (unit; zero for points in free space)
  Vec3 wo;       // direction back along the incoming ray (unit), or zero
  float time = 0;

  Ray spawn_ray(Vec3 d) const {
    Vec3 o = offset_ray_origin(p, p_error, n, d);
    return Ray{o, d, kInfinity, time};
  }
  // A ray to point p2 that stops just short of it (d is not normalised:
  // t in [0, 1 - kShadowEpsilon]).
  Ray spawn_ray_to(Vec3 p2) const {
    Vec3 o = offset_ray_origin(p, p_error, n, p2 - p);
    return Ray{o, p2 - o, 1 - kShadowEpsilon, time};
  }
  Ray spawn_ray_to(const Interaction& it) const { return spawn_ray_to(it, it.p - p); }
  // As above, but leaving by the side that direction `side` (a light sample's wi) leaves by: for
  // a grazing wi, it.p - p (it.p rounded far away: an infinite light's point) can name the
  // other side, and the ray would start beyond the surface the scattering function saw wi stay
  // in front of (light leaked into a closed sphere far from the origin).
  Ray spawn_ray_to(const Interaction& it, Vec3 side) const {
    Vec3 o = offset_ray_origin(p, p_error, n, side);
    Vec3 t = offset_ray_origin(it.p, it.p_error, it.n, o - it.p);
    return Ray{o, t - o, 1 - kShadowEpsilon, time};
  }
};

struct ShadingFrame {
  Vec3 n, dpdu, dpdv, dndu, dndv;
};

struct SurfaceInteraction : Interaction {
  Vec2 uv;
  Vec3 dpdu, dpdv, dndu, dndv;
  ShadingFrame shading;
  // Screen-space differentials (zero when the ray had none).
  Vec3 dpdx, dpdy;
  float dudx = 0, dvdx = 0, dudy = 0, dvdy = 0;

  float t_hit = 0;            // the ray parameter of the hit
  uint32_t shape = kNone;     // index into the archive's shapes
  uint32_t prim = 0;          // triangle within the mesh (0 for quadrics)
  uint32_t instance = kNone;  // index into the archive's instances, or kNone
  int32_t face_index = 0;     // the mesh's faceIndices entry (ptex), or 0

  // Sets the shading frame; pbrt-v3's rule: the geometric normal is flipped to
  // the shading normal's side when orientation_is_authoritative is false (mesh
  // normals), else the shading normal follows the geometric one.
  void set_shading_geometry(Vec3 dpdus, Vec3 dpdvs, Vec3 dndus, Vec3 dndvs,
                            bool orientation_is_authoritative) {
    shading.n = normalize(cross(dpdus, dpdvs));
    if (orientation_is_authoritative)
      n = face_forward(n, shading.n);
    else
      shading.n = face_forward(shading.n, n);
    shading.dpdu = dpdus;
    shading.dpdv = dpdvs;
    shading.dndu = dndus;
    shading.dndv = dndvs;
  }

  // pbrt-v3's SurfaceInteraction::ComputeDifferentials: the offsets of the
  // differential rays' hits on the tangent plane, and from them du/dx etc.
  void compute_differentials(const RayDifferential& ray) {
    if (ray.has_differentials) {
      float d = dot(n, p);
      float tx = -(dot(n, ray.rx_o) - d) / dot(n, ray.rx_d);
      float ty = -(dot(n, ray.ry_o) - d) / dot(n, ray.ry_d);
      if (std::isfinite(tx) && std::isfinite(ty)) {
        Vec3 px = ray.rx_o + ray.rx_d * tx;
        Vec3 py = ray.ry_o + ray.ry_d * ty;
        dpdx = px - p;
        dpdy = py - p;
        int dim[2];
        if (std::fabs(n.x) > std::fabs(n.y) && std::fabs(n.x) > std::fabs(n.z)) {
          dim[0] = 1;
          dim[1] = 2;
        } else if (std::fabs(n.y) > std::fabs(n.z)) {
          dim[0] = 0;
          dim[1] = 2;
        } else {
          dim[0] = 0;
          dim[1] = 1;
        }
        float a[2][2] = {{dpdu[dim[0]], dpdv[dim[0]]}, {dpdu[dim[1]], dpdv[dim[1]]}};
        float bx[2] = {px[dim[0]] - p[dim[0]], px[dim[1]] - p[dim[1]]};
        float by[2] = {py[dim[0]] - p[dim[0]], py[dim[1]] - p[dim[1]]};
        auto solve = [&](const float b[2], float* x0, float* x1) {
          float det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
          if (std::fabs(det) < 1e-23f) return false;
          *x0 = (a[1][1] * b[0] - a[0][1] * b[1]) / det;
          *x1 = (a[0][0] * b[1] - a[1][0] * b[0]) / det;
          return std::isfinite(*x0) && std::isfinite(*x1);
        };
        if (!solve(bx, &dudx, &dvdx)) dudx = dvdx = 0;
        if (!solve(by, &dudy, &dvdy)) dudy = dvdy = 0;
        return;
      }
    }
    dudx = dvdx = dudy = dvdy = 0;
    dpdx = dpdy = Vec3{};
  }
};

}  // namespace rt
