// runtime/render/lens_system.h — the lens stack of pbrt-v3's realistic camera.
//
// A list of spherical element interfaces (and one flat aperture stop) along
// the optical axis, front (scene side) to back (film side), in metres. The
// film sits at camera-space z = 0 and the lens in front of it at z > 0: the
// rear element's vertex is at z = rear_z(), the front one's at front_z().
//
// build() does what pbrt-v3's RealisticCamera constructor does: the stop's
// diameter becomes the requested aperture (unless that exceeds the stop's),
// the rear element's distance to the film is set so that the plane at
// focus_distance is in focus (thick-lens approximation, book 3rd ed. 6.4.4),
// and the exit pupil is bounded for 64 radial film intervals by tracing a
// grid of rays through the lens (6.4.5), in parallel and deterministically.
// Rays given to and returned by the traces are in camera space.
#pragma once

#include <string>
#include <vector>

#include "runtime/core/ray.h"

namespace rt {

struct PupilBounds {
  Vec2 min{kInfinity, kInfinity}, max{-kInfinity, -kInfinity};  // empty
  bool empty() const { return max.x < min.x || max.y < min.y; }
  bool inside(Vec2 p) const { return p.x >= min.x && p.x <= max.x && p.y >= min.y && p.y <= max.y; }
  float area() const { return empty() ? 0 : (max.x - min.x) * (max.y - min.y); }
  Vec2 lerp(Vec2 u) const {
    return {(1 - u.x) * min.x + u.x * max.x, (1 - u.y) * min.y + u.y * max.y};
  }
};

class LensSystem {
 public:
  static constexpr int kPupilIntervals = 64;
  static constexpr int kPupilSamples = 1024 * 1024;  // per interval, as pbrt-v3

  // lens_data: 4 floats per element as the archive's "lensdata" (mm; stops
  // have curvature radius 0). aperture_diameter in mm, focus_distance and
  // film_diagonal in metres. pupil_samples < kPupilSamples only for tests.
  [[nodiscard]] bool build(const float* lens_data, size_t count, float aperture_diameter,
                           float focus_distance, float film_diagonal, std::string* error,
                           int pupil_samples = kPupilSamples);

  // A ray leaving the film toward the rear element, traced out of the front
  // one; false when an element's aperture or total internal reflection stops it.
  bool trace_from_film(const Ray& camera_ray, Ray* out) const;
  // The same for n <= kMaxTraced rays at once (passed[k]: ray k's result, out[k] its ray):
  // interface by interface, so that their chains of dependent square roots and divisions
  // overlap (a camera sample traces its ray and two neighbours for the differentials).
  static constexpr int kMaxTraced = 4;
  void trace_from_film(const Ray* camera_rays, int n, Ray* out, bool* passed) const;
  // A ray entering the front element, traced to the film side.
  bool trace_from_scene(const Ray& camera_ray, Ray* out) const;

  // The bounds, on the plane of the rear element, of the points through
  // which rays from film points (r0..r1, 0, 0) leave the lens.
  PupilBounds bound_exit_pupil(float r0, float r1, int samples) const;
  // A point on the rear plane for the film point p_film (metres) from u in
  // [0,1)^2, inside the pupil bounds of its radius rotated to its angle;
  // *bounds_area is those bounds' area.
  Vec3 sample_exit_pupil(Vec2 p_film, Vec2 u, float* bounds_area) const;

  float rear_z() const { return elements_.back().thickness; }
  float front_z() const;
  float rear_radius() const { return elements_.back().aperture_radius; }
  const std::vector<PupilBounds>& pupil_bounds() const { return pupil_; }

 private:
  struct Element {
    float curvature_radius, thickness, eta, aperture_radius;
  };
  // One interface as trace_from_film meets it, rear to front, with what the
  // per-ray loop would otherwise recompute: where it sits, 1/|R|, the
  // squared aperture and the eta ratio of its refraction.
  struct FilmStep {
    float plane_z;   // the stop's plane (lens space)
    float center_z;  // a sphere's centre on the axis
    float radius;    // signed curvature radius; 0 for the stop
    float inv_abs_radius, aperture2, eta_ratio;
  };
  // Ray r (lens space, unit direction) on to interface s: false when s stops it.
  static bool film_step(const FilmStep& s, Ray& r);
  bool thick_lens(float pz[2], float fz[2], std::string* error) const;
  void prepare_film_steps();

  std::vector<Element> elements_;
  std::vector<FilmStep> film_steps_;
  std::vector<PupilBounds> pupil_;
  float film_diagonal_ = 0.035f;
};

}  // namespace rt
