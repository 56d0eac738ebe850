// runtime/render/integrator.h — pbrt-v3's whitted, directlighting, path, volpath,
// ambientocclusion and bdpt integrators (bdpt: runtime/render/bdpt.h).
//
// An Integrator computes the radiance along one camera ray. Its kernel is a
// template instantiated for the effects the archive says the scene has
// (area lights, infinite lights, media), picked once at construction: a scene
// without area lights never looks up emission at a hit, one without an
// infinite light never evaluates escaping rays, and volpath on a scene
// without media runs the path kernel (pbrt-v3's volpath is path there). Per-thread counters (rays,
// shadow rays) are passed in, so nothing here is shared and written.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "format/scene_archive.h"
#include "runtime/core/rgb.h"
#include "runtime/light/light_distribution.h"
#include "runtime/render/render_scene.h"
#include "runtime/render/visibility.h"
#include "runtime/sampler/sampler.h"

namespace rt {

enum class IntegratorType : uint8_t {
  kWhitted,
  kDirectLighting,
  kPath,
  kVolPath,
  kAmbientOcclusion,
  kBdpt
};

class Bdpt;
class Camera;
class Film;

// Only volpath simulates participating media (bdpt and mlt would too); the
// others ignore them, as pbrt-v3 does, after a warning.
inline bool simulates_media(IntegratorType t) {
  return t == IntegratorType::kVolPath;
}

struct IntegratorSettings {
  IntegratorType type = IntegratorType::kPath;
  int max_depth = 5;
  bool sample_all_lights = true;  // directlighting strategy "all" (else "one")
  float rr_threshold = 1;
  std::string light_strategy = "spatial";
  // ambientocclusion: cosine-weighted (else uniform) hemisphere rays, and how many.
  bool cos_sample = true;
  int ao_samples = 64;
  bool has_pixel_bounds = false;
  Bounds2i pixel_bounds;
  // Lights' "nsamples" are divided by this (at least 1 left): pbrt-v3's --quick uses 4.
  int light_nsamples_divisor = 1;
};

// Reads the scene's integrator; "not supported yet: <type> integrator (file:line)"
// for the ones this renderer does not have.
[[nodiscard]] bool read_integrator(const pbrta::SceneArchive& archive, IntegratorSettings* out,
                                   std::string* error);

class Integrator {
 public:
  Integrator();
  ~Integrator();
  // bdpt connects to the camera and splats to the film: both must be given and outlive this.
  [[nodiscard]] bool init(const RenderScene& scene, const IntegratorSettings& settings,
                          std::string* error, const Camera* camera = nullptr, Film* film = nullptr);
  // Requests the sampler arrays the integrator will use (before cloning it); bdpt sets the
  // film's splat scale for the sampler's count.
  void preprocess(Sampler* sampler);
  Rgb li(const RayDifferential& ray, Sampler& sampler, RayCounters* counters) const {
    return kernel_(*this, ray, sampler, counters);
  }
  const IntegratorSettings& settings() const { return settings_; }

 private:
  template <bool kAreaLights, bool kInfinite>
  friend struct Kernels;
  using Kernel = Rgb (*)(const Integrator&, const RayDifferential&, Sampler&, RayCounters*);

  const RenderScene* scene_ = nullptr;
  IntegratorSettings settings_;
  LightDistribution distribution_;
  std::vector<int> light_samples_;  // per light, rounded by the sampler (strategy "all")
  int ao_samples_ = 0;              // ambientocclusion's, rounded by the sampler
  Kernel kernel_ = nullptr;
  std::unique_ptr<Bdpt> bdpt_;
};

}  // namespace rt
