// runtime/render/subpaths.cpp — see subpaths.h. The algorithms are the pbrt book's (3rd ed., 16.3).
#include "runtime/render/subpaths.h"

#include <cmath>

#include "runtime/medium/phase.h"

namespace rt {

namespace {

// pbrt-v3's CorrectShadingNormal: importance carried across a shading normal is not
// symmetric with radiance; this factor restores what the adjoint BSDF owes.
float shading_normal_correction(const SurfaceInteraction& si, Vec3 wo, Vec3 wi,
                                TransportMode mode) {
  if (mode != TransportMode::kImportance) return 1;
  float num = abs_dot(wo, si.shading.n) * abs_dot(wi, si.n);
  float denom = abs_dot(wo, si.n) * abs_dot(wi, si.shading.n);
  return denom == 0 ? 0 : num / denom;
}

}  // namespace

bool Subpaths::is_light(const Vertex& v) const {
  return v.type == VertexType::kLight || (v.type == VertexType::kSurface && v.area_light != kNone);
}
bool Subpaths::is_infinite_light(const Vertex& v) const {
  return v.type == VertexType::kLight && v.infinite;
}
bool Subpaths::is_delta_light(const Vertex& v) const {
  return v.type == VertexType::kLight && v.light != kNone && scene.lights.is_delta(v.light);
}
bool Subpaths::connectible(const Vertex& v) const {
  switch (v.type) {
    case VertexType::kLight:
      return v.light == kNone || scene.lights.kind(v.light) != LightKind::kDistant;
    case VertexType::kCamera:
      return true;
    case VertexType::kSurface:
      return v.bsdf.num_components(kDiffuse | kGlossy | kReflection | kTransmission) > 0;
    case VertexType::kMedium:
      return true;
  }
  return false;
}

// A solid-angle density at `from` towards `next`, as an area density at next.
float Subpaths::convert_density(const Vertex& from, float pdf, const Vertex& next) const {
  if (is_infinite_light(next)) return pdf;
  Vec3 w = next.p() - from.p();
  float d2 = length_squared(w);
  if (d2 == 0) return 0;
  // One division: the cosine's normalisation and the squared distance together.
  if (next.on_surface()) return pdf * abs_dot(next.ng(), w) / (d2 * std::sqrt(d2));
  return pdf / d2;
}

Rgb Subpaths::f(const Vertex& v, const Vertex& next, TransportMode mode) const {
  if (v.type != VertexType::kSurface && v.type != VertexType::kMedium) return Rgb();
  Vec3 wi = next.p() - v.p();
  if (length_squared(wi) == 0) return Rgb();
  wi = normalize(wi);
  if (v.type == VertexType::kMedium) return Rgb(phase_hg(dot(v.si.wo, wi), v.g));
  return v.bsdf.f(v.si.wo, wi) * shading_normal_correction(v.si, v.si.wo, wi, mode);
}

// Emission from light vertex v towards vertex `to`.
Rgb Subpaths::le(const Vertex& v, const Vertex& to) const {
  if (!is_light(v)) return Rgb();
  Vec3 w = to.p() - v.p();
  if (length_squared(w) == 0) return Rgb();
  w = normalize(w);
  if (is_infinite_light(v)) return scene.lights.infinite_le(RayDifferential(Ray{v.p(), -w}));
  return scene.lights.area_le(v.si, w);
}

// pbrt-v3's InfiniteLightDensity: the density of choosing an infinite light and sampling
// direction -w from it (w leaves the light).
float Subpaths::infinite_light_density(Vec3 w) const {
  float pdf = 0;
  for (uint32_t l = 0; l < scene.lights.count(); ++l)
    if (scene.lights.kind(l) == LightKind::kInfinite)
      pdf += scene.lights.pdf_li(l, Interaction{}, -w, nullptr) * choice->discrete_pdf(int(l));
  return pdf;
}

// The area density with which light vertex v would emit towards next.
float Subpaths::pdf_light(const Vertex& v, const Vertex& next) const {
  Vec3 w = next.p() - v.p();
  float d2 = length_squared(w);
  if (d2 == 0) return 0;
  w = w / std::sqrt(d2);
  float pdf;
  if (is_infinite_light(v)) {
    pdf = 1 / (kPi * world_radius * world_radius);
  } else {
    uint32_t light = v.type == VertexType::kLight ? v.light : v.area_light;
    float pdf_pos = 0, pdf_dir = 0;
    scene.lights.pdf_le(light, Ray{v.p(), w, kInfinity, v.si.time}, v.ng(), &pdf_pos, &pdf_dir);
    pdf = pdf_dir / d2;
  }
  if (next.on_surface()) pdf *= abs_dot(next.ng(), w);
  return pdf;
}

// The density of light vertex v as the origin of a light subpath going towards next.
float Subpaths::pdf_light_origin(const Vertex& v, const Vertex& next) const {
  Vec3 w = next.p() - v.p();
  if (length_squared(w) == 0) return 0;
  w = normalize(w);
  if (is_infinite_light(v)) return infinite_light_density(w);
  uint32_t light = v.type == VertexType::kLight ? v.light : v.area_light;
  float pdf_pos = 0, pdf_dir = 0;
  scene.lights.pdf_le(light, Ray{v.p(), w, kInfinity, v.si.time}, v.ng(), &pdf_pos, &pdf_dir);
  return pdf_pos * choice->discrete_pdf(int(light));
}

// The area density at next of sampling it from v, having arrived from prev.
float Subpaths::pdf(const Vertex& v, const Vertex* prev, const Vertex& next) const {
  if (v.type == VertexType::kLight) return pdf_light(v, next);
  Vec3 wn = next.p() - v.p();
  if (length_squared(wn) == 0) return 0;
  wn = normalize(wn);
  float pdf = 0;
  if (v.type == VertexType::kCamera) {
    float pdf_pos = 0;
    camera.pdf_we(Ray{v.p(), wn, kInfinity, v.si.time}, &pdf_pos, &pdf);
  } else {
    Vec3 wp = prev->p() - v.p();
    if (length_squared(wp) == 0) return 0;
    wp = normalize(wp);
    pdf = v.type == VertexType::kMedium ? phase_hg(dot(wp, wn), v.g) : v.bsdf.pdf(wp, wn);
  }
  return convert_density(v, pdf, next);
}

Rgb Subpaths::end_f(const Vertex& v, const Vertex* prev, const Vertex& other, TransportMode mode,
                    bool* known, float* to_other, float* to_prev) const {
  *known = prev && v.type == VertexType::kSurface;
  if (!*known) return f(v, other, mode);
  Vec3 wi = other.p() - v.p();
  if (length_squared(wi) == 0) {
    *to_other = *to_prev = 0;
    return Rgb();
  }
  wi = normalize(wi);
  // The walk's own direction back to prev (f's wo), for the densities too.
  const Vec3 wo = v.si.wo;
  float ab, ba;
  const Rgb value =
      v.bsdf.f_pdf_both(wo, wi, &ab, &ba) * shading_normal_correction(v.si, wo, wi, mode);
  *to_other = convert_density(v, ab, other);
  *to_prev = convert_density(v, ba, *prev);
  return value;
}

// The medium a ray leaving vertex v along w travels in: a surface that bounds two media
// changes it (pbrt-v3's GetMedium).
uint32_t Subpaths::medium_toward(const Vertex& v, Vec3 w) const {
  if (v.type != VertexType::kSurface) return v.medium;
  return medium_after(scene, v.si, w, v.medium);
}

// What reaches `to` from vertex `from`: 0 behind a surface, else the media's transmittance.
Rgb Subpaths::visibility(const Vertex& from, const Interaction& to) const {
  ++counters->shadow_rays;
  return transmittance(scene, from.si, to, medium_toward(from, to.p - from.p()), sampler, counters);
}

// The geometric term between two vertices, with their visibility.
Rgb Subpaths::g(const Vertex& v0, const Vertex& v1) const {
  Vec3 d = v0.p() - v1.p();
  float g = 1 / length_squared(d);
  d = d * std::sqrt(g);
  if (v0.on_surface()) g *= abs_dot(v0.ns(), d);
  if (v1.on_surface()) g *= abs_dot(v1.ns(), d);
  return visibility(v0, v1.si) * g;
}

// A walk from ray, filling path[0 ..) (path[-1] is where it starts); pdf is the
// solid-angle density of ray's direction. pbrt-v3's RandomWalk: no Russian roulette.
int Subpaths::random_walk(RayDifferential ray, uint32_t medium, Rgb beta, float pdf, int max_depth,
                          TransportMode mode, Vertex* path, uint32_t skip_first) const {
  if (max_depth == 0) return 0;
  int bounces = 0;
  float pdf_fwd = pdf, pdf_rev = 0;
  for (uint32_t skip = skip_first;; skip = kNone) {
    SurfaceInteraction si;
    ++counters->rays;
    const bool found = scene.geometry.intersect(ray, &si, skip);
    bool scattered = false;
    Vec3 p;
    if (medium != kNone) {
      Ray segment = ray;
      if (found) segment.tmax = si.t_hit;
      beta *= scene.media.sample(medium, segment, sampler, &scattered, &p);
    }
    if (beta.is_black()) break;
    Vertex& v = path[bounces];
    Vertex& prev = path[bounces - 1];
    if (scattered) {
      // A medium vertex: the phase function is its BSDF, and its own inverse density.
      v.reset_except_bsdf();
      v.type = VertexType::kMedium;
      v.medium = medium;
      v.g = scene.media[medium].g;
      v.si.p = p;
      v.si.wo = -ray.d;
      v.si.time = ray.time;
      v.beta = beta;
      v.pdf_fwd = convert_density(prev, pdf_fwd, v);
      if (++bounces >= max_depth) break;
      Vec3 wi;
      pdf_fwd = pdf_rev = sample_hg(v.si.wo, v.g, sampler.get_2d(), &wi);
      ray = RayDifferential(Ray{p, wi, kInfinity, ray.time});
      prev.pdf_rev = convert_density(v, pdf_rev, prev);
      continue;
    }
    if (!found) {
      // Light from infinity, seen by the camera path.
      if (mode == TransportMode::kRadiance) {
        v.reset_except_bsdf();
        v.type = VertexType::kLight;
        v.infinite = true;
        v.si.p = ray.at(1);
        v.si.n = -ray.d;
        v.si.time = ray.time;
        v.beta = beta;
        v.pdf_fwd = pdf_fwd;
        ++bounces;
      }
      break;
    }
    if (!scattering_at(scene, &si, ray, mode, true, &v.bsdf)) {
      medium = medium_after(scene, si, ray.d, medium);  // a medium boundary, not a surface
      ray = RayDifferential(si.spawn_ray(ray.d));
      continue;
    }
    v.type = VertexType::kSurface;
    v.medium = medium;
    v.delta = false;
    v.infinite = false;
    v.light = kNone;
    v.area_light = scene.lights.area_light_at(si);
    v.si = si;
    v.beta = beta;
    v.pdf_rev = 0;
    v.pdf_fwd = convert_density(prev, pdf_fwd, v);
    if (++bounces >= max_depth) break;
    Vec3 wi, wo = si.wo;
    uint8_t flags = 0;
    Rgb f = v.bsdf.sample_f(wo, &wi, sampler.get_2d(), &pdf_fwd, kAllBxdf, &flags);
    if (f.is_black() || pdf_fwd == 0) break;
    beta *= f * (abs_dot(wi, si.shading.n) / pdf_fwd);
    pdf_rev = v.bsdf.pdf(wi, wo);
    if (flags & kSpecular) {
      v.delta = true;
      pdf_rev = pdf_fwd = 0;
    }
    beta *= shading_normal_correction(si, wo, wi, mode);
    medium = medium_after(scene, si, wi, medium);
    ray = RayDifferential(si.spawn_ray(wi));
    prev.pdf_rev = convert_density(v, pdf_rev, prev);
  }
  return bounces;
}

int Subpaths::camera_subpath(const RayDifferential& ray, int max_depth, Vertex* path) const {
  if (max_depth == 0) return 0;
  Vertex& c = path[0];
  c.reset_except_bsdf();
  c.type = VertexType::kCamera;
  c.si.p = ray.o;
  c.si.time = ray.time;
  c.beta = Rgb(1.f);
  c.medium = scene.camera_medium;
  float pdf_pos = 0, pdf_dir = 0;
  camera.pdf_we(ray, &pdf_pos, &pdf_dir);
  return random_walk(ray, c.medium, c.beta, pdf_dir, max_depth - 1, TransportMode::kRadiance,
                     path + 1) +
         1;
}

int Subpaths::light_subpath(int max_depth, float time, Vertex* path) const {
  if (max_depth == 0 || scene.lights.count() == 0) return 0;
  float light_pmf = 0;
  const int light = choice->sample_discrete(sampler.get_1d(), &light_pmf);
  if (light_pmf == 0) return 0;
  Ray ray;
  Vec3 n_light;
  float pdf_pos = 0, pdf_dir = 0;
  const Vec2 u1 = sampler.get_2d(), u2 = sampler.get_2d();
  Rgb le =
      scene.lights.sample_le(uint32_t(light), u1, u2, time, &ray, &n_light, &pdf_pos, &pdf_dir);
  if (pdf_pos == 0 || pdf_dir == 0 || le.is_black()) return 0;
  Vertex& v = path[0];
  v.reset_except_bsdf();
  v.type = VertexType::kLight;
  v.light = uint32_t(light);
  const LightKind kind = scene.lights.kind(v.light);
  v.infinite = kind == LightKind::kInfinite || kind == LightKind::kDistant;
  v.si.p = ray.o;
  v.si.n = n_light;
  v.si.time = time;
  v.beta = le;
  v.pdf_fwd = pdf_pos * light_pmf;
  v.medium = scene.lights.emission_medium(v.light, ray.d, n_light);
  Rgb beta = le * (abs_dot(n_light, ray.d) / (light_pmf * pdf_pos * pdf_dir));
  int n = random_walk(RayDifferential(ray), v.medium, beta, pdf_dir, max_depth - 1,
                      TransportMode::kImportance, path + 1,
                      scene.lights.shape_left_behind(v.light, ray, n_light));
  if (v.infinite) {
    // Lights at infinity: the first hit's density is the emission disk's, projected; the
    // light's own is that of sampling its direction.
    if (n > 0) {
      path[1].pdf_fwd = pdf_pos;
      if (path[1].on_surface()) path[1].pdf_fwd *= abs_dot(ray.d, path[1].ng());
    }
    v.pdf_fwd = infinite_light_density(ray.d);
  }
  return n + 1;
}

// pbrt-v3's MISWeight: the power heuristic over every strategy that could make the path of
// s light and t camera vertices, from ratios of reverse to forward densities.
float Subpaths::mis_weight(const Vertex* light_path, const Vertex* camera_path,
                           const Vertex& sampled, int s, int t,
                           const JoinedDensities& known) const {
  if (s + t == 2) return 1;
  const Vertex* qs = s > 0 ? &light_path[s - 1] : nullptr;
  const Vertex* pt = t > 0 ? &camera_path[t - 1] : nullptr;
  const Vertex* qs_minus = s > 1 ? &light_path[s - 2] : nullptr;
  const Vertex* pt_minus = t > 1 ? &camera_path[t - 2] : nullptr;
  if (s == 1)
    qs = &sampled;
  else if (t == 1)
    pt = &sampled;
  // The joined ends' reverse densities, which neither walk knew.
  // A surface end's two (toward the other end and back along its own path) came with its f
  // (end_f); a medium vertex's are found here.
  float pt_rev = 0, pt_minus_rev = 0, qs_rev = 0, qs_minus_rev = 0;
  if (s == 0) {
    pt_rev = pdf_light_origin(*pt, *pt_minus);
  } else if (known.qs) {
    pt_rev = known.pt_rev;
    qs_minus_rev = known.qs_minus_rev;
  } else if (qs_minus) {
    pt_rev = pdf(*qs, qs_minus, *pt);
    qs_minus_rev = pdf(*qs, pt, *qs_minus);
  } else {
    pt_rev = pdf(*qs, nullptr, *pt);
  }
  if (s == 0) {
    pt_minus_rev = pt_minus ? pdf_light(*pt, *pt_minus) : 0;
  } else if (known.pt) {
    qs_rev = known.qs_rev;
    pt_minus_rev = known.pt_minus_rev;
  } else if (pt_minus) {
    qs_rev = pdf(*pt, pt_minus, *qs);
    pt_minus_rev = pdf(*pt, qs, *pt_minus);
  } else {
    qs_rev = pdf(*pt, nullptr, *qs);
  }
  auto remap0 = [](float f) { return f != 0 ? f : 1.f; };

  float sum = 0, ri = 1;
  for (int i = t - 1; i > 0; --i) {
    const Vertex& v = i == t - 1 ? *pt : camera_path[i];
    const float rev = i == t - 1 ? pt_rev : i == t - 2 ? pt_minus_rev : v.pdf_rev;
    ri *= remap0(rev) / remap0(v.pdf_fwd);
    const bool delta = i != t - 1 && v.delta;
    if (!delta && !camera_path[i - 1].delta) sum += ri;
  }
  ri = 1;
  for (int i = s - 1; i >= 0; --i) {
    const Vertex& v = i == s - 1 ? *qs : light_path[i];
    const float rev = i == s - 1 ? qs_rev : i == s - 2 ? qs_minus_rev : v.pdf_rev;
    ri *= remap0(rev) / remap0(v.pdf_fwd);
    const bool delta = i != s - 1 && v.delta;
    const bool delta_before =
        i > 0 ? light_path[i - 1].delta : is_delta_light(s == 1 ? *qs : light_path[0]);
    if (!delta && !delta_before) sum += ri;
  }
  return 1 / (1 + sum);
}

// pbrt-v3's ConnectBDPT: the contribution of strategy (s, t), MIS-weighted; for t = 1 also
// the raster point it lands on.
Rgb Subpaths::connect(const Vertex* light_path, const Vertex* camera_path, int s, int t,
                      Vec2* p_raster, float* mis) const {
  if (t > 1 && s != 0 && camera_path[t - 1].type == VertexType::kLight) return Rgb();
  Rgb l;
  Vertex sampled;
  JoinedDensities known;
  if (s == 0) {
    const Vertex& pt = camera_path[t - 1];
    if (is_light(pt)) l = le(pt, camera_path[t - 2]) * pt.beta;
  } else if (t == 1) {
    const Vertex& qs = light_path[s - 1];
    if (!connectible(qs)) return Rgb();
    Vec3 wi;
    float pdf = 0;
    Interaction lens;
    Rgb we = camera.sample_wi(qs.si, sampler.get_2d(), &wi, &pdf, p_raster, &lens);
    if (pdf > 0 && !we.is_black()) {
      sampled.type = VertexType::kCamera;
      sampled.si.p = lens.p;
      sampled.si.n = lens.n;
      sampled.si.time = lens.time;
      sampled.beta = we / pdf;
      const Rgb fq =
          end_f(qs, s > 1 ? &light_path[s - 2] : nullptr, sampled, TransportMode::kImportance,
                &known.qs, &known.pt_rev, &known.qs_minus_rev);
      l = qs.beta * fq * sampled.beta;
      if (qs.on_surface()) l *= abs_dot(wi, qs.ns());
      if (!l.is_black()) l *= visibility(qs, lens);
    }
  } else if (s == 1) {
    const Vertex& pt = camera_path[t - 1];
    if (!connectible(pt)) return Rgb();
    float light_pmf = 0;
    const int light = choice->sample_discrete(sampler.get_1d(), &light_pmf);
    LightSample ls;
    Rgb lw = scene.lights.sample_li(
        uint32_t(light), pt.si, sampler.get_2d_if(!scene.lights.is_delta(uint32_t(light))), &ls);
    if (ls.pdf > 0 && light_pmf > 0 && !lw.is_black()) {
      sampled.type = VertexType::kLight;
      sampled.light = uint32_t(light);
      const LightKind kind = scene.lights.kind(sampled.light);
      sampled.infinite = kind == LightKind::kInfinite || kind == LightKind::kDistant;
      static_cast<Interaction&>(sampled.si) = ls.p_light;
      sampled.beta = lw / (ls.pdf * light_pmf);
      sampled.pdf_fwd = pdf_light_origin(sampled, pt);
      const Rgb fp = end_f(pt, t > 1 ? &camera_path[t - 2] : nullptr, sampled,
                           TransportMode::kRadiance, &known.pt, &known.qs_rev, &known.pt_minus_rev);
      l = pt.beta * fp * sampled.beta;
      if (pt.on_surface()) l *= abs_dot(ls.wi, pt.ns());
      if (!l.is_black()) l *= visibility(pt, ls.p_light);
    }
  } else {
    const Vertex& qs = light_path[s - 1];
    const Vertex& pt = camera_path[t - 1];
    if (connectible(qs) && connectible(pt)) {
      const Rgb fq = end_f(qs, &light_path[s - 2], pt, TransportMode::kImportance, &known.qs,
                           &known.pt_rev, &known.qs_minus_rev);
      const Rgb fp = end_f(pt, &camera_path[t - 2], qs, TransportMode::kRadiance, &known.pt,
                           &known.qs_rev, &known.pt_minus_rev);
      l = qs.beta * fq * fp * pt.beta;
      if (!l.is_black()) l *= g(qs, pt);
    }
  }
  if (mis) *mis = 0;
  if (l.is_black()) return l;
  const float w = mis_weight(light_path, camera_path, sampled, s, t, known);
  if (mis) *mis = w;
  return l * w;
}

}  // namespace rt
