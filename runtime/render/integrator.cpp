// runtime/render/integrator.cpp — see integrator.h. The algorithms are the
// pbrt book's (3rd ed., ch. 14 and 16.1 for specular differentials).
#include "runtime/render/integrator.h"

#include <algorithm>
#include <cmath>

#include "runtime/core/sampling.h"
#include "runtime/material/bsdf.h"
#include "runtime/medium/phase.h"
#include "runtime/render/bdpt.h"
#include "runtime/render/direct_lighting.h"

namespace rt {

bool read_integrator(const pbrta::SceneArchive& a, IntegratorSettings* s, std::string* error) {
  uint32_t e = a.scene().integrator;
  std::string_view type = a.type_name(e);
  if (type == "whitted")
    s->type = IntegratorType::kWhitted;
  else if (type == "directlighting")
    s->type = IntegratorType::kDirectLighting;
  else if (type == "path")
    s->type = IntegratorType::kPath;
  else if (type == "volpath")
    s->type = IntegratorType::kVolPath;
  else if (type == "ambientocclusion")
    s->type = IntegratorType::kAmbientOcclusion;
  else if (type == "bdpt")
    s->type = IntegratorType::kBdpt;
  else if (type == "mlt")
    s->type = IntegratorType::kMlt;
  else if (type == "sppm")
    s->type = IntegratorType::kSppm;
  else {
    *error = "not supported yet: " + std::string(type) + " integrator (" + a.where(e) + ")";
    return false;
  }
  s->max_depth = a.get_int(e, "maxdepth", 5);
  if (s->type == IntegratorType::kDirectLighting) {
    std::string_view strategy = a.get_string(e, "strategy");
    if (strategy == "one")
      s->sample_all_lights = false;
    else if (strategy == "all" || strategy.empty())
      s->sample_all_lights = true;
    else {
      *error = a.where(e) + ": error: directlighting strategy \"" + std::string(strategy) +
               "\" unknown (\"all\" or \"one\")";
      return false;
    }
  }
  if (s->type == IntegratorType::kPath || s->type == IntegratorType::kVolPath) {
    s->rr_threshold = a.get_float(e, "rrthreshold", 1);
    std::string_view ls = a.get_string(e, "lightsamplestrategy");
    s->light_strategy = ls.empty() ? "spatial" : std::string(ls);
  }
  if (s->type == IntegratorType::kMlt) {
    s->mlt_bootstrap = a.get_int(e, "bootstrapsamples", 100000);
    s->mlt_chains = a.get_int(e, "chains", 1000);
    s->mlt_mutations_per_pixel = a.get_int(e, "mutationsperpixel", 100);
    s->mlt_large_step_probability = a.get_float(e, "largestepprobability", 0.3f);
    s->mlt_sigma = a.get_float(e, "sigma", 0.01f);
    if (s->mlt_bootstrap < 1 || s->mlt_chains < 1 || s->mlt_mutations_per_pixel < 1) {
      *error = a.where(e) +
               ": error: mlt \"bootstrapsamples\", \"chains\" and "
               "\"mutationsperpixel\" must be at least 1";
      return false;
    }
  }
  if (s->type == IntegratorType::kSppm) {
    // pbrtc resolved "numiterations" into "iterations" (the schema's alias).
    s->sppm_iterations = a.get_int(e, "iterations", 64);
    s->sppm_photons_per_iteration = a.get_int(e, "photonsperiteration", -1);
    s->sppm_radius = a.get_float(e, "radius", 1);
    if (s->sppm_iterations < 1) {
      *error = a.where(e) + ": error: sppm \"iterations\" must be at least 1";
      return false;
    }
  }
  if (s->type == IntegratorType::kBdpt) {
    // pbrt-v3's bdpt picks the light that starts a light subpath by power by default.
    std::string_view ls = a.get_string(e, "lightsamplestrategy");
    s->light_strategy = ls.empty() ? "power" : std::string(ls);
    s->bdpt_visualize_strategies = a.get_int(e, "visualizestrategies", 0) != 0;
    s->bdpt_visualize_weights = a.get_int(e, "visualizeweights", 0) != 0;
  }
  if (s->type == IntegratorType::kAmbientOcclusion) {
    s->cos_sample = a.get_int(e, "cossample", 1) != 0;
    s->ao_samples = a.get_int(e, "nsamples", 64);
    if (s->ao_samples < 1) {
      *error = a.where(e) + ": error: ambientocclusion \"nsamples\" must be at least 1";
      return false;
    }
  }
  const pbrta::ValueRecord* pb = a.value(e, "pixelbounds");
  if (pb && (pb->flags & pbrta::kValueGiven) && pb->count == 4) {
    const uint32_t* w = &a.words[pb->offset];
    s->has_pixel_bounds = true;
    s->pixel_bounds = {{int32_t(w[0]), int32_t(w[2])}, {int32_t(w[1]), int32_t(w[3])}};
  }
  return true;
}

template <bool kAreaLights, bool kInfinite>
struct Kernels {
  using Self = Integrator;

