// runtime/render/direct_lighting.h — pbrt-v3's EstimateDirect and UniformSampleOneLight
// (book 3rd ed., 14.3, with 15.3's media), shared by the directlighting kernel
// (integrator.cpp) and sppm's camera pass (sppm.cpp); path and volpath take only its light
// half (sample_one_light's kLightOnly) and weigh the scattering half on their own path.
//
// A VertexScatter says what scatters at a vertex: a surface's BSDF (its cosine
// folded in) or, with kMedia, a medium's phase function (bsdf null).
// estimate_direct() takes one light sample and one scattering sample and weights
// them by the power heuristic; sample_one_light() picks the light from a
// distribution (uniformly when it is null; at the given site of it, if any, else at
// the interaction's point) and divides by its pmf, drawing the
// light choice (1D), the light point (2D) and the scattering sample (2D) in
// pbrt-v3's order, so a sampler's dimensions line up with pbrt-v3's.
//
// The templates are instantiated for the scene's effects as the kernels are:
// kAreaLights (a scattering sample may hit an emitter), kInfinite (it may escape
// to an infinite light), kMedia (visibility is transmittance). Everything reads
// the scene only; rays and shadow rays are counted in *c.
#pragma once

#include <algorithm>
#include <cstdint>

#include "runtime/core/rgb.h"
#include "runtime/core/sampling.h"
#include "runtime/light/light_distribution.h"
#include "runtime/material/bsdf.h"
#include "runtime/medium/phase.h"
#include "runtime/render/render_scene.h"
#include "runtime/render/visibility.h"
#include "runtime/sampler/sampler.h"

namespace rt {

// A surface's BSDF or a medium's phase function at a vertex. medium is the
// ray's medium there; a surface that bounds media changes it for rays leaving
// through its other side (pbrt-v3's GetMedium).
struct VertexScatter {
  const Bsdf* bsdf = nullptr;
  Vec3 wo, n, ns;
  float g = 0;
  const ShapeInfo* shape = nullptr;
  uint32_t medium = kNone;

