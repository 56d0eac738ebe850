// runtime/render/bdpt.cpp — see bdpt.h. The algorithm is the pbrt book's (3rd ed., 16.3).
#include "runtime/render/bdpt.h"

#include "runtime/render/subpaths.h"

namespace rt {

bool Bdpt::init(const RenderScene& scene, const Camera& camera, Film* film, int max_depth,
                std::string_view light_strategy, std::string* error) {
  scene_ = &scene;
  camera_ = &camera;
  film_ = film;
  max_depth_ = max_depth;
  if (!camera.supports_importance()) {
    *error =
        "not supported: bdpt needs a perspective camera (pbrt-v3's other cameras have no "
        "importance function either)";
    return false;
  }
  if (scene.media.size() > 0) {
    *error = "not supported yet: bdpt with participating media";
    return false;
  }
  scene.geometry.world_bounds().bounding_sphere(&world_center_, &world_radius_);
  return distribution_.build(scene.lights, scene.geometry.world_bounds(), light_strategy, error);
}

Rgb Bdpt::li(const RayDifferential& camera_ray, Sampler& sampler, RayCounters* counters) const {
  thread_local PathBuffers buffers;
  buffers.reserve(size_t(max_depth_) + 2);
  Vertex* cam = buffers.camera_path();
  Vertex* lig = buffers.light_path();
  Subpaths c{*scene_, *camera_, world_radius_, nullptr, sampler, counters};
  const int n_camera = c.camera_subpath(camera_ray, max_depth_ + 2, cam);
  c.choice = &distribution_.lookup(cam[0].p());
  const int n_light = c.light_subpath(max_depth_ + 1, cam[0].si.time, lig);
  Rgb l;
  for (int t = 1; t <= n_camera; ++t)
    for (int s = 0; s <= n_light; ++s) {
      const int depth = t + s - 2;
      if ((s == 1 && t == 1) || depth < 0 || depth > max_depth_) continue;
      Vec2 p_raster;
      Rgb lp = c.connect(lig, cam, s, t, &p_raster);
      if (t != 1)
        l += lp;
      else if (!lp.is_black())
        film_->add_splat(p_raster, lp);
    }
  return l;
}

}  // namespace rt