  static bool intersect(const Self& I, const Ray& ray, SurfaceInteraction* si, RayCounters* c) {
    ++c->rays;
    return I.scene_->geometry.intersect(ray, si);
  }

  // intersect(), and the light grid's record for the hit starts loading as soon as Embree has
  // the hit's distance: the record is a cache miss at nearly every bounce, and the hit's
  // interaction is made while it loads. The point is Embree's (the exact one may lie in the
  // next voxel: then the hint was wasted, nothing else).
  static bool intersect_prefetching_light_site(const Self& I, const Ray& ray,
                                               SurfaceInteraction* si, RayCounters* c) {
    ++c->rays;
    SceneGeometry::PendingHit pending;
    const SceneGeometry& geometry = I.scene_->geometry;
    if (!geometry.intersect_ids(ray, si, &pending)) return false;
    I.distribution_.prefetch(I.distribution_.site(ray.at(si->t_hit)));
    geometry.complete(pending, ray, si);
    return true;
  }

  static Rgb emitted(const Self& I, const SurfaceInteraction& si, Vec3 w) {
    if constexpr (kAreaLights) return I.scene_->lights.area_le(si, w);
    return Rgb();
  }

  // A hint: should the ray leaving along w escape, the lookups of the environment maps it
  // then reads are on their way while it is traced (each is a cache miss). With one infinite
  // light, w's coordinates in its map, for weighted_emission.
  static MapDirection prefetch_escape(const Self& I, Vec3 w) {
    MapDirection d;
    if constexpr (kInfinite) {
      const std::vector<uint32_t>& infinite = I.scene_->lights.infinite_lights();
      for (uint32_t light : infinite) d = I.scene_->lights.prefetch_infinite(light, w);
      if (infinite.size() > 1) d = {};
    }
    return d;
  }

  static Rgb escaped(const Self& I, const RayDifferential& ray) {
    if constexpr (kInfinite) return I.scene_->lights.infinite_le(ray);
    return Rgb();
  }

  // What scatters at a vertex, and direct lighting there: direct_lighting.h,
  // shared with sppm.
  using Scatter = VertexScatter;

  static Scatter surface_scatter(const Self& I, const SurfaceInteraction& si, const Bsdf& bsdf,
                                 uint32_t medium) {
    return rt::surface_scatter(*I.scene_, si, bsdf, medium);
  }

  static uint32_t medium_after(const Self& I, const SurfaceInteraction& si, Vec3 w,
                               uint32_t medium) {
    return rt::medium_after(*I.scene_, si, w, medium);
  }

  static Rgb estimate_direct(const Self& I, const Interaction& it, const Scatter& sc,
                             Vec2 u_scattering, uint32_t light, Vec2 u_light, Sampler& sampler,
                             RayCounters* c) {
    return rt::estimate_direct<kAreaLights, kInfinite>(*I.scene_, it, sc, u_scattering, light,
                                                       u_light, sampler, c);
  }

