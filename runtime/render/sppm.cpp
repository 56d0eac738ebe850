// runtime/render/sppm.cpp — see sppm.h. The algorithm is the pbrt book's (3rd ed., 16.2).
#include "runtime/render/sppm.h"

#include <tbb/concurrent_vector.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <vector>

#include "runtime/core/atomic_add.h"
#include "runtime/core/clock.h"
#include "runtime/light/light_distribution.h"
#include "runtime/material/bsdf.h"
#include "runtime/render/direct_lighting.h"
#include "runtime/render/progress_bar.h"
#include "runtime/render/sppm_grid.h"
#include "runtime/sampler/pixel_seed.h"
#include "runtime/sampler/radical_inverse.h"
#include "runtime/sampler/sampler_kinds.h"

namespace rt {

namespace {

constexpr int kTileSize = 16;
// How much of a pass's photon count carries over into the next radius (the
// book's alpha; pbrt-v3 fixes it at 2/3).
constexpr float kGamma = 2.f / 3.f;

// The sample values of photon paths: coordinate `dim` of Halton point `index`.
// Seed 0: pbrt-v3's plain radical inverses; other seeds scramble the digits with
// permutations drawn from the seed, so renders with different seeds are independent.
class PhotonSequence {
 public:
  explicit PhotonSequence(uint64_t seed) : seed_(seed) {
    if (seed != 0)
      permutations_ =
          std::make_unique<DigitPermutations>(mix_seed(seed, SeedPurpose::kGlobalTable, 0x5bb3));
  }
  float get(uint64_t index, int dim) const {
    // pbrt-v3 has primes for 1000 dimensions and stops past them; paths that long are rare
    // enough that hashed values (unstratified, still unbiased) do.
    if (dim >= kHaltonDimensions) return hashed_uniform(seed_, Point2i{}, index, uint64_t(dim));
    const double v = permutations_ ? permutations_->scrambled(dim, index)
                                   : radical_inverse_of_dimension(dim, index);
    return std::min(float(v), kOneMinusEpsilon);
  }

 private:
  uint64_t seed_;
  std::unique_ptr<DigitPermutations> permutations_;
};

// pbrt-v3's UniformSampleOneLight at a surface, instantiated for the scene's effects.
using DirectLight = Rgb (*)(const RenderScene&, const SurfaceInteraction&, const Bsdf&, Sampler&,
                            RayCounters*);

template <bool kAreaLights, bool kInfinite>
Rgb direct_light(const RenderScene& scene, const SurfaceInteraction& si, const Bsdf& bsdf,
                 Sampler& sampler, RayCounters* c) {
  return sample_one_light<kAreaLights, kInfinite, false>(
      scene, si, surface_scatter(scene, si, bsdf, kNone), sampler, nullptr, c);
}

DirectLight pick_direct_light(uint64_t effects) {
  const bool area = effects & pbrta::kEffectAreaLights;
  const bool infinite = effects & pbrta::kEffectInfiniteLights;
  if (area && infinite) return &direct_light<true, true>;
  if (area) return &direct_light<true, false>;
  if (infinite) return &direct_light<false, true>;
  return &direct_light<false, false>;
}

// What a pixel keeps across iterations, and its visible point of this one (whose
// position and radius are in the grid's spheres, its BSDF in a separate array).
struct PixelState {
  Rgb ld;       // light the camera paths found directly, summed over iterations
  Rgb tau;      // photon flux, rescaled to the current radius
  float n = 0;  // photons accumulated so far (pbrt-v3's N: fractional)
  float radius = 0;
  Vec3 wo;   // the visible point's direction back along the camera path
  Rgb beta;  // its camera path weight; black: no visible point this iteration
};

// A pass's photons at one visible point. Atomic: photons of every thread add here.
struct PhotonSums {
  std::atomic<double> phi[3];
  std::atomic<int64_t> m;
};

struct ThreadCounters {
  RayCounters rays;
  uint64_t samples = 0, nonfinite = 0;
};

class SppmRender {
 public:
  SppmRender(const RenderScene& scene, const Camera& camera, Film* film, const SppmSettings& s,
             const RenderOptions& options)
      : scene_(scene),
        camera_(camera),
        sample_use_(camera.sample_use(scene.effects)),
        film_(film),
        settings_(s),
        bounds_(film->cropped_pixel_bounds()),
        width_(bounds_.width()),
        npixels_(size_t(bounds_.width()) * size_t(bounds_.height())),
        photons_(sppm_photons_per_iteration(s, *film)),
        direct_(pick_direct_light(scene.effects)),
        photon_sequence_(s.seed),
        pixels_(npixels_),
        spheres_(npixels_),
        visible_(npixels_),
        sums_(new PhotonSums[npixels_]) {
    for (PixelState& p : pixels_) p.radius = s.radius;
    for (size_t i = 0; i < npixels_; ++i) reset_sums(i);
    const int spp = options.differential_spp > 0 ? options.differential_spp : s.iterations;
    diff_scale_ = 1 / std::sqrt(float(spp));
    // One sample per pixel per iteration, over the cropped pixels as pbrt-v3's SPPM sets it up.
    camera_sampler_ = make_halton_sampler(s.iterations, s.seed, bounds_, false);
    // Photons leave lights chosen by power (pbrt-v3's ComputeLightPowerDistribution); that
    // strategy cannot fail.
    std::string unused;
    (void)light_choice_.build(scene.lights, scene.geometry.world_bounds(), "power", &unused);
  }

