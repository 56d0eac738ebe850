// runtime/render/mlt.h — pbrt-v3's Metropolis light transport (book 3rd ed., 16.4):
// primary-sample-space MLT (Kelemen et al. 2002) over bidirectional path strategies,
// multiplexed by path length (Hachisuka et al. 2014).
//
// A path of a given depth is a point of the unit hypercube (MltSampler): its numbers pick
// the strategy (s, t) among depth + 2, the film point, the camera and light subpaths and the
// connection (subpaths.h); its value is that strategy's contribution times the number of
// strategies. Bootstrap: `bootstrap` independent points per depth estimate the image's total
// luminance b and seed the chains; `chains` Markov chains, started by importance from the
// bootstrap, share the mutationsperpixel x pixels mutations, each proposing a mutated point
// and splatting both states with their expected weights (Veach's expected-value splats). The
// film's splats are scaled by b / mutationsperpixel. Chains run in parallel (oneTBB), each
// with its own generator, so the image does not depend on the thread count (up to the order
// of float additions on the film).
#pragma once

#include <string>

#include "runtime/film/film.h"
#include "runtime/render/camera.h"
#include "runtime/render/integrator.h"
#include "runtime/render/render_scene.h"
#include "runtime/render/renderer.h"

namespace rt {

struct MltSettings {
  int max_depth = 5;
  int64_t bootstrap_samples = 100000;
  int chains = 1000;
  int64_t mutations_per_pixel = 100;
  float large_step_probability = 0.3f;
  float sigma = 0.01f;
  uint64_t seed = 0;  // pbrtrun --seed: offsets every generator
};

// The scene's mlt settings; spp_override > 0 (pbrtrun --spp) sets the mutations per pixel,
// as the pbrt-v3 in ../shared/peers does.
MltSettings mlt_settings(const IntegratorSettings& settings, int spp_override, uint64_t seed);

// False with *error for input it cannot render (a camera without importance, media).
[[nodiscard]] bool render_mlt(const RenderScene& scene, const Camera& camera, Film* film,
                              const MltSettings& settings, const RenderOptions& options,
                              RenderStats* stats, std::string* error);

}  // namespace rt