  template <bool kMedia, bool kLightOnly = false>
  static Rgb sample_one_light(const Self& I, const Interaction& it, const Scatter& sc,
                              Sampler& sampler, const LightDistribution* distribution,
                              RayCounters* c, const LightDistribution::Site* site = nullptr) {
    return rt::sample_one_light<kAreaLights, kInfinite, kMedia, kLightOnly>(
        *I.scene_, it, sc, sampler, distribution, c, site);
  }

  // The vertex a path's ray left: where, its light site, the ray's density there, and whether
  // the ray is that vertex's non-specular scattering sample (weigh), which counts the lights
  // it meets (weighted_emission).
  struct LeftVertex {
    Interaction it;
    LightDistribution::Site site;
    float pdf = 0;
    bool weigh = false;
  };

  // What the path's scattering sample from `from` meets of the lights, weighted by the power
  // heuristic against the light sample taken there: the other half of that vertex's direct
  // lighting. A light whose pdf_li is 0 there counts nothing, as in pbrt-v3's EstimateDirect.
  static Rgb weighted_emission(const Self& I, bool found, const SurfaceInteraction& si,
                               const RayDifferential& ray, const LeftVertex& from,
                               const MapDirection& escape) {
    const LightSet& lights = I.scene_->lights;
    Rgb l;
    if (found) {
      if constexpr (kAreaLights) {
        const uint32_t light = lights.area_light_at(si);
        if (light == kNone) return l;
        l = lights.area_le(si, -ray.d);
        if (l.is_black()) return l;
        const float light_pdf =
            I.distribution_.pmf(from.site, int(light)) * lights.pdf_li(light, from.it, ray.d, &si);
        return light_pdf == 0 ? Rgb() : l * power_heuristic(1, from.pdf, 1, light_pdf);
      }
      return l;
    }
    if constexpr (kInfinite)
      for (uint32_t light : lights.infinite_lights()) {
        float pdf_li = 0;
        const Rgb le = lights.infinite_le_one(light, ray, &pdf_li, escape);
        if (le.is_black()) continue;
        const float light_pdf = I.distribution_.pmf(from.site, int(light)) * pdf_li;
        if (light_pdf > 0) l += le * power_heuristic(1, from.pdf, 1, light_pdf);
      }
    return l;
  }

  static Rgb sample_all_lights(const Self& I, const SurfaceInteraction& it, const Bsdf& bsdf,
                               Sampler& sampler, RayCounters* c) {
    Rgb l;
    const Scatter sc = surface_scatter(I, it, bsdf, kNone);
    uint32_t n = I.scene_->lights.count();
    for (uint32_t j = 0; j < n; ++j) {
      int ns = I.light_samples_[j];
      const Vec2* u_light = sampler.get_2d_array(ns);
      const Vec2* u_scattering = sampler.get_2d_array(ns);
      if (!u_light || !u_scattering) {
        const bool delta = I.scene_->lights.is_delta(j);
        Vec2 ul = sampler.get_2d_if(!delta), us = sampler.get_2d_if(!delta);
        l += estimate_direct(I, it, sc, us, j, ul, sampler, c);
      } else {
        Rgb ld;
        for (int k = 0; k < ns; ++k)
          ld += estimate_direct(I, it, sc, u_scattering[k], j, u_light[k], sampler, c);
        l += ld / float(ns);
      }
    }
    return l;
  }

