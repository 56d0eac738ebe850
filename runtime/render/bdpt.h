// runtime/render/bdpt.h — pbrt-v3's bidirectional path tracer (book 3rd ed., 16.3; Veach 1997).
//
// For each camera sample: a camera subpath (from the camera ray) and a light
// subpath (from a light chosen by the light distribution, "power" unless the
// scene names another, leaving by LightSet::sample_le), each a random walk of
// up to maxdepth bounces without Russian roulette; then every pair of
// prefixes (s light vertices, t camera vertices, s + t - 2 <= maxdepth) is
// joined: s = 0 takes emission the camera path found, s = 1 samples a light
// from the camera vertex, t = 1 connects the light vertex to the lens
// (Camera::sample_wi) and splats to the film point it lands on, the others
// join the two end vertices through the BSDFs. Each strategy is weighted by
// the power heuristic (exponent 2) over all the strategies that could have
// made the same path, from the area densities recorded forwards and
// backwards along both walks, as pbrt-v3's MISWeight. Radiance at the
// camera sample is returned; t = 1 contributions go to Film::add_splat (the
// sample's half), which the renderer scales by 1 / spp rendered (set_splat_scale).
//
// Importance transport uses TransportMode::kImportance BSDFs and pbrt-v3's
// shading-normal correction; participating media scatter at medium vertices
// (subpaths.h). Cameras other than perspective have no importance function,
// as in pbrt-v3, and are refused. Read-only after init():
// li() is thread-safe.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "runtime/film/film.h"
#include "runtime/light/light_distribution.h"
#include "runtime/render/camera.h"
#include "runtime/render/render_scene.h"
#include "runtime/render/visibility.h"
#include "runtime/sampler/sampler.h"

namespace rt {

// pbrt-v3's visualizestrategies / visualizeweights: one image per strategy (s, t) of each
// depth, bdpt_dDD_sSS_tTT.exr, of that strategy's unweighted or MIS-weighted contributions
// (splatted, box-filtered, full resolution). The weighted ones add up to the render.
struct BdptVisualize {
  bool strategies = false, weights = false;
};

class Bdpt {
 public:
  [[nodiscard]] bool init(const RenderScene& scene, const Camera& camera, Film* film, int max_depth,
                          std::string_view light_strategy, std::string* error,
                          BdptVisualize visualize = {});
  // The end of a render pass (renderer.h) for the strategy images: their pending splats
  // committed (keep) or dropped, scaled for the samples per pixel rendered so far (the
  // renderer does the same for the image's film).
  void end_pass(bool keep, int64_t samples);
  // The strategy images, when asked for, into `directory` ("" = the current one).
  [[nodiscard]] bool write_strategy_images(const std::string& directory, std::string* error) const;
  // The strategy image of (s, t), or null (tests).
  const Film* strategy_film(int s, int t) const;
  // The camera ray must come from `camera` (its differentials scaled as the renderer does).
  Rgb li(const RayDifferential& camera_ray, Sampler& sampler, RayCounters* counters) const;

 private:
  const RenderScene* scene_ = nullptr;
  const Camera* camera_ = nullptr;
  Film* film_ = nullptr;
  int max_depth_ = 5;
  LightDistribution distribution_;
  Vec3 world_center_;
  float world_radius_ = 0;
  BdptVisualize visualize_;
  std::vector<std::unique_ptr<Film>> strategy_films_;  // by buffer_index(s, t)
};

}  // namespace rt
