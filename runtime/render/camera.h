// runtime/render/camera.h — pbrt-v3's projective and environment cameras.
//
// Built from the archive's camera entity and its camera-from-world transform
// at the (possibly --resdiv-reduced) film resolution, exactly as pbrt-v3
// builds them: the screen window follows the frame aspect ratio (fov spans
// the shorter image axis), raster -> camera through the inverse projection,
// thin-lens depth of field, and ray differentials one pixel apart in x and y
// (the integrator scales them by 1/sqrt(spp), as pbrt-v3 does).
//
// The realistic camera traces each ray from a film point (the film's
// physical extent from its diagonal) through the lens stack of its lens
// file (lens_system.h), toward a point sampled inside the exit pupil's
// bounds; rays the lens stops get weight 0, the others pbrt-v3's cos^4
// weight (relative to the on-axis pupil area under "simpleweighting", the
// radiometric one otherwise). Its differentials are finite differences of
// rays from film points 0.05 pixel away, as pbrt-v3's generic camera does.
//
// Each ray has a time in [shutteropen, shutterclose]; a camera whose
// transform differs at the start and end times moves to where pbrt-v3's
// animated transform puts it then (animated_transform.h).
#pragma once

#include <string>

#include "format/scene_archive.h"
#include "runtime/core/animated_transform.h"
#include "runtime/core/ray.h"
#include "runtime/core/transform.h"
#include "runtime/render/lens_system.h"

namespace rt {

struct CameraSample {
  Vec2 p_film;  // raster position (pixel + offset)
  Vec2 p_lens;
  float time = 0;
};

class Camera {
 public:
  enum class Type : uint8_t { kPerspective, kOrthographic, kEnvironment, kRealistic };
  // The film's diagonal in metres for the realistic camera (Film::diagonal());
  // without it build() reads the film entity's "diagonal" from the archive.
  void set_film_diagonal(float metres) { film_diagonal_ = metres; }
  // Rays per radial interval of the exit-pupil search (fewer only in tests).
  void set_pupil_samples(int n) { pupil_samples_ = n; }
  // resolution: the film's full resolution after --resdiv.
  [[nodiscard]] bool build(const pbrta::SceneArchive& archive, Point2i resolution,
                           std::string* error);
  // A world-space ray with differentials for the sample; returns its weight (1, or 0 for none).
  float generate_ray_differential(const CameraSample& sample, RayDifferential* ray) const;
  Type type() const { return type_; }
  const LensSystem& lens() const { return lens_; }  // realistic only

 private:
  bool build_realistic(const pbrta::SceneArchive& archive, uint32_t entity, std::string* error);
  // The realistic camera's camera-space ray; weight 0 when the lens stops it.
  float realistic_ray(const CameraSample& sample, Ray* ray) const;

  Type type_ = Type::kPerspective;
  Transform camera_to_world_;
  // An animated camera moves by pbrt-v3's interpolation of its world-from-camera keyframes.
  AnimatedTransform motion_;
  Transform to_world(float time) const {
    return motion_.animated() ? motion_.at(time) : camera_to_world_;
  }
  Transform raster_to_camera_;
  Vec3 dx_camera_, dy_camera_;
  float lens_radius_ = 0, focal_distance_ = 1e6f;
  float shutter_open_ = 0, shutter_close_ = 1;
  Point2i resolution_;
  // Realistic camera.
  LensSystem lens_;
  float film_diagonal_ = -1;  // metres; < 0: from the archive
  int pupil_samples_ = LensSystem::kPupilSamples;
  Vec2 film_extent_;  // physical film size, metres
  bool simple_weighting_ = true;
};

}  // namespace rt