  // Perfect specular reflection or transmission, with pbrt-v3's ray differentials.
  static Rgb specular(const Self& I, const RayDifferential& ray, const SurfaceInteraction& si,
                      const Bsdf& bsdf, Sampler& sampler, int depth, bool transmit,
                      RayCounters* c) {
    Vec3 wo = si.wo, wi;
    float pdf = 0;
    uint8_t type = uint8_t((transmit ? kTransmission : kReflection) | kSpecular);
    Rgb f = bsdf.sample_f(wo, &wi, sampler.get_2d(), &pdf, type);
    Vec3 ns = si.shading.n;
    if (pdf <= 0 || f.is_black() || abs_dot(wi, ns) == 0) return Rgb();
    RayDifferential rd(si.spawn_ray(wi));
    if (ray.has_differentials) {
      rd.has_differentials = true;
      rd.rx_o = si.p + si.dpdx;
      rd.ry_o = si.p + si.dpdy;
      Vec3 dndx = si.shading.dndu * si.dudx + si.shading.dndv * si.dvdx;
      Vec3 dndy = si.shading.dndu * si.dudy + si.shading.dndv * si.dvdy;
      Vec3 dwodx = -ray.rx_d - wo, dwody = -ray.ry_d - wo;
      if (!transmit) {
        float ddndx = dot(dwodx, ns) + dot(wo, dndx);
        float ddndy = dot(dwody, ns) + dot(wo, dndy);
        rd.rx_d = wi - dwodx + 2.f * (dot(wo, ns) * dndx + ddndx * ns);
        rd.ry_d = wi - dwody + 2.f * (dot(wo, ns) * dndy + ddndy * ns);
      } else {
        float eta = 1 / bsdf.eta;
        if (dot(wo, ns) < 0) {
          eta = 1 / eta;
          ns = -ns;
          dndx = -dndx;
          dndy = -dndy;
        }
        float ddndx = dot(dwodx, ns) + dot(wo, dndx);
        float ddndy = dot(dwody, ns) + dot(wo, dndy);
        float mu = eta * dot(wo, ns) - abs_dot(wi, ns);
        float k = eta - (eta * eta * dot(wo, ns)) / abs_dot(wi, ns);
        rd.rx_d = wi - eta * dwodx + (mu * dndx + (k * ddndx) * ns);
        rd.ry_d = wi - eta * dwody + (mu * dndy + (k * ddndy) * ns);
      }
    }
    return f * li_recursive(I, rd, sampler, depth + 1, c) * (abs_dot(wi, ns) / pdf);
  }

  // Whitted and direct lighting share the recursive structure.
  static Rgb li_recursive(const Self& I, const RayDifferential& ray, Sampler& sampler, int depth,
                          RayCounters* c) {
    SurfaceInteraction si;
    if (!intersect(I, ray, &si, c)) return escaped(I, ray);
    Rgb l = emitted(I, si, si.wo);
    Bsdf bsdf;
    if (!scattering_at(*I.scene_, &si, ray, TransportMode::kRadiance, false, &bsdf))
      return l + li_recursive(I, RayDifferential(si.spawn_ray(ray.d)), sampler, depth, c);
    const LightSet& lights = I.scene_->lights;
    if (I.settings_.type == IntegratorType::kWhitted) {
      for (uint32_t j = 0; j < lights.count(); ++j) {
        LightSample ls;
        Rgb li = lights.sample_li(j, si, sampler.get_2d_if(!lights.is_delta(j)), &ls);
        if (li.is_black() || ls.pdf == 0) continue;
        Rgb f = bsdf.f(si.wo, ls.wi);
        if (f.is_black()) continue;
        ++c->shadow_rays;
        if (!I.scene_->geometry.occluded(si.spawn_ray_to(ls.p_light, ls.wi), ls.own_shape))
          l += f * li * (abs_dot(ls.wi, si.shading.n) / ls.pdf);
      }
    } else if (lights.count() > 0) {
      if (I.settings_.sample_all_lights)
        l += sample_all_lights(I, si, bsdf, sampler, c);
      else
        l += sample_one_light<false>(I, si, surface_scatter(I, si, bsdf, kNone), sampler, nullptr,
                                     c);
    }
    if (depth + 1 < I.settings_.max_depth)
      for (bool transmit : {false, true}) {
        // Without a lobe to sample, pbrt-v3's SpecularReflect/Transmit still draw their 2-D
        // sample; so do we, as a skip (the dimensions after it stay where they are), without
        // computing it: at every diffuse hit of a whitted or direct-lighting render.
        if (bsdf.num_components(uint8_t((transmit ? kTransmission : kReflection) | kSpecular)))
          l += specular(I, ray, si, bsdf, sampler, depth, transmit, c);
        else
          sampler.skip_2d();
      }
    return l;
  }

