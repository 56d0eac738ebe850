// runtime/material/bsdf.h — the world-space BSDF at a shading point (book section 9.1).
//
// Up to kMaxLobes lobes stored inline (no heap), expressed in the shading
// frame (shading normal, normalised shading dp/du, their cross product) set
// by init(). As in pbrt-v3, f() decides between reflection and transmission
// with the geometric normal, so light leaks from shading normals are avoided;
// sample_f picks one matching lobe uniformly with u.x, and unless it is
// specular returns the sum of all matching lobes' f and the average of their
// pdfs. eta is the relative index of refraction across the surface (for
// Russian roulette's eta-scale bookkeeping), 1 for opaque materials.
#pragma once

#include "runtime/core/interaction.h"
#include "runtime/material/bxdf.h"

namespace rt {

class Bsdf {
 public:
  static constexpr int kMaxLobes = 8;

  void init(const SurfaceInteraction& si, float eta = 1);
  // False (and the lobe dropped) when the BSDF is full.
  bool add(const Bxdf& lobe);
  // Multiplies every lobe's weight (mix materials).
  void scale_lobes(Rgb s);

  int num_lobes() const { return n_; }
  const Bxdf& lobe(int i) const { return lobes_[i]; }
  int num_components(uint8_t flags = kAllBxdf) const;

  Vec3 world_to_local(Vec3 v) const { return {dot(v, ss_), dot(v, ts_), dot(v, ns_)}; }
  Vec3 local_to_world(Vec3 v) const { return ss_ * v.x + ts_ * v.y + ns_ * v.z; }
  Vec3 shading_normal() const { return ns_; }
  Vec3 geometric_normal() const { return ng_; }

  Rgb f(Vec3 wo_world, Vec3 wi_world, uint8_t flags = kAllBxdf) const;
  Rgb sample_f(Vec3 wo_world, Vec3* wi_world, Vec2 u, float* pdf, uint8_t flags = kAllBxdf,
               uint8_t* sampled_flags = nullptr) const;
  float pdf(Vec3 wo_world, Vec3 wi_world, uint8_t flags = kAllBxdf) const;

  float eta = 1;

 private:
  Vec3 ns_, ng_, ss_, ts_;
  int n_ = 0;
  Bxdf lobes_[kMaxLobes];
};

}  // namespace rt
