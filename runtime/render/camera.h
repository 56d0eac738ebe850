// runtime/render/camera.h — pbrt-v3's projective and environment cameras.
//
// Built from the archive's camera entity and its camera-from-world transform
// at the (possibly --resdiv-reduced) film resolution, exactly as pbrt-v3
// builds them: the screen window follows the frame aspect ratio (fov spans
// the shorter image axis), raster -> camera through the inverse projection,
// thin-lens depth of field, and ray differentials one pixel apart in x and y
// (the integrator scales them by 1/sqrt(spp), as pbrt-v3 does). Only textures
// read differentials, so in a scene the archive says has none (its effects
// lack the textures bit) rays are made without them: the same rays, less work
// (but for the realistic camera's, which decide whether a ray counts).
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
//
// The bidirectional integrators also need the camera's importance W_e
// (pbrt book 3rd ed., 16.1.1), which pbrt-v3 defines for the perspective
// camera only: W_e is normalised so that, over the image's solid angle and
// the lens, the integral of W_e cos(theta) is 1. As in pbrt-v3, the image's
// area A on the camera-space plane z = 1 comes from the full resolution,
// while a ray counts as inside the image by the film's sample bounds
// (GetSampleBounds: the crop window widened by the filter radius), so with a
// crop or a wide filter the integral is not exactly 1 there either. The other
// cameras answer 0, and supports_importance() says which is which.
#pragma once

#include <optional>
#include <string>

#include "format/scene_archive.h"
#include "runtime/core/animated_transform.h"
#include "runtime/core/interaction.h"
#include "runtime/core/ray.h"
#include "runtime/core/rgb.h"
#include "runtime/core/transform.h"
#include "runtime/render/lens_system.h"
#include "runtime/sampler/sampler.h"

namespace rt {

struct CameraSample {
  Vec2 p_film;  // raster position (pixel + offset)
  Vec2 p_lens;
  float time = 0;
};

// Which of a camera sample's values anything reads (Camera::sample_use).
struct CameraSampleUse {
  bool time = true;
  bool lens = true;
};

// pbrt-v3's Sampler::GetCameraSample: the film offset within pixel, time and lens point, drawn
// in that order from the sampler's current sample. A value `use` says nothing reads has its
// dimensions skipped, not computed, and stays 0: later dimensions are the same either way.
inline CameraSample pixel_camera_sample(Sampler& sampler, Point2i pixel, CameraSampleUse use = {}) {
  CameraSample cs;
  const Vec2 u = sampler.get_2d();
  cs.p_film = {float(pixel.x) + u.x, float(pixel.y) + u.y};
  if (use.time)
    cs.time = sampler.get_1d();
  else
    sampler.skip_1d();
  if (use.lens)
    cs.p_lens = sampler.get_2d();
  else
    sampler.skip_2d();
  return cs;
}

class Camera {
 public:
  enum class Type : uint8_t { kPerspective, kOrthographic, kEnvironment, kRealistic };
  // The film's diagonal in metres for the realistic camera (Film::diagonal());
  // without it build() reads the film entity's "diagonal" from the archive.
  void set_film_diagonal(float metres) { film_diagonal_ = metres; }
  // Rays per radial interval of the exit-pupil search (fewer only in tests).
  void set_pupil_samples(int n) { pupil_samples_ = n; }
  // The film's sample bounds (Film::sample_bounds()), which decide whether a
  // ray reaches the image in we() and pdf_we(); call before build(). Without
  // it they are the full resolution, as for a box filter of radius 0.5 and no crop.
  void set_sample_bounds(const Bounds2i& bounds) {
    sample_bounds_ = bounds;
    sample_bounds_given_ = true;
  }
  // resolution: the film's full resolution after --resdiv.
  [[nodiscard]] bool build(const pbrta::SceneArchive& archive, Point2i resolution,
                           std::string* error);
  // A world-space ray with differentials for the sample; returns its weight (1, or 0 for none).
  float generate_ray_differential(const CameraSample& sample, RayDifferential* ray) const;
  // The same ray with its differentials then scaled by diff_scale
  // (RayDifferential::scale_differentials), bit for bit; the still pinhole scales them before
  // storing the ray (the caller's scaling reloaded the fields just stored, a stalled
  // store-to-load forward per camera ray: 2% of a whitted room, perf).
  float generate_ray_differential(const CameraSample& sample, float diff_scale,
                                  RayDifferential* ray) const;
  // The time u in [0, 1) names within the shutter interval (light tracing's photon times).
  float shutter_time(float u) const { return lerp(u, shutter_open_, shutter_close_); }
  Type type() const { return type_; }
  // The lens point is read by a realistic camera and a thin lens (lensradius > 0); the time
  // only where something moves: `effects` has the archive's motion-blur bit (the camera, a
  // shape or an instance moves; ARCHIVE.md section 4).
  CameraSampleUse sample_use(uint64_t effects) const;
  const LensSystem& lens() const { return lens_; }  // realistic only

