// runtime/render/mlt.cpp — see mlt.h. The algorithm is the pbrt book's (3rd ed., 16.4).
#include "runtime/render/mlt.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <vector>

#include "runtime/core/clock.h"
#include "runtime/light/light_distribution.h"
#include "runtime/render/mlt_sampler.h"
#include "runtime/render/progress_bar.h"
#include "runtime/render/subpaths.h"

namespace rt {

namespace {

// The sampler's streams: camera subpath, light subpath, connection.
constexpr int kCameraStream = 0, kLightStream = 1, kConnectionStream = 2, kStreams = 3;

struct Paths {
  const RenderScene& scene;
  const Camera& camera;
  const Film& film;
  const LightDistribution& lights;
  float world_radius;
  int64_t mutations_per_pixel;
  std::atomic<uint64_t>* nonfinite;  // paths whose value was NaN or infinite (counted as 0)

  // The value of the sampler's current point as a path of `depth` bounces, and its film point.
  Rgb l(MltSampler& sampler, int depth, Vec2* p_raster, RayCounters* counters) const {
    thread_local PathBuffers buffers;
    sampler.start_stream(kCameraStream);
    int s, t, strategies;
    if (depth == 0) {
      strategies = 1;
      s = 0;
      t = 2;
    } else {
      strategies = depth + 2;
      s = std::min(int(sampler.get_1d() * float(strategies)), strategies - 1);
      t = strategies - s;
    }
    const Bounds2i b = film.sample_bounds();
    const Vec2 u = sampler.get_2d();
    *p_raster = {lerp(u.x, float(b.min.x), float(b.max.x)),
                 lerp(u.y, float(b.min.y), float(b.max.y))};
    CameraSample cs;
    cs.p_film = *p_raster;
    cs.time = sampler.get_1d();
    cs.p_lens = sampler.get_2d();
    RayDifferential ray;
    if (camera.generate_ray_differential(cs, 1 / std::sqrt(float(mutations_per_pixel)), &ray) == 0)
      return Rgb();
    ++counters->camera_rays;
    buffers.reserve(size_t(std::max(s, t)) + 1);
    Vertex* cam = buffers.camera_path();
    Vertex* lig = buffers.light_path();
    Subpaths paths{scene, camera, world_radius, &lights.lookup(ray.o), sampler, counters};
    if (paths.camera_subpath(ray, t, cam) != t) return Rgb();
    sampler.start_stream(kLightStream);
    if (paths.light_subpath(s, cam[0].si.time, lig) != s) return Rgb();
    sampler.start_stream(kConnectionStream);
    Rgb l = paths.connect(lig, cam, s, t, p_raster) * float(strategies);
    ++counters->paths;
    counters->zero_radiance_paths += l.is_black();
    if (!l.is_finite()) {
      ++*nonfinite;
      return Rgb();
    }
    return l;
  }
};

}  // namespace

MltSettings mlt_settings(const IntegratorSettings& settings, int spp_override, uint64_t seed) {
  MltSettings ms;
  ms.max_depth = settings.max_depth;
  ms.bootstrap_samples = settings.mlt_bootstrap;
  ms.chains = settings.mlt_chains;
  ms.mutations_per_pixel = spp_override > 0 ? spp_override : settings.mlt_mutations_per_pixel;
  ms.large_step_probability = settings.mlt_large_step_probability;
  ms.sigma = settings.mlt_sigma;
  ms.seed = seed;
  return ms;
}

bool render_mlt(const RenderScene& scene, const Camera& camera, Film* film,
                const MltSettings& settings, const RenderOptions& options, RenderStats* stats,
                std::string* error) {
  auto t0 = std::chrono::steady_clock::now();
  *stats = RenderStats{};
  if (!camera.supports_importance()) {
    *error =
        "not supported: mlt needs a perspective camera (pbrt-v3's other cameras have no "
        "importance function either)";
    return false;
  }
  LightDistribution lights;
  if (!lights.build(scene.lights, scene.geometry.world_bounds(), "power", error)) return false;
  Vec3 center;
  float radius;
  scene.geometry.world_bounds().bounding_sphere(&center, &radius);
  const int depths = settings.max_depth + 1;
  std::atomic<uint64_t> nonfinite{0}, accepted{0};
  const Paths paths{scene, camera, *film, lights, radius, settings.mutations_per_pixel, &nonfinite};
  tbb::enumerable_thread_specific<RayCounters> counters;

  // Bootstrap: the luminance of independent paths of every depth.
  const int64_t n_bootstrap = settings.bootstrap_samples * depths;
  std::vector<float> weights(static_cast<size_t>(n_bootstrap));
  // One sampler per thread, restarted for each path (as if made anew), so that its storage
  // is allocated once, not once per path.
  tbb::enumerable_thread_specific<MltSampler> bootstrap_samplers(
      settings.mutations_per_pixel, uint64_t(0), settings.sigma, settings.large_step_probability,
      kStreams, settings.seed);
  tbb::parallel_for(int64_t(0), settings.bootstrap_samples, [&](int64_t i) {
    RayCounters& c = counters.local();
    MltSampler& sampler = bootstrap_samplers.local();
    for (int depth = 0; depth < depths; ++depth) {
      const int64_t index = i * depths + depth;
      sampler.restart(uint64_t(index));
      Vec2 p;
      weights[size_t(index)] = std::max(0.f, paths.l(sampler, depth, &p, &c).luminance());
    }
  });
  Distribution1D bootstrap(weights.data(), int(n_bootstrap));
  const float b = bootstrap.integral() * float(depths);
  film->enable_splats();
  film->set_splat_scale(b / float(settings.mutations_per_pixel));
  if (!(b > 0)) return true;  // nothing reaches the camera: a black image

  const int64_t total = settings.mutations_per_pixel * film->sample_bounds().area();
  const int chains = std::max(1, settings.chains);
  ProgressBar progress(total, options.quiet);  // in mutations
  tbb::parallel_for(0, chains, [&](int i) {
    RayCounters& c = counters.local();
    const int64_t first = int64_t(i) * total / chains;
    const int64_t mutations = std::min(int64_t(i + 1) * total / chains, total) - first;
    Rng rng(settings.seed, uint64_t(i));
    const int index = bootstrap.sample_discrete(rng.next_float());
    const int depth = index % depths;
    MltSampler sampler(settings.mutations_per_pixel, uint64_t(index), settings.sigma,
                       settings.large_step_probability, kStreams, settings.seed);
    Vec2 p_current;
    Rgb l_current = paths.l(sampler, depth, &p_current, &c);
    // Counted per chain: one shared counter bumped per mutation bounces its cache line
    // between the cores.
    uint64_t chain_accepted = 0;
    for (int64_t j = 0; j < mutations; ++j) {
      if ((j & 1023) == 1023) progress.add(1024);
      sampler.start_iteration();
      Vec2 p_proposed;
      Rgb l_proposed = paths.l(sampler, depth, &p_proposed, &c);
      const float y_current = l_current.luminance(), y_proposed = l_proposed.luminance();
      const float accept = y_current > 0 ? std::min(1.f, y_proposed / y_current) : 1.f;
      // Both states, each by its expected share of this step.
      if (accept > 0 && y_proposed > 0)
        film->add_splat(p_proposed, l_proposed * (accept / y_proposed));
      if (y_current > 0) film->add_splat(p_current, l_current * ((1 - accept) / y_current));
      if (rng.next_float() < accept) {
        ++chain_accepted;
        p_current = p_proposed;
        l_current = l_proposed;
        sampler.accept();
      } else {
        sampler.reject();
      }
    }
    progress.add(mutations & 1023);
    accepted += chain_accepted;
  });
  progress.finish();
  film->commit_splats();
  for (const RayCounters& c : counters) {
    stats->paths += c.paths;
    stats->zero_radiance_paths += c.zero_radiance_paths;
    stats->camera_rays += c.camera_rays;
    stats->rays += c.rays;
    stats->shadow_rays += c.shadow_rays;
  }
  stats->samples = uint64_t(total);
  stats->nonfinite_samples = nonfinite.load();
  stats->mutations = uint64_t(total);
  stats->accepted = accepted.load();
  stats->seconds = seconds_since(t0);
  return true;
}

}  // namespace rt
