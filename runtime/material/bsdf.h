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

#include <new>
#include <type_traits>

#include "runtime/core/interaction.h"
#include "runtime/material/bxdf.h"

namespace rt {

// The shading frame (shading normal, normalised shading dp/du, their cross product) and the
// geometric normal f() tells reflection from transmission by.
struct BsdfFrame {
  Vec3 ns, ng, ss, ts;
  Vec3 world_to_local(Vec3 v) const { return {dot(v, ss), dot(v, ts), dot(v, ns)}; }
  Vec3 local_to_world(Vec3 v) const { return ss * v.x + ts * v.y + ns * v.z; }
};

// f() of lobes [0, n) in frame: what Bsdf::f returns, for BSDFs kept in other forms (sppm's
// visible points).
Rgb lobes_f(const BsdfFrame& frame, const Bxdf* lobes, int n, Vec3 wo_world, Vec3 wi_world,
            uint8_t flags = kAllBxdf);

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

  const BsdfFrame& frame() const { return frame_; }
  Vec3 world_to_local(Vec3 v) const { return frame_.world_to_local(v); }
  Vec3 local_to_world(Vec3 v) const { return frame_.local_to_world(v); }
  Vec3 shading_normal() const { return frame_.ns; }
  Vec3 geometric_normal() const { return frame_.ng; }

  Rgb f(Vec3 wo_world, Vec3 wi_world, uint8_t flags = kAllBxdf) const;
  Rgb sample_f(Vec3 wo_world, Vec3* wi_world, Vec2 u, float* pdf, uint8_t flags = kAllBxdf,
               uint8_t* sampled_flags = nullptr) const;
  float pdf(Vec3 wo_world, Vec3 wi_world, uint8_t flags = kAllBxdf) const;
  // f() and pdf() at once, the same values: the frame change and what lobes share made once.
  Rgb f_pdf(Vec3 wo_world, Vec3 wi_world, uint8_t flags, float* pdf) const;
  // f(a, b), pdf(a, b) and pdf(b, a) at once, the same values (the frame change and what
  // lobes share made once): a bidirectional connection's end asks for all three.
  Rgb f_pdf_both(Vec3 a_world, Vec3 b_world, float* pdf_ab, float* pdf_ba) const;

  float eta = 1;

 private:
  // Room for the lobes, each constructed as it is added: a render makes a Bsdf at every hit,
  // most with one or two lobes, and constructing all eight up front cost a whitted render a
  // fortieth of its time. Bxdf is plain data (trivially copyable and destructible).
  struct LobeStorage {
    alignas(Bxdf) unsigned char bytes[kMaxLobes * sizeof(Bxdf)];
    Bxdf* data() { return std::launder(reinterpret_cast<Bxdf*>(bytes)); }
    const Bxdf* data() const { return std::launder(reinterpret_cast<const Bxdf*>(bytes)); }
    Bxdf& operator[](int i) { return data()[i]; }
    const Bxdf& operator[](int i) const { return data()[i]; }
    operator const Bxdf*() const { return data(); }
  };
  static_assert(std::is_trivially_copyable_v<Bxdf> && std::is_trivially_destructible_v<Bxdf>);

  BsdfFrame frame_;
  int n_ = 0;
  LobeStorage lobes_;
};

}  // namespace rt