  static Rgb li_whitted_or_direct(const Self& I, const RayDifferential& ray, Sampler& sampler,
                                  RayCounters* c) {
    return li_recursive(I, ray, sampler, 0, c);
  }

  // pbrt-v3's path integrator; with kMedia, its volpath: rays carry the
  // medium they travel in, which may scatter them (a phase-function vertex
  // with its own light sample) before they reach the surface.
  //
  // A vertex's direct lighting is split as pbrt-v4's path integrator splits it: the light
  // sample is taken there, and the path's own next scattering sample stands for the scattering
  // sample pbrt-v3 traces separately (through the medium, with volpath), weighted where it
  // meets a light (weighted_emission). One traversal and one BSDF or phase sample a vertex
  // fewer; the same expectation (the weights depend on directions only, so any unbiased
  // transmittance along either ray keeps it).
  template <bool kMedia, bool kSubsurface>
  static Rgb li_path(const Self& I, const RayDifferential& camera_ray, Sampler& sampler,
                     RayCounters* c) {
    Rgb l, beta(1.f);
    RayDifferential ray = camera_ray;
    bool specular_bounce = false;
    float eta_scale = 1;
    LeftVertex from;      // path: weigh is cleared past an interface
    MapDirection escape;  // the BSDF sample's direction in the environment map
    const int max_depth = I.settings_.max_depth;
    uint32_t medium = kMedia ? I.scene_->camera_medium : kNone;
    for (int bounces = 0;; ++bounces) {
      SurfaceInteraction si;
      bool found = intersect_prefetching_light_site(I, ray, &si, c);
      LightDistribution::Site light_site;
      if (found) light_site = I.distribution_.site(si.p);
      if constexpr (kMedia) {
        bool scattered = false;
        Vec3 p;
        if (medium != kNone) {
          Ray seg = ray;
          if (found) seg.tmax = si.t_hit;
          beta *= I.scene_->media.sample(medium, seg, sampler, &scattered, &p);
        }
        if (beta.is_black()) break;
        if (scattered) {
          if (bounces >= max_depth) break;
          Interaction mi;
          mi.p = p;
          mi.wo = -ray.d;
          mi.time = ray.time;
          Scatter sc;
          sc.wo = mi.wo;
          sc.g = I.scene_->media[medium].g;
          sc.medium = medium;
          const LightDistribution::Site site = I.distribution_.site(mi.p);
          l += beta * sample_one_light<true, true>(I, mi, sc, sampler, &I.distribution_, c, &site);
          Vec3 wi;
          const float phase_pdf = sample_hg(mi.wo, sc.g, sampler.get_2d(), &wi);
          from = {mi, site, phase_pdf, true};
          ray = RayDifferential(mi.spawn_ray(wi));
          specular_bounce = false;
          if (!russian_roulette(I, &beta, eta_scale, bounces, sampler)) break;
          continue;
        }
      }
      // volpath's scattering sample passes through interfaces (pbrt-v3's IntersectTr): an
      // emitter on one counts nothing, and past the last vertex the sample still goes on
      // through one to find the light it stands for.
      const bool through = kMedia && found && I.scene_->shapes[si.shape].passes_through;
      if (bounces == 0 || specular_bounce) {
        if (found)
          l += beta * emitted(I, si, -ray.d);
        else
          l += beta * escaped(I, ray);
      } else if (from.weigh && !through) {
        l += beta * weighted_emission(I, found, si, ray, from, escape);
      }
      if (!found) break;
      if (bounces >= max_depth && !(through && from.weigh)) break;
      Bsdf bsdf;
      if (!scattering_at(*I.scene_, &si, ray, TransportMode::kRadiance, true, &bsdf)) {
        if constexpr (kMedia) medium = medium_after(I, si, ray.d, medium);
        // path's scattering sample (pbrt-v3's EstimateDirect) stops at the interface, whatever
        // lies behind it; volpath's goes on.
        if constexpr (!kMedia) from.weigh = false;
        ray = RayDifferential(si.spawn_ray(ray.d));
        --bounces;
        continue;
      }
      // Without media the light sample's values are drawn first, as ever, but it is taken after
      // the BSDF's sample: the environment map's table line it reads (a cache miss) loads
      // meanwhile. Nothing either computes depends on the other.
      LightPick pick;
      bool picked = false;
      if (bsdf.num_components(kAllBxdf & ~kSpecular) > 0) {
        if constexpr (kMedia) {
          l += beta * sample_one_light<kMedia, true>(I, si, surface_scatter(I, si, bsdf, medium),
                                                     sampler, &I.distribution_, c, &light_site);
        } else {
          picked = pick_light<true>(*I.scene_, si, sampler, &I.distribution_, &light_site, &pick);
          if (kInfinite && picked) I.scene_->lights.prefetch_sample(pick.light, pick.u);
        }
      }
      Vec3 wo = -ray.d, wi;
      float pdf = 0;
      uint8_t flags = 0;
      Rgb f = bsdf.sample_f(wo, &wi, sampler.get_2d(), &pdf, kAllBxdf, &flags);
      if (picked)
        l += beta * light_half<false>(*I.scene_, si, surface_scatter(I, si, bsdf, medium), pick,
                                      sampler, c);
      if (f.is_black() || pdf == 0) break;
      beta *= f * (abs_dot(wi, si.shading.n) / pdf);
      specular_bounce = flags & kSpecular;
      from = {si, light_site, pdf, !specular_bounce};
      if ((flags & kSpecular) && (flags & kTransmission)) {
        float eta = bsdf.eta;
        eta_scale *= dot(wo, si.n) > 0 ? eta * eta : 1 / (eta * eta);
      }
      const uint32_t arrived_in = medium;
      if constexpr (kMedia) medium = medium_after(I, si, wi, medium);
      ray = RayDifferential(si.spawn_ray(wi));
      escape = prefetch_escape(I, wi);
      if constexpr (kSubsurface) {
        // Light refracted into a subsurface material leaves it at a point the BSSRDF picks,
        // where it is lit directly and continues by the exit lobe.
        const uint32_t m = I.scene_->shapes[si.shape].material;
        Bssrdf bssrdf;
        if ((flags & kTransmission) && I.scene_->materials.compute_bssrdf(m, si, &bssrdf)) {
          SurfaceInteraction pi;
          float sp_pdf = 0;
          Rgb sp = sample_exit(I, bssrdf, si, sampler.get_1d(), sampler.get_2d(), &pi, &sp_pdf, c);
          if (sp.is_black() || sp_pdf == 0) break;
          beta *= sp / sp_pdf;
          Bsdf exit;
          exit.init(pi);
          exit.add(make_bssrdf_exit(bssrdf.eta, TransportMode::kRadiance));
          pi.wo = pi.shading.n;
          const LightDistribution::Site exit_site = I.distribution_.site(pi.p);
          l +=
              beta * sample_one_light<kMedia, true>(I, pi, surface_scatter(I, pi, exit, arrived_in),
                                                    sampler, &I.distribution_, c, &exit_site);
          float exit_pdf = 0;
          uint8_t exit_flags = 0;
          Rgb fe = exit.sample_f(pi.wo, &wi, sampler.get_2d(), &exit_pdf, kAllBxdf, &exit_flags);
          if (fe.is_black() || exit_pdf == 0) break;
          beta *= fe * (abs_dot(wi, pi.shading.n) / exit_pdf);
          specular_bounce = exit_flags & kSpecular;
          from = {pi, exit_site, exit_pdf, !specular_bounce};
          if constexpr (kMedia) medium = medium_after(I, pi, wi, arrived_in);
          ray = RayDifferential(pi.spawn_ray(wi));
        }
      }
      if (!russian_roulette(I, &beta, eta_scale, bounces, sampler)) break;
    }
    return l;
  }