  bool empty() const { return npixels_ == 0; }

  void camera_pass(int iteration) {
    overflow_.clear();  // last iteration's visible points are gone
    const int nx = (bounds_.width() + kTileSize - 1) / kTileSize;
    const int ny = (bounds_.height() + kTileSize - 1) / kTileSize;
    tbb::parallel_for(
        tbb::blocked_range<int>(0, nx * ny, 1),
        [&](const tbb::blocked_range<int>& range) {
          ThreadCounters& tc = counters_.local();
          for (int t = range.begin(); t != range.end(); ++t) {
            const int x0 = bounds_.min.x + (t % nx) * kTileSize;
            const int y0 = bounds_.min.y + (t / nx) * kTileSize;
            std::unique_ptr<Sampler> sampler = camera_sampler_->clone();
            for (int y = y0; y < std::min(y0 + kTileSize, bounds_.max.y); ++y)
              for (int x = x0; x < std::min(x0 + kTileSize, bounds_.max.x); ++x)
                trace_camera_path({x, y}, iteration, *sampler, &tc);
          }
        },
        tbb::simple_partitioner());
  }

  void build_grid() { grid_.build(spheres_, uint32_t(npixels_)); }

  void photon_pass(int iteration) {
    if (scene_.lights.count() == 0) return;
    tbb::parallel_for(tbb::blocked_range<int64_t>(0, photons_, 8192),
                      [&](const tbb::blocked_range<int64_t>& range) {
                        ThreadCounters& tc = counters_.local();
                        for (int64_t j = range.begin(); j != range.end(); ++j)
                          trace_photon(uint64_t(iteration) * uint64_t(photons_) + uint64_t(j), &tc);
                      });
  }

  // pbrt-v3's progressive radius reduction; clears the visible points for the next iteration.
  void update() {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, npixels_, 4096),
                      [&](const tbb::blocked_range<size_t>& range) {
                        for (size_t i = range.begin(); i != range.end(); ++i) update_pixel(i);
                      });
  }

  void write_image(int iterations) {
    const double np = double(iterations) * double(photons_);
    for (size_t i = 0; i < npixels_; ++i) {
      const PixelState& px = pixels_[i];
      Rgb l = px.ld / float(iterations);
      const double area = np * kPi * double(px.radius) * double(px.radius);
      if (area > 0) l += px.tau * float(1 / area);
      film_->set_pixel(
          {bounds_.min.x + int(i % size_t(width_)), bounds_.min.y + int(i / size_t(width_))}, l);
    }
  }