  uint32_t medium_toward(Vec3 w) const {
    if (!shape || !shape->medium_transition()) return medium;
    return dot(w, n) > 0 ? shape->outside_medium : shape->inside_medium;
  }
  // pdf null: the caller needs no density (a delta light's sample has no MIS weight).
  // lobes: the BSDF lobes whose density *pdf is (f is the same either way: a specular lobe's
  // is 0).
  template <bool kMedia>
  Rgb f(Vec3 wi, float* pdf, uint8_t flags = kAllBxdf & ~kSpecular) const {
    if constexpr (kMedia) {
      if (!bsdf) {
        const float p = phase_hg(dot(wo, wi), g);
        if (pdf) *pdf = p;
        return Rgb(p);
      }
    }
    return (pdf ? bsdf->f_pdf(wo, wi, flags, pdf) : bsdf->f(wo, wi, flags)) * abs_dot(wi, ns);
  }
  // A surface's non-specular lobes (pbrt-v3's EstimateDirect; the path kernels sample their
  // own scattering).
  Rgb sample(Vec2 u, Vec3* wi, float* pdf, bool* specular) const {
    *specular = false;
    uint8_t sampled = 0;
    Rgb f = bsdf->sample_f(wo, wi, u, pdf, kAllBxdf & ~kSpecular, &sampled);
    *specular = sampled & kSpecular;
    return f * abs_dot(*wi, ns);
  }
};

inline VertexScatter surface_scatter(const RenderScene& scene, const SurfaceInteraction& si,
                                     const Bsdf& bsdf, uint32_t medium) {
  VertexScatter sc;
  sc.bsdf = &bsdf;
  sc.wo = si.wo;
  sc.n = si.n;
  sc.ns = si.shading.n;
  sc.shape = &scene.shapes[si.shape];
  sc.medium = medium;
  return sc;
}

// The light's half of estimate_direct: one sample of the light, weighted by the power heuristic
// against the density of scattering samples drawn from `lobes` (a delta light's: unweighted).
// The light sample's density is its pdf times light_pmf, the probability the light was
// chosen with: 1 where the scattering sample only counts this light (pbrt-v3's EstimateDirect).
template <bool kMedia>
Rgb estimate_light_sample(const RenderScene& scene, const Interaction& it, const VertexScatter& sc,
                          uint32_t light, Vec2 u_light, uint8_t lobes, float light_pmf,
                          Sampler& sampler, RayCounters* c) {
  const LightSet& lights = scene.lights;
  Rgb ld;
  LightSample ls;
  // An environment map's texels are read once the shadow ray is clear (behind it, and never
  // for a blocked sample); the scale stands in for them until then.
  Rgb li = lights.sample_li(light, it, u_light, &ls, !kMedia);
  const bool delta = lights.is_delta(light);
  if (ls.pdf > 0 && !li.is_black()) {
    float scattering_pdf = 0;
    Rgb f = sc.template f<kMedia>(ls.wi, delta ? nullptr : &scattering_pdf, lobes);
    if (!f.is_black()) {
      ++c->shadow_rays;
      if constexpr (kMedia)
        li *= transmittance(scene, it, ls.p_light, ls.wi, sc.medium_toward(ls.wi), sampler, c);
      else if (scene.geometry.occluded(it.spawn_ray_to(ls.p_light, ls.wi), ls.own_shape))
        li = Rgb();
      else
        li = lights.finish_li(ls);
      if (!li.is_black()) {
        if (delta)
          ld += f * li / ls.pdf;
        else
          ld += f * li * (power_heuristic(1, light_pmf * ls.pdf, 1, scattering_pdf) / ls.pdf);
      }
    }
  }
  return ld;
}

// pbrt-v3's EstimateDirect on a surface without media: the light half, then a scattering
// sample of the non-specular lobes traced to see whether it meets the same light.
template <bool kAreaLights, bool kInfinite>
Rgb estimate_direct(const RenderScene& scene, const Interaction& it, const VertexScatter& sc,
                    Vec2 u_scattering, uint32_t light, Vec2 u_light, Sampler& sampler,
                    RayCounters* c) {
  const LightSet& lights = scene.lights;
  const Rgb ld = estimate_light_sample<false>(scene, it, sc, light, u_light, kAllBxdf & ~kSpecular,
                                              1, sampler, c);
  if (lights.is_delta(light)) return ld;
  Vec3 wi;
  float scattering_pdf = 0;
  bool sampled_specular = false;
  Rgb f = sc.sample(u_scattering, &wi, &scattering_pdf, &sampled_specular);
  if (f.is_black() || scattering_pdf <= 0) return ld;
  MapDirection map_wi;
  if constexpr (kInfinite) map_wi = lights.prefetch_infinite(light, wi);
  Ray ray = it.spawn_ray(wi);
  // A direction that cannot meet the light is not traced (pbrt-v3's Pdf_Li test first): most
  // of a small light's scattering samples miss it, and each was a closest-hit query.
  if constexpr (kAreaLights)
    if (!lights.may_meet(light, ray)) return ld;
  SurfaceInteraction hit;
  // Only a hit on this light is read: the rest of a triangle's interaction waits until it is
  // one.
  SceneGeometry::PendingHit pending;
  ++c->rays;
  const bool found = scene.geometry.intersect_ids(ray, &hit, &pending);
  Rgb le;
  float light_pdf = 0;
  if (found) {
    if constexpr (kAreaLights) {
      if (lights.area_light_at(hit) == light) {
        scene.geometry.complete(pending, ray, &hit);
        le = lights.area_le(hit, -wi);
        if (!sampled_specular) light_pdf = lights.pdf_li(light, it, wi, &hit);
      }
    }
  } else if constexpr (kInfinite) {
    if (lights.kind(light) == LightKind::kInfinite) {
      RayDifferential rd(ray);
      le = lights.infinite_le_one(light, rd, sampled_specular ? nullptr : &light_pdf, map_wi);
    }
  }
  if (le.is_black()) return ld;
  float weight = 1;
  if (!sampled_specular) {
    if (light_pdf == 0) return ld;
    weight = power_heuristic(1, scattering_pdf, 1, light_pdf);
  }
  return ld + f * le * (weight / scattering_pdf);
}

// sample_one_light's first half: the light chosen for a vertex (with the probability *pick
// records) and the values drawn for its sample, in pbrt-v3's order; with kLightOnly the
// scattering sample's dimension is skipped here too. false: no light to sample (no lights,
// or the choice's pmf is 0), the light half then adds nothing.
struct LightPick {
  uint32_t light = 0;
  float pmf = 0;
  Vec2 u;
  bool delta = false;
};
template <bool kLightOnly>
bool pick_light(const RenderScene& scene, const Interaction& it, Sampler& sampler,
                const LightDistribution* distribution, const LightDistribution::Site* site,
                LightPick* pick) {
  uint32_t n = scene.lights.count();
  if (n == 0) return false;
  if (distribution) {
    const float u = sampler.get_1d();
    pick->light = uint32_t(site ? distribution->sample(*site, u, &pick->pmf)
                                : distribution->sample(it.p, u, &pick->pmf));
    if (pick->pmf == 0) return false;
  } else {
    pick->light = std::min(uint32_t(sampler.get_1d() * n), n - 1);
    pick->pmf = 1.f / n;
  }
  // A delta light reads neither value (its one direction needs no sample, and no BSDF sample
  // can hit it).
  pick->delta = scene.lights.is_delta(pick->light);
  pick->u = sampler.get_2d_if(!pick->delta);
  if constexpr (kLightOnly) sampler.skip_2d();
  return true;
}

// kLightOnly: only the light's half, weighted against the path's own next scattering sample
// (drawn from every lobe), which the caller weighs where it meets a light (pbrt-v4's path
// integrator does the same; one ray a vertex fewer than pbrt-v3's, the same expectation). The
// scattering sample's dimension is skipped, so the sampler's later dimensions stay pbrt-v3's.
// A caller may also pick_light, do other work, then light_half: the same result.
template <bool kMedia>
Rgb light_half(const RenderScene& scene, const Interaction& it, const VertexScatter& sc,
               const LightPick& pick, Sampler& sampler, RayCounters* c) {
  return estimate_light_sample<kMedia>(scene, it, sc, pick.light, pick.u, kAllBxdf, pick.pmf,
                                       sampler, c) /
         pick.pmf;
}

template <bool kAreaLights, bool kInfinite, bool kMedia, bool kLightOnly = false>
Rgb sample_one_light(const RenderScene& scene, const Interaction& it, const VertexScatter& sc,
                     Sampler& sampler, const LightDistribution* distribution, RayCounters* c,
                     const LightDistribution::Site* site = nullptr) {
  LightPick pick;
  if (!pick_light<kLightOnly>(scene, it, sampler, distribution, site, &pick)) return Rgb();
  if constexpr (kLightOnly) {
    return light_half<kMedia>(scene, it, sc, pick, sampler, c);
  } else {
    static_assert(!kMedia, "pbrt-v3's whole EstimateDirect runs on surfaces without media only");
    Vec2 u_scattering = sampler.get_2d_if(!pick.delta);
    return estimate_direct<kAreaLights, kInfinite>(scene, it, sc, u_scattering, pick.light, pick.u,
                                                   sampler, c) /
           pick.pmf;
  }
}

}  // namespace rt