  // Camera importance, pbrt-v3's (perspective only; the others give 0).
  bool supports_importance() const { return type_ == Type::kPerspective; }
  // pbrt-v3's PerspectiveCamera::We: the importance a ray leaving the camera carries (0 outside the
  // image or for a direction facing away), and with p_raster the raster point it passes through.
  Rgb we(const Ray& ray, Vec2* p_raster = nullptr) const;
  // pbrt-v3's Pdf_We: positional (1/lens area, or 1 for a pinhole) and directional pdfs of such a
  // ray.
  void pdf_we(const Ray& ray, float* pdf_pos, float* pdf_dir) const;
  // pbrt-v3's Sample_Wi: from reference point `ref` (world; its time used for the camera's
  // position), a point on the lens (u picks it; pinhole: the camera position), *wi towards the
  // lens, *pdf the solid-angle density of that lens point seen from ref, *p_raster where the ray
  // from the lens point through ref lands, and *lens the lens point as an Interaction (p, n =
  // camera's viewing direction, time; p_error 0). Returns We for that ray (0 and *pdf 0 when
  // nothing).
  Rgb sample_wi(const Interaction& ref, Vec2 u, Vec3* wi, float* pdf, Vec2* p_raster,
                Interaction* lens) const;

 private:
  bool build_realistic(const pbrta::SceneArchive& archive, uint32_t entity, std::string* error);
  // The realistic camera's ray from the film toward the exit pupil (lens space), and the area
  // of the pupil bounds it was sampled in.
  Ray realistic_film_ray(const CameraSample& sample, float* pupil_area) const;
  // The weight of the ray the lens made of film_ray, whose time and extent it sets.
  float realistic_weight(const Ray& film_ray, float pupil_area, Ray* ray) const;
  // Where a ray leaving the lens meets the film, for we() and pdf_we(): false when it faces
  // away from the viewing direction; else its cosine to it and its raster point.
  bool project_to_raster(const Ray& ray, float* cos_theta, Vec2* p_raster) const;
  // The same with the camera's world-to-camera transform and its unit viewing direction
  // (world) at the ray's time.
  bool project_through(const Transform& from_world, Vec3 forward, const Ray& ray, float* cos_theta,
                       Vec2* p_raster) const;
  bool inside_sample_bounds(Vec2 p_raster) const;
  float lens_area() const;

  Type type_ = Type::kPerspective;
  Transform camera_to_world_;
  // Its inverse and its +z axis, normalised: a still camera's projection reads them.
  Transform camera_from_world_;
  Vec3 forward_world_;
  // An animated camera moves by pbrt-v3's interpolation of its world-from-camera keyframes.
  AnimatedTransform motion_;
  // The world-from-camera transform at `time`: a still camera's read in place (no 128-byte
  // copy a ray), a moving camera's built in *moving.
  const Transform& to_world(float time, std::optional<Transform>* moving) const {
    return motion_.animated() ? moving->emplace(motion_.at(time)) : camera_to_world_;
  }
  // The camera-space origin in world space (still camera) and its rounding bound.
  Vec3 origin_world_, origin_error_;
  // A still pinhole perspective camera's ray through raster point (x, y) points along
  // x dir_x_ + y dir_y_ + dir_0_ (world space, unnormalised): the raster plane maps affinely
  // onto the camera's near plane, and normalising drops the scale.
  bool still_pinhole_ = false;
  Vec3 dir_x_, dir_y_, dir_0_;
  // diff_scale: scale the differentials by it, or null.
  float still_pinhole_ray(const CameraSample& sample, const float* diff_scale,
                          RayDifferential* ray) const;
  Transform raster_to_camera_, raster_from_camera_;
  Vec3 dx_camera_, dy_camera_;
  float lens_radius_ = 0, focal_distance_ = 1e6f;
  float shutter_open_ = 0, shutter_close_ = 1;
  Point2i resolution_;
  Bounds2i sample_bounds_;
  bool sample_bounds_given_ = false;
  float image_area_ = 0;  // perspective: the full image's area on the camera-space plane z = 1
  // Realistic camera.
  LensSystem lens_;
  float film_diagonal_ = -1;  // metres; < 0: from the archive
  int pupil_samples_ = LensSystem::kPupilSamples;
  Vec2 film_extent_;  // physical film size, metres
  bool simple_weighting_ = true;
  // Whether rays carry differentials: only where the archive says a texture can read them.
  bool differentials_ = true;
};

}  // namespace rt