  void add_stats(RenderStats* stats) const {
    for (const ThreadCounters& tc : counters_) {
      stats->samples += tc.samples;
      stats->nonfinite_samples += tc.nonfinite;
      stats->camera_rays += tc.rays.camera_rays;
      stats->rays += tc.rays.rays;
      stats->shadow_rays += tc.rays.shadow_rays;
    }
  }

 private:
  size_t index(Point2i p) const {
    return size_t(p.y - bounds_.min.y) * size_t(width_) + size_t(p.x - bounds_.min.x);
  }

  void reset_sums(size_t i) {
    for (auto& c : sums_[i].phi) c.store(0, std::memory_order_relaxed);
    sums_[i].m.store(0, std::memory_order_relaxed);
  }

  // The camera path of pixel p in this iteration: its direct light, and where it
  // first meets a diffuse surface (its visible point).
  void trace_camera_path(Point2i p, int iteration, Sampler& sampler, ThreadCounters* tc) {
    const size_t i = index(p);
    PixelState& px = pixels_[i];
    sampler.start_pixel(p);
    sampler.set_sample_number(iteration);
    const CameraSample cs = pixel_camera_sample(sampler, p, sample_use_);
    RayDifferential ray;
    const float weight = camera_.generate_ray_differential(cs, diff_scale_, &ray);
    ++tc->rays.camera_rays;
    ++tc->samples;
    if (weight == 0) return;

    const int max_depth = settings_.max_depth;
    Bsdf bsdf;
    Rgb beta(weight), ld;
    bool specular_bounce = false;
    bool visible = false;
    SurfaceInteraction si;
    for (int depth = 0; depth < max_depth; ++depth) {
      ++tc->rays.rays;
      if (!scene_.geometry.intersect(ray, &si)) {
        // pbrt-v3 adds the lights' Le of an escaping ray whatever the bounce before it.
        ld += beta * scene_.lights.infinite_le(ray);
        break;
      }
      if (!scattering_at(scene_, &si, ray, TransportMode::kRadiance, true, &bsdf)) {
        ray = RayDifferential(si.spawn_ray(ray.d));  // a medium boundary: not a vertex
        --depth;
        continue;
      }
      const Vec3 wo = -ray.d;
      if (depth == 0 || specular_bounce) ld += beta * scene_.lights.area_le(si, wo);
      ld += beta * direct_(scene_, si, bsdf, sampler, &tc->rays);
      const bool diffuse = bsdf.num_components(kDiffuse | kReflection | kTransmission) > 0;
      const bool glossy = bsdf.num_components(kGlossy | kReflection | kTransmission) > 0;
      if (diffuse || (glossy && depth == max_depth - 1)) {
        px.wo = wo;
        px.beta = beta;
        keep_visible_bsdf(i, bsdf);
        visible = true;
        break;
      }
      if (depth == max_depth - 1) break;
      Vec3 wi;
      float pdf = 0;
      uint8_t flags = 0;
      const Rgb f = bsdf.sample_f(wo, &wi, sampler.get_2d(), &pdf, kAllBxdf, &flags);
      if (pdf == 0 || f.is_black()) break;
      specular_bounce = flags & kSpecular;
      beta *= f * (abs_dot(wi, si.shading.n) / pdf);
      const float y = beta.luminance();
      if (y < 0.25f) {
        const float continue_probability = std::min(1.f, y);
        if (sampler.get_1d() > continue_probability) break;
        beta /= continue_probability;
      }
      ray = RayDifferential(si.spawn_ray(wi));
    }
    if (!ld.is_finite() || (visible && !px.beta.is_finite())) {
      ++tc->nonfinite;
      px.beta = Rgb();
      return;
    }
    px.ld += ld;
    if (visible && !px.beta.is_black()) spheres_[i] = {si.p, px.radius};
  }

