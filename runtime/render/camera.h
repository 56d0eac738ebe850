// runtime/render/camera.h — pbrt-v3's projective and environment cameras.
//
// Built from the archive's camera entity and its camera-from-world transform
// at the (possibly --resdiv-reduced) film resolution, exactly as pbrt-v3
// builds them: the screen window follows the frame aspect ratio (fov spans
// the shorter image axis), raster -> camera through the inverse projection,
// thin-lens depth of field, and ray differentials one pixel apart in x and y
// (the integrator scales them by 1/sqrt(spp), as pbrt-v3 does).
#pragma once

#include <string>

#include "format/scene_archive.h"
#include "runtime/core/ray.h"
#include "runtime/core/transform.h"

namespace rt {

struct CameraSample {
  Vec2 p_film;  // raster position (pixel + offset)
  Vec2 p_lens;
  float time = 0;
};

class Camera {
 public:
  enum class Type : uint8_t { kPerspective, kOrthographic, kEnvironment };
  // resolution: the film's full resolution after --resdiv.
  [[nodiscard]] bool build(const pbrta::SceneArchive& archive, Point2i resolution,
                           std::string* error);
  // A world-space ray with differentials for the sample; returns its weight (1, or 0 for none).
  float generate_ray_differential(const CameraSample& sample, RayDifferential* ray) const;
  Type type() const { return type_; }

 private:
  Type type_ = Type::kPerspective;
  Transform camera_to_world_;
  Transform raster_to_camera_;
  Vec3 dx_camera_, dy_camera_;
  float lens_radius_ = 0, focal_distance_ = 1e6f;
  float shutter_open_ = 0, shutter_close_ = 1;
  Point2i resolution_;
};

}  // namespace rt