  // pbrt-v3's SeparableBSSRDF::Sample_Sp: the probe chord's hits on the same
  // material, one picked uniformly; returns Sp there and its pdf (per area,
  // over the axes, channels and hits).
  static Rgb sample_exit(const Self& I, const Bssrdf& b, const SurfaceInteraction& po, float u1,
                         Vec2 u2, SurfaceInteraction* pi, float* pdf, RayCounters* c) {
    *pdf = 0;
    Vec3 start, target;
    float u_pick;
    if (!b.probe(u1, u2, &start, &target, &u_pick)) return Rgb();
    // A few hits suffice for any closed shape; a chord through more is cut short.
    constexpr int kMaxHits = 16;
    SurfaceInteraction hits[kMaxHits];
    int found = 0;
    Interaction base;
    base.p = start;
    base.time = po.time;
    for (int guard = 0; guard < 1024 && found < kMaxHits; ++guard) {
      Ray r = base.spawn_ray_to(target);
      if (r.d == Vec3{}) break;
      SurfaceInteraction& h = hits[found];
      if (!intersect(I, r, &h, c)) break;
      base = h;
      if (I.scene_->shapes[h.shape].material == b.material) ++found;
    }
    if (found == 0) return Rgb();
    *pi = hits[std::min(int(u_pick * float(found)), found - 1)];
    *pdf = b.pdf_sp(pi->p, pi->n) / float(found);
    return b.sr(length(po.p - pi->p));
  }

