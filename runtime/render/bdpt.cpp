// runtime/render/bdpt.cpp — see bdpt.h. The algorithm is the pbrt book's (3rd ed., 16.3).
#include "runtime/render/bdpt.h"

#include <cstdio>

#include "runtime/render/subpaths.h"

namespace rt {

namespace {

// pbrt-v3's BufferIndex: strategies ordered by depth, then s.
int buffer_index(int s, int t) {
  const int above = s + t - 2;
  return s + above * (5 + above) / 2;
}

}  // namespace

bool Bdpt::init(const RenderScene& scene, const Camera& camera, Film* film, int max_depth,
                std::string_view light_strategy, std::string* error, BdptVisualize visualize) {
  scene_ = &scene;
  camera_ = &camera;
  film_ = film;
  film_->enable_splats();
  max_depth_ = max_depth;
  visualize_ = visualize;
  strategy_films_.clear();
  if (visualize.strategies || visualize.weights) {
    strategy_films_.resize(size_t((1 + max_depth) * (6 + max_depth) / 2));
    const float whole[4] = {0, 1, 0, 1};
    for (int depth = 0; depth <= max_depth; ++depth)
      for (int s = 0; s <= depth + 2; ++s) {
        const int t = depth + 2 - s;
        if (t == 0 || (s == 1 && t == 1)) continue;
        char name[64];
        std::snprintf(name, sizeof name, "bdpt_d%02d_s%02d_t%02d.exr", depth, s, t);
        auto f = std::make_unique<Film>();
        if (!f->build(film->full_resolution(), whole, Filter{}, 1, kInfinity,
                      film->diagonal() * 1000, name, error))
          return false;
        f->enable_splats();
        f->keep_pass_splats_apart();  // end_pass() commits or drops each pass
        strategy_films_[size_t(buffer_index(s, t))] = std::move(f);
      }
  }
  if (!camera.supports_importance()) {
    *error =
        "not supported: bdpt needs a perspective camera (pbrt-v3's other cameras have no "
        "importance function either)";
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
  // The camera sample's film point, for strategy images of t >= 2 (the renderer keeps it).
  Vec2 p_film;
  const int half = sample_half(sampler.current_pixel(), sampler.current_sample_number());
  if (!strategy_films_.empty()) camera_->we(camera_ray, &p_film);
  Rgb l;
  for (int t = 1; t <= n_camera; ++t)
    for (int s = 0; s <= n_light; ++s) {
      const int depth = t + s - 2;
      if ((s == 1 && t == 1) || depth < 0 || depth > max_depth_) continue;
      Vec2 p_raster = p_film;
      float mis = 0;
      Rgb lp = c.connect(lig, cam, s, t, &p_raster, &mis);
      ++counters->paths;
      counters->zero_radiance_paths += lp.is_black();
      if (!strategy_films_.empty()) {
        Rgb value = visualize_.weights ? lp : mis == 0 ? Rgb() : lp / mis;
        strategy_films_[size_t(buffer_index(s, t))]->add_splat(p_raster, value, half);
      }
      if (t != 1)
        l += lp;
      else if (!lp.is_black())
        film_->add_splat(p_raster, lp, half);
    }
  return l;
}

void Bdpt::end_pass(bool keep, int64_t samples) {
  for (auto& f : strategy_films_) {
    if (!f) continue;
    if (keep)
      f->commit_splats();
    else
      f->discard_splats();
    f->set_splat_scale(1.f / float(std::max<int64_t>(samples, 1)));
    f->set_sample_count(samples);
  }
}

const Film* Bdpt::strategy_film(int s, int t) const {
  const int i = buffer_index(s, t);
  return i >= 0 && size_t(i) < strategy_films_.size() ? strategy_films_[size_t(i)].get() : nullptr;
}

bool Bdpt::write_strategy_images(const std::string& directory, std::string* error) const {
  for (const auto& f : strategy_films_)
    if (f && !f->write(directory.empty() ? f->filename() : directory + "/" + f->filename(), error))
      return false;
  return true;
}

}  // namespace rt
