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
//
// path and volpath split each vertex's direct lighting as pbrt-v4 does (the path's own next
// scattering sample stands for the one pbrt-v3's EstimateDirect traces separately; see li_path):
// pbrt-v3's expectation, one ray a vertex fewer, so their images converge to pbrt-v3's without
// matching its samples one for one. The others keep pbrt-v3's estimators.
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
  kBdpt,
  kMlt,  // not a per-camera-sample integrator: render_mlt (mlt.h) renders the whole image
  // Likewise: render_sppm (sppm.h).
  kSppm,
};

class Bdpt;
class Camera;
class Film;

// volpath, bdpt and mlt simulate participating media; the others ignore them, as pbrt-v3
// does, after a warning.
inline bool simulates_media(IntegratorType t) {
  return t == IntegratorType::kVolPath || t == IntegratorType::kBdpt || t == IntegratorType::kMlt;
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
  // mlt (pbrt-v3's names): bootstrapsamples, chains, mutationsperpixel, largestepprobability,
  // sigma.
  // bdpt: visualizestrategies / visualizeweights (bdpt.h).
  bool bdpt_visualize_strategies = false, bdpt_visualize_weights = false;
  int64_t mlt_bootstrap = 100000, mlt_mutations_per_pixel = 100;
  int mlt_chains = 1000;
  float mlt_large_step_probability = 0.3f, mlt_sigma = 0.01f;
  // sppm (pbrt-v3's names): iterations (alias numiterations), photonsperiteration (-1: one per
  // film pixel), radius; imagewritefrequency is accepted and ignored (one image at the end).
  int sppm_iterations = 64;
  int64_t sppm_photons_per_iteration = -1;
  float sppm_radius = 1;
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
  // Requests the sampler arrays the integrator will use (before cloning it).
  void preprocess(Sampler* sampler);
  // The end of a render pass: bdpt's strategy images keep or drop the pass's splats
  // (Bdpt::end_pass); nothing for the others.
  void end_pass(bool keep, int64_t samples) const;
  Rgb li(const RayDifferential& ray, Sampler& sampler, RayCounters* counters) const {
    return kernel_(*this, ray, sampler, counters);
  }
  const IntegratorSettings& settings() const { return settings_; }
  const RenderScene& scene() const { return *scene_; }  // after init()
  // bdpt's strategy images (visualizestrategies / visualizeweights) into `directory`; nothing
  // for the other integrators.
  [[nodiscard]] bool write_extra_images(const std::string& directory, std::string* error) const;
  const Bdpt* bdpt() const { return bdpt_.get(); }

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
