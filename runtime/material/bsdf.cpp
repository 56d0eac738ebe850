// runtime/material/bsdf.cpp — lobe selection and the world/local frame change.
#include "runtime/material/bsdf.h"

namespace rt {

void Bsdf::init(const SurfaceInteraction& si, float eta_) {
  eta = eta_;
  frame_.ns = si.shading.n;
  frame_.ng = si.n;
  frame_.ss = normalize(si.shading.dpdu);
  frame_.ts = cross(frame_.ns, frame_.ss);
  n_ = 0;
}

bool Bsdf::add(const Bxdf& lobe) {
  if (n_ == kMaxLobes) return false;
  new (lobes_.bytes + size_t(n_++) * sizeof(Bxdf)) Bxdf(lobe);
  return true;
}

void Bsdf::scale_lobes(Rgb s) {
  for (int i = 0; i < n_; ++i) lobes_[i].scale *= s;
}

int Bsdf::num_components(uint8_t flags) const {
  int n = 0;
  for (int i = 0; i < n_; ++i)
    if (lobes_[i].matches(flags)) ++n;
  return n;
}

namespace {
// Over the lobes matching flags: adds to *f the f of those on wi's side of the surface
// (reflect: wo's), and, when pdf is given, to *pdf the pdf of each but lobe `skip` (whose pdf
// the caller has); a lobe that gives both computes them at once. Returns how many match.
// Inlined into each caller (three, on the hot path: left to itself GCC made it a call).
[[gnu::always_inline]] inline int sum_lobes(const Bxdf* lobes, int n, Vec3 wo, Vec3 wi,
                                            bool reflect, uint8_t flags, Rgb* f, float* pdf,
                                            int skip = -1) {
  int matching = 0;
  for (int i = 0; i < n; ++i) {
    const Bxdf& b = lobes[i];
    if (!b.matches(flags)) continue;
    ++matching;
    const bool want_pdf = pdf && i != skip;
    if ((reflect && (b.flags & kReflection)) || (!reflect && (b.flags & kTransmission))) {
      if (want_pdf) {
        float p;
        *f += b.f_pdf(wo, wi, &p);
        *pdf += p;
      } else {
        *f += b.f(wo, wi);
      }
    } else if (want_pdf) {
      *pdf += b.pdf(wo, wi);
    }
  }
  return matching;
}
}  // namespace

Rgb lobes_f(const BsdfFrame& frame, const Bxdf* lobes, int n, Vec3 wo_world, Vec3 wi_world,
            uint8_t flags) {
  Vec3 wi = frame.world_to_local(wi_world), wo = frame.world_to_local(wo_world);
  if (wo.z == 0) return Rgb(0);
  const bool reflect = dot(wi_world, frame.ng) * dot(wo_world, frame.ng) > 0;
  Rgb f(0);
  sum_lobes(lobes, n, wo, wi, reflect, flags, &f, nullptr);
  return f;
}

Rgb Bsdf::f(Vec3 wo_world, Vec3 wi_world, uint8_t flags) const {
  return lobes_f(frame_, lobes_, n_, wo_world, wi_world, flags);
}

Rgb Bsdf::sample_f(Vec3 wo_world, Vec3* wi_world, Vec2 u, float* pdf, uint8_t flags,
                   uint8_t* sampled_flags) const {
  *pdf = 0;
  if (sampled_flags) *sampled_flags = 0;
  int matching = num_components(flags);
  if (matching == 0) return Rgb(0);
  int comp = std::min(int(std::floor(u.x * matching)), matching - 1);
  const Bxdf* chosen = nullptr;
  int chosen_index = 0;
  for (int i = 0, count = comp; i < n_; ++i)
    if (lobes_[i].matches(flags) && count-- == 0) {
      chosen = &lobes_[i];
      chosen_index = i;
      break;
    }
  // Reuse the part of u.x that selected the lobe as a fresh uniform sample.
  Vec2 u_remapped{std::min(u.x * matching - comp, kOneMinusEpsilon), u.y};

  Vec3 wo = world_to_local(wo_world), wi;
  if (wo.z == 0) return Rgb(0);
  uint8_t sampled = chosen->flags;
  // A non-specular lobe's own value is replaced by the sum over the lobes below.
  const bool specular = chosen->flags & kSpecular;
  Rgb f(0);
  if (specular)
    f = chosen->sample_f(wo, &wi, u_remapped, pdf, &sampled);
  else
    chosen->sample_wi(wo, &wi, u_remapped, pdf, &sampled);
  if (*pdf == 0) return Rgb(0);
  if (sampled_flags) *sampled_flags = sampled;
  *wi_world = local_to_world(wi);

  if (!specular) {
    // The other lobes' pdfs are added to the chosen one's, and every lobe on wi's side gives
    // its f (as f() sums them).
    const bool reflect = dot(*wi_world, frame_.ng) * dot(wo_world, frame_.ng) > 0;
    sum_lobes(lobes_, n_, wo, wi, reflect, flags, &f, pdf, chosen_index);
  }
  if (matching > 1) *pdf /= matching;
  return f;
}

Rgb Bsdf::f_pdf(Vec3 wo_world, Vec3 wi_world, uint8_t flags, float* pdf) const {
  *pdf = 0;
  if (n_ == 0) return Rgb(0);
  Vec3 wo = world_to_local(wo_world), wi = world_to_local(wi_world);
  if (wo.z == 0) return Rgb(0);
  const bool reflect = dot(wi_world, frame_.ng) * dot(wo_world, frame_.ng) > 0;
  Rgb f(0);
  float sum = 0;
  const int matching = sum_lobes(lobes_, n_, wo, wi, reflect, flags, &f, &sum);
  *pdf = matching > 0 ? sum / matching : 0;
  return f;
}

float Bsdf::pdf(Vec3 wo_world, Vec3 wi_world, uint8_t flags) const {
  if (n_ == 0) return 0;
  Vec3 wo = world_to_local(wo_world), wi = world_to_local(wi_world);
  if (wo.z == 0) return 0;
  float pdf = 0;
  int matching = 0;
  for (int i = 0; i < n_; ++i)
    if (lobes_[i].matches(flags)) {
      ++matching;
      pdf += lobes_[i].pdf(wo, wi);
    }
  return matching > 0 ? pdf / matching : 0;
}

Rgb Bsdf::f_pdf_both(Vec3 a_world, Vec3 b_world, float* pdf_ab, float* pdf_ba) const {
  *pdf_ab = *pdf_ba = 0;
  if (n_ == 0) return Rgb(0);
  const Vec3 a = world_to_local(a_world), b = world_to_local(b_world);
  const bool reflect = dot(b_world, frame_.ng) * dot(a_world, frame_.ng) > 0;
  Rgb f(0);
  float sum_ab = 0, sum_ba = 0;
  int matching = 0;
  for (int i = 0; i < n_; ++i) {
    const Bxdf& lobe = lobes_[i];
    if (!lobe.matches(kAllBxdf)) continue;
    ++matching;
    float ab, ba;
    if ((reflect && (lobe.flags & kReflection)) || (!reflect && (lobe.flags & kTransmission)))
      f += lobe.f_pdf_both(a, b, &ab, &ba);
    else
      lobe.pdf_both(a, b, &ab, &ba);
    sum_ab += ab;
    sum_ba += ba;
  }
  if (matching == 0) return Rgb(0);
  if (a.z != 0) *pdf_ab = sum_ab / matching;
  if (b.z != 0) *pdf_ba = sum_ba / matching;
  return a.z != 0 ? f : Rgb(0);
}

}  // namespace rt