  void trace_photon(uint64_t index, ThreadCounters* tc) {
    int dim = 0;
    auto next = [&] { return photon_sequence_.get(index, dim++); };
    float light_pmf = 0;
    const int light = light_choice_.lookup(Vec3{}).sample_discrete(next(), &light_pmf);
    if (light_pmf == 0) return;
    const Vec2 u_origin{next(), next()};
    const Vec2 u_direction{next(), next()};
    const float time = camera_.shutter_time(next());
    Ray emitted;
    Vec3 n_light;
    float pdf_pos = 0, pdf_dir = 0;
    const Rgb le = scene_.lights.sample_le(uint32_t(light), u_origin, u_direction, time, &emitted,
                                           &n_light, &pdf_pos, &pdf_dir);
    if (pdf_pos == 0 || pdf_dir == 0 || le.is_black()) return;
    Rgb beta = le * (abs_dot(n_light, emitted.d) / (light_pmf * pdf_pos * pdf_dir));
    if (beta.is_black()) return;

    RayDifferential ray(emitted);
    Bsdf bsdf;
    uint32_t skip = scene_.lights.shape_left_behind(uint32_t(light), emitted, n_light);
    for (int depth = 0; depth < settings_.max_depth; ++depth, skip = kNone) {
      SurfaceInteraction si;
      ++tc->rays.rays;
      if (!scene_.geometry.intersect(ray, &si, skip)) break;
      // The first hit is direct light, which the camera pass estimated already.
      if (depth > 0) deposit(si.p, -ray.d, beta, tc);
      if (!scattering_at(scene_, &si, ray, TransportMode::kImportance, true, &bsdf)) {
        ray = RayDifferential(si.spawn_ray(ray.d));
        --depth;
        continue;
      }
      const Vec3 wo = -ray.d;
      Vec3 wi;
      float pdf = 0;
      uint8_t flags = 0;
      const Vec2 u{next(), next()};
      const Rgb f = bsdf.sample_f(wo, &wi, u, &pdf, kAllBxdf, &flags);
      if (f.is_black() || pdf == 0) break;
      const Rgb beta_new = beta * f * (abs_dot(wi, si.shading.n) / pdf);
      // Roulette keeps the photon's luminance about constant: photons of one pass carry
      // similar power, which keeps the density estimate's variance down.
      const float q = std::max(0.f, 1 - beta_new.luminance() / beta.luminance());
      if (next() < q) break;
      beta = beta_new / (1 - q);
      ray = RayDifferential(si.spawn_ray(wi));
    }
  }

  void deposit(Vec3 p, Vec3 wi, Rgb beta, ThreadCounters* tc) {
    grid_.for_each_containing(p, [&](uint32_t i) {
      const Rgb phi = beta * visible_f(i, pixels_[i].wo, wi);
      if (!phi.is_finite()) {
        ++tc->nonfinite;
        return;
      }
      for (int c = 0; c < 3; ++c) atomic_add(&sums_[i].phi[c], phi[c]);
      sums_[i].m.fetch_add(1, std::memory_order_relaxed);
    });
  }

  void update_pixel(size_t i) {
    PixelState& px = pixels_[i];
    const int64_t m = sums_[i].m.load(std::memory_order_relaxed);
    if (m > 0) {
      const float n_new = px.n + kGamma * float(m);
      const float r_new = px.radius * std::sqrt(n_new / (px.n + float(m)));
      Rgb phi;
      for (int c = 0; c < 3; ++c) phi[c] = float(sums_[i].phi[c].load(std::memory_order_relaxed));
      px.tau = (px.tau + px.beta * phi) * (r_new * r_new / (px.radius * px.radius));
      px.n = n_new;
      px.radius = r_new;
      reset_sums(i);
    }
    px.beta = Rgb();
    spheres_[i].radius = -1;
  }