  // pbrt-v3's roulette after the fourth bounce; false: the path ends.
  static bool russian_roulette(const Self& I, Rgb* beta, float eta_scale, int bounces,
                               Sampler& sampler) {
    Rgb rr_beta = *beta * eta_scale;
    if (rr_beta.max_component() < I.settings_.rr_threshold && bounces > 3) {
      float q = std::max(0.05f, 1 - rr_beta.max_component());
      if (sampler.get_1d() < q) return false;
      *beta /= 1 - q;
    }
    return true;
  }

  // pbrt-v3's AOIntegrator: the unoccluded fraction of the hemisphere about
  // the geometric normal (facing the ray), cosine-weighted, times pi: an
  // open plane gives pi. The frame is (dpdu, n x dpdu, n) as pbrt-v3's, so
  // the same samples make the same rays.
  static Rgb li_ambient_occlusion(const Self& I, const RayDifferential& camera_ray,
                                  Sampler& sampler, RayCounters* c) {
    RayDifferential ray = camera_ray;
    SurfaceInteraction si;
    Bsdf bsdf;
    for (;;) {
      if (!intersect(I, ray, &si, c)) return Rgb();
      if (scattering_at(*I.scene_, &si, ray, TransportMode::kRadiance, true, &bsdf)) break;
      ray = RayDifferential(si.spawn_ray(ray.d));  // interface material: not a surface
    }
    Vec3 n = face_forward(si.n, -ray.d);
    Vec3 s = normalize(si.dpdu);
    Vec3 t = cross(si.n, s);
    const int ns = I.ao_samples_;
    const Vec2* u = sampler.get_2d_array(ns);
    float sum = 0;
    for (int i = 0; i < ns; ++i) {
      Vec2 ui = u ? u[i] : sampler.get_2d();
      Vec3 w;
      float pdf;
      if (I.settings_.cos_sample) {
        w = cosine_sample_hemisphere(ui);
        pdf = cosine_hemisphere_pdf(std::abs(w.z));
      } else {
        w = uniform_sample_hemisphere(ui);
        pdf = uniform_hemisphere_pdf();
      }
      // A sample on the disk's rim gives a grazing ray of pdf 0 (0/0 in pbrt-v3,
      // which then drops the whole camera sample as not-a-number); it adds nothing.
      if (pdf == 0) continue;
      Vec3 wi = s * w.x + t * w.y + n * w.z;
      ++c->shadow_rays;
      if (!I.scene_->geometry.occluded(si.spawn_ray(wi))) sum += dot(wi, n) / (pdf * ns);
    }
    return Rgb(sum);
  }

