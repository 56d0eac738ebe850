// runtime/render/lens_system.cpp — see lens_system.h.
#include "runtime/render/lens_system.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "runtime/core/math.h"
#include "runtime/material/local_frame.h"
#include "runtime/sampler/radical_inverse.h"

namespace rt {

namespace {

// The lens is traced in "lens space": camera space mirrored in z, so the
// film is at z = 0 and the elements at negative z, as the book lays it out.
Ray mirror_z(const Ray& r) {
  Ray m = r;
  m.o.z = -m.o.z;
  m.d.z = -m.d.z;
  return m;
}

// The ray against the sphere of the given signed radius centred on the axis
// at z_center: the hit on the element's cap (nearer or farther root, by
// which way the ray travels and which way the surface bulges), with the
// normal facing the ray's origin.
bool hit_spherical_element(float radius, float z_center, const Ray& r, float* t, Vec3* n) {
  Vec3 o = r.o - Vec3{0, 0, z_center};
  double a = double(r.d.x) * r.d.x + double(r.d.y) * r.d.y + double(r.d.z) * r.d.z;
  double b = 2 * (double(r.d.x) * o.x + double(r.d.y) * o.y + double(r.d.z) * o.z);
  double c = double(o.x) * o.x + double(o.y) * o.y + double(o.z) * o.z - double(radius) * radius;
  double t0, t1;
  if (!solve_quadratic(a, b, c, &t0, &t1)) return false;
  bool closer = (r.d.z > 0) != (radius < 0);
  *t = float(closer ? std::min(t0, t1) : std::max(t0, t1));
  if (*t < 0) return false;
  *n = face_forward(normalize(o + r.d * *t), -r.d);
  return true;
}

}  // namespace

float LensSystem::front_z() const {
  float z = 0;
  for (const Element& e : elements_) z += e.thickness;
  return z;
}

void LensSystem::prepare_film_steps() {
  film_steps_.clear();
  float element_z = 0;
  for (int i = int(elements_.size()) - 1; i >= 0; --i) {
    const Element& e = elements_[size_t(i)];
    element_z -= e.thickness;
    FilmStep s;
    s.plane_z = element_z;
    s.center_z = element_z + e.curvature_radius;
    s.radius = e.curvature_radius;
    s.inv_abs_radius = e.curvature_radius != 0 ? 1 / std::fabs(e.curvature_radius) : 0;
    s.aperture2 = e.aperture_radius * e.aperture_radius;
    // Air (eta 0 in lens files, or the scene) past the front element.
    float eta_t = (i > 0 && elements_[size_t(i - 1)].eta != 0) ? elements_[size_t(i - 1)].eta : 1;
    s.eta_ratio = e.eta / eta_t;
    film_steps_.push_back(s);
  }
}

// The hot path of realistic-camera rays (three to five traces per sample).
// Unlike hit_spherical_element it keeps the direction unit length (refract()
// of unit vectors is unit), so the quadratic is t^2 + 2 b t + c with no
// division, and the normal is the hit's offset from the centre times 1/|R|
// instead of a normalisation: two divisions and two square roots fewer per
// interface, on a chain of dependent interfaces.
[[gnu::always_inline]] inline bool LensSystem::film_step(const FilmStep& s, Ray& r) {
  float t;
  if (s.radius == 0) {
    // A ray bent back toward the film by the previous interface never
    // reaches the stop's plane.
    if (r.d.z >= 0) return false;
    t = (s.plane_z - r.o.z) / r.d.z;
  } else {
    const double ox = r.o.x, oy = r.o.y, oz = double(r.o.z) - s.center_z;
    const double b = ox * r.d.x + oy * r.d.y + oz * r.d.z;
    const double c = ox * ox + oy * oy + oz * oz - double(s.radius) * s.radius;
    const double disc = b * b - c;
    if (disc < 0) return false;
    const double root = std::sqrt(disc);
    // The nearer or farther root, by which way the ray travels and which
    // way the surface bulges.
    const bool nearer = (r.d.z > 0) != (s.radius < 0);
    t = float(nearer ? -b - root : -b + root);
    if (t < 0) return false;
  }
  const Vec3 p = r.at(t);
  if (p.x * p.x + p.y * p.y > s.aperture2) return false;
  r.o = p;
  if (s.radius != 0) {
    const Vec3 n = face_forward(Vec3{p.x, p.y, p.z - s.center_z} * s.inv_abs_radius, -r.d);
    Vec3 w;
    if (!refract(-r.d, n, s.eta_ratio, &w)) return false;
    r.d = w;
  }
  return true;
}

bool LensSystem::trace_from_film(const Ray& camera_ray, Ray* out) const {
  Ray r = mirror_z(camera_ray);
  r.d = normalize(r.d);
  for (const FilmStep& s : film_steps_)
    if (!film_step(s, r)) return false;
  if (out) *out = mirror_z(r);
  return true;
}

void LensSystem::trace_from_film(const Ray* camera_rays, int n, Ray* out, bool* passed) const {
  Ray r[kMaxTraced];
  bool alive[kMaxTraced] = {};
  for (int k = 0; k < n; ++k) {
    r[k] = mirror_z(camera_rays[k]);
    r[k].d = normalize(r[k].d);
    alive[k] = true;
  }
  for (const FilmStep& s : film_steps_)
    for (int k = 0; k < n; ++k)
      if (alive[k]) alive[k] = film_step(s, r[k]);
  for (int k = 0; k < n; ++k) {
    passed[k] = alive[k];
    if (alive[k]) out[k] = mirror_z(r[k]);
  }
}

bool LensSystem::trace_from_scene(const Ray& camera_ray, Ray* out) const {
  float element_z = -front_z();
  Ray r = mirror_z(camera_ray);
  for (size_t i = 0; i < elements_.size(); ++i) {
    const Element& e = elements_[i];
    bool stop = e.curvature_radius == 0;
    float t;
    Vec3 n;
    if (stop) {
      t = (element_z - r.o.z) / r.d.z;
    } else if (!hit_spherical_element(e.curvature_radius, element_z + e.curvature_radius, r, &t,
                                      &n)) {
      return false;
    }
    Vec3 p = r.at(t);
    if (p.x * p.x + p.y * p.y > e.aperture_radius * e.aperture_radius) return false;
    r.o = p;
    if (!stop) {
      float eta_i = (i == 0 || elements_[i - 1].eta == 0) ? 1 : elements_[i - 1].eta;
      float eta_t = e.eta != 0 ? e.eta : 1;
      Vec3 w;
      if (!refract(normalize(-r.d), n, eta_i / eta_t, &w)) return false;
      r.d = w;
    }
    element_z += e.thickness;
  }
  if (out) *out = mirror_z(r);
  return true;
}

// Principal plane pz and focal point fz (lens-space z) from a ray parallel
// to the axis at height r_in.o.x and its refracted continuation r_out.
static void cardinal_points(const Ray& r_in, const Ray& r_out, float* pz, float* fz) {
  float tf = -r_out.o.x / r_out.d.x;
  *fz = -r_out.at(tf).z;
  float tp = (r_in.o.x - r_out.o.x) / r_out.d.x;
  *pz = -r_out.at(tp).z;
}

bool LensSystem::thick_lens(float pz[2], float fz[2], std::string* error) const {
  // Close enough to the axis for the paraxial approximation, far enough for precision.
  float x = 0.001f * film_diagonal_;
  Ray scene_ray;
  scene_ray.o = {x, 0, front_z() + 1};
  scene_ray.d = {0, 0, -1};
  Ray film_ray;
  if (!trace_from_scene(scene_ray, &film_ray)) {
    *error =
        "unable to trace a ray from the scene to the film for the thick lens approximation "
        "(is the aperture stop extremely small?)";
    return false;
  }
  cardinal_points(scene_ray, film_ray, &pz[0], &fz[0]);
  film_ray.o = {x, 0, rear_z() - 1};
  film_ray.d = {0, 0, 1};
  if (!trace_from_film(film_ray, &scene_ray)) {
    *error =
        "unable to trace a ray from the film to the scene for the thick lens approximation "
        "(is the aperture stop extremely small?)";
    return false;
  }
  cardinal_points(film_ray, scene_ray, &pz[1], &fz[1]);
  return true;
}

bool LensSystem::build(const float* data, size_t count, float aperture_diameter,
                       float focus_distance, float film_diagonal, std::string* error,
                       int pupil_samples) {
  if (count == 0 || count % 4 != 0) {
    *error = "the lens data has " + std::to_string(count) +
             " values; expected 4 per element (radius, thickness, eta, aperture)";
    return false;
  }
  film_diagonal_ = film_diagonal;
  elements_.clear();
  for (size_t i = 0; i < count; i += 4) {
    float diameter = data[i + 3];
    // pbrt-v3 keeps the stop's own diameter when the request exceeds it.
    if (data[i] == 0 && aperture_diameter <= diameter) diameter = aperture_diameter;
    elements_.push_back(
        {data[i] * 0.001f, data[i + 1] * 0.001f, data[i + 2], diameter * 0.001f / 2});
  }
  prepare_film_steps();

  // Focus: move the film so that the thick lens images focus_distance onto it.
  float pz[2], fz[2];
  if (!thick_lens(pz, fz, error)) return false;
  float f = fz[0] - pz[0];
  float z = -focus_distance;
  float c = (pz[1] - z - pz[0]) * (pz[1] - z - 4 * f - pz[0]);
  if (c <= 0) {
    *error = "the focus distance " + std::to_string(focus_distance) + " is too short for this lens";
    return false;
  }
  float delta = 0.5f * (pz[1] - z + pz[0] - std::sqrt(c));
  elements_.back().thickness += delta;
  prepare_film_steps();

  pupil_.assign(kPupilIntervals, PupilBounds());
  // Each interval writes only its own bounds: the result does not depend on scheduling.
  tbb::parallel_for(0, kPupilIntervals, [&](int i) {
    float r0 = float(i) / kPupilIntervals * film_diagonal / 2;
    float r1 = float(i + 1) / kPupilIntervals * film_diagonal / 2;
    pupil_[size_t(i)] = bound_exit_pupil(r0, r1, pupil_samples);
  });
  return true;
}

PupilBounds LensSystem::bound_exit_pupil(float r0, float r1, int samples) const {
  float rear = rear_radius();
  PupilBounds proj;
  proj.min = {-1.5f * rear, -1.5f * rear};
  proj.max = {1.5f * rear, 1.5f * rear};
  PupilBounds bounds;
  int exiting = 0;
  float rz = rear_z();
  for (int i = 0; i < samples; ++i) {
    Vec3 p_film{lerp((i + 0.5f) / samples, r0, r1), 0, 0};
    Vec2 u{float(radical_inverse(2, uint64_t(i))), float(radical_inverse(3, uint64_t(i)))};
    Vec2 q = proj.lerp(u);
    Vec3 p_rear{q.x, q.y, rz};
    Ray r;
    r.o = p_film;
    r.d = p_rear - p_film;
    // Points already inside cannot grow the bounds: skip their trace.
    if (bounds.inside(q) || trace_from_film(r, nullptr)) {
      bounds.min = {std::min(bounds.min.x, q.x), std::min(bounds.min.y, q.y)};
      bounds.max = {std::max(bounds.max.x, q.x), std::max(bounds.max.y, q.y)};
      ++exiting;
    }
  }
  if (exiting == 0) return proj;
  // One grid spacing of slack for what the samples missed.
  Vec2 diag = proj.max - proj.min;
  float pad = 2 * std::sqrt(diag.x * diag.x + diag.y * diag.y) / std::sqrt(float(samples));
  bounds.min = {bounds.min.x - pad, bounds.min.y - pad};
  bounds.max = {bounds.max.x + pad, bounds.max.y + pad};
  return bounds;
}

Vec3 LensSystem::sample_exit_pupil(Vec2 p_film, Vec2 u, float* bounds_area) const {
  float r_film = std::sqrt(p_film.x * p_film.x + p_film.y * p_film.y);
  int n = int(pupil_.size());
  int index = std::min(n - 1, int(r_film / (film_diagonal_ / 2) * n));
  const PupilBounds& b = pupil_[size_t(index)];
  if (bounds_area) *bounds_area = b.area();
  Vec2 p = b.lerp(u);
  // The bounds were found for film points on +x; rotate to p_film's angle.
  float sin_t = r_film != 0 ? p_film.y / r_film : 0;
  float cos_t = r_film != 0 ? p_film.x / r_film : 1;
  return {cos_t * p.x - sin_t * p.y, sin_t * p.x + cos_t * p.y, rear_z()};
}

}  // namespace rt