  // A visible point's BSDF, kept for the photon pass, which only evaluates f(): the frame and
  // the lobes, kInlineLobes of them in place (a diffuse point's material has one or two: matte,
  // plastic, substrate), a BSDF of more lobes whole in overflow_. A whole Bsdf per pixel was
  // 1016 bytes, this is 296: v3-caustic-glass-sppm's 2.8M pixels held 2.8 GB of them.
  static constexpr int kInlineLobes = 2;
  struct VisibleBsdf {
    BsdfFrame frame;
    int n = 0;
    uint32_t overflow = kNone;
    Bxdf lobes[kInlineLobes];
  };

  void keep_visible_bsdf(size_t i, const Bsdf& bsdf) {
    VisibleBsdf& v = visible_[i];
    v.frame = bsdf.frame();
    v.n = bsdf.num_lobes();
    v.overflow = kNone;
    if (v.n > kInlineLobes) {
      v.overflow = uint32_t(overflow_.push_back(bsdf) - overflow_.begin());
      return;
    }
    for (int k = 0; k < v.n; ++k) v.lobes[k] = bsdf.lobe(k);
  }

  Rgb visible_f(size_t i, Vec3 wo, Vec3 wi) const {
    const VisibleBsdf& v = visible_[i];
    if (v.overflow != kNone) return overflow_[v.overflow].f(wo, wi);
    return lobes_f(v.frame, v.lobes, v.n, wo, wi);
  }

  const RenderScene& scene_;
  const Camera& camera_;
  const CameraSampleUse sample_use_;  // what of each camera sample is drawn
  Film* film_;
  SppmSettings settings_;
  Bounds2i bounds_;
  int width_;
  size_t npixels_;
  int64_t photons_;
  DirectLight direct_;
  PhotonSequence photon_sequence_;
  float diff_scale_ = 1;
  std::unique_ptr<Sampler> camera_sampler_;
  LightDistribution light_choice_;
  std::vector<PixelState> pixels_;
  std::vector<GridSphere> spheres_;        // the visible points: position, the pixel's radius
  std::vector<VisibleBsdf> visible_;       // and BSDF
  tbb::concurrent_vector<Bsdf> overflow_;  // this iteration's BSDFs of more lobes
  std::unique_ptr<PhotonSums[]> sums_;
  SphereGrid grid_;
  tbb::enumerable_thread_specific<ThreadCounters> counters_;
};

}  // namespace

SppmSettings sppm_settings(const IntegratorSettings& settings, int spp_override, uint64_t seed) {
  SppmSettings s;
  s.iterations = spp_override > 0 ? spp_override : settings.sppm_iterations;
  s.photons_per_iteration = settings.sppm_photons_per_iteration;
  s.radius = settings.sppm_radius;
  s.max_depth = settings.max_depth;
  s.seed = seed;
  return s;
}

int64_t sppm_photons_per_iteration(const SppmSettings& settings, const Film& film) {
  if (settings.photons_per_iteration > 0) return settings.photons_per_iteration;
  const Bounds2i b = film.cropped_pixel_bounds();
  return int64_t(b.width()) * int64_t(b.height());
}

RenderStats render_sppm(const RenderScene& scene, const Camera& camera, Film* film,
                        const SppmSettings& settings, const RenderOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  RenderStats stats;
  SppmRender r(scene, camera, film, settings, options);
  if (r.empty() || settings.iterations < 1) return stats;
  {
    // Two units per iteration: the camera pass and the photon pass.
    ProgressBar progress(2 * int64_t(settings.iterations), options.quiet);
    for (int it = 0; it < settings.iterations; ++it) {
      r.camera_pass(it);
      progress.add(1);
      r.build_grid();
      r.photon_pass(it);
      r.update();
      progress.add(1);
      if (it == 0) stats.first_tile_seconds = seconds_since(t0);
    }
  }
  r.write_image(settings.iterations);
  r.add_stats(&stats);
  stats.iterations = uint64_t(settings.iterations);
  stats.photons =
      uint64_t(settings.iterations) * uint64_t(sppm_photons_per_iteration(settings, *film));
  stats.seconds = seconds_since(t0);
  return stats;
}

}  // namespace rt