  static Rgb li_bdpt(const Self& I, const RayDifferential& ray, Sampler& sampler, RayCounters* c) {
    return I.bdpt_->li(ray, sampler, c);
  }

  static Integrator::Kernel pick(IntegratorType t, bool media, bool subsurface) {
    switch (t) {
      case IntegratorType::kBdpt:
        return &li_bdpt;
      case IntegratorType::kAmbientOcclusion:
        return &li_ambient_occlusion;
      case IntegratorType::kPath:
        return subsurface ? &li_path<false, true> : &li_path<false, false>;
      case IntegratorType::kVolPath:
        if (media) return subsurface ? &li_path<true, true> : &li_path<true, false>;
        return subsurface ? &li_path<false, true> : &li_path<false, false>;
      default:
        return &li_whitted_or_direct;
    }
  }
};

Integrator::Integrator() = default;
Integrator::~Integrator() = default;

bool Integrator::init(const RenderScene& scene, const IntegratorSettings& settings,
                      std::string* error, const Camera* camera, Film* film) {
  scene_ = &scene;
  settings_ = settings;
  if (settings.type == IntegratorType::kBdpt) {
    if (!camera || !film) {
      *error = "bdpt needs the camera and the film";
      return false;
    }
    bdpt_ = std::make_unique<Bdpt>();
    BdptVisualize v;
    v.strategies = settings.bdpt_visualize_strategies;
    v.weights = settings.bdpt_visualize_weights;
    if (!bdpt_->init(scene, *camera, film, settings.max_depth, settings.light_strategy, error, v))
      return false;
  }
  const bool path =
      settings.type == IntegratorType::kPath || settings.type == IntegratorType::kVolPath;
  if (path && !distribution_.build(scene.lights, scene.geometry.world_bounds(),
                                   settings.light_strategy, error))
    return false;
  const bool area = scene.effects & pbrta::kEffectAreaLights;
  const bool infinite = scene.effects & pbrta::kEffectInfiniteLights;
  const bool media = simulates_media(settings.type) && scene.media.size() > 0;
  const bool subsurface = scene.effects & pbrta::kEffectSubsurface;
  if (area && infinite)
    kernel_ = Kernels<true, true>::pick(settings.type, media, subsurface);
  else if (area)
    kernel_ = Kernels<true, false>::pick(settings.type, media, subsurface);
  else if (infinite)
    kernel_ = Kernels<false, true>::pick(settings.type, media, subsurface);
  else
    kernel_ = Kernels<false, false>::pick(settings.type, media, subsurface);
  return true;
}

bool Integrator::write_extra_images(const std::string& directory, std::string* error) const {
  return !bdpt_ || bdpt_->write_strategy_images(directory, error);
}

void Integrator::end_pass(bool keep, int64_t samples) const {
  if (bdpt_) bdpt_->end_pass(keep, samples);
}

void Integrator::preprocess(Sampler* sampler) {
  light_samples_.clear();
  if (bdpt_) return;
  if (settings_.type == IntegratorType::kAmbientOcclusion) {
    ao_samples_ = sampler->round_count(settings_.ao_samples);
    sampler->request_2d_array(ao_samples_);
    return;
  }
  if (settings_.type != IntegratorType::kDirectLighting || !settings_.sample_all_lights) return;
  const LightSet& lights = scene_->lights;
  for (uint32_t j = 0; j < lights.count(); ++j)
    light_samples_.push_back(sampler->round_count(
        std::max(1, lights.nsamples(j) / std::max(1, settings_.light_nsamples_divisor))));
  for (int d = 0; d < settings_.max_depth; ++d)
    for (uint32_t j = 0; j < lights.count(); ++j) {
      sampler->request_2d_array(light_samples_[j]);
      sampler->request_2d_array(light_samples_[j]);
    }
}

}  // namespace rt
