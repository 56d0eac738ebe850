// runtime/render/camera.cpp — see camera.h.
#include "runtime/render/camera.h"

#include <cmath>
#include <cstring>

#include "runtime/core/sampling.h"

namespace rt {

namespace {

// Given and holding a value: computed defaults may be stored with count 0.
bool given_value(const pbrta::SceneArchive& a, uint32_t e, std::string_view name) {
  return a.given(e, name) && a.value(e, name)->count > 0;
}

}  // namespace

bool Camera::build(const pbrta::SceneArchive& a, Point2i res, std::string* error) {
  const pbrta::SceneRecord& scene = a.scene();
  uint32_t e = scene.camera;
  std::string_view type = a.type_name(e);
  if (type == "perspective")
    type_ = Type::kPerspective;
  else if (type == "orthographic")
    type_ = Type::kOrthographic;
  else if (type == "environment")
    type_ = Type::kEnvironment;
  else if (type == "realistic")
    type_ = Type::kRealistic;
  else {
    *error = "not supported yet: " + std::string(type) + " camera (" + a.where(e) + ")";
    return false;
  }
  const pbrta::TransformRecord& t = a.transforms[scene.camera_transform];
  Transform camera_from_world = Transform::from_doubles(t.start);
  if (!camera_from_world.invertible() || !Transform::from_doubles(t.end).invertible()) {
    *error = a.where(e) + ": error: the camera transform is singular";
    return false;
  }
  camera_to_world_ = camera_from_world.inverse();
  camera_from_world_ = camera_to_world_.inverse();
  forward_world_ = normalize(camera_to_world_.vector({0, 0, 1}));
  origin_world_ = camera_to_world_.point({0, 0, 0}, &origin_error_);
  motion_ = AnimatedTransform(t.start, t.end, float(t.start_time), float(t.end_time), true);
  resolution_ = res;
  if (!sample_bounds_given_) sample_bounds_ = {{0, 0}, res};
  shutter_open_ = a.get_float(e, "shutteropen", 0);
  shutter_close_ = a.get_float(e, "shutterclose", 1);
  // Only textures (and bump maps, which are textures) read a ray's differentials.
  differentials_ = (a.header().effects & pbrta::kEffectTextures) != 0;
  if (type_ == Type::kEnvironment) return true;
  if (type_ == Type::kRealistic) return build_realistic(a, e, error);

  lens_radius_ = a.get_float(e, "lensradius", 0);
  focal_distance_ = a.get_float(e, "focaldistance", 1e6f);
  float frame = given_value(a, e, "frameaspectratio") ? a.get_float(e, "frameaspectratio")
                                                      : float(res.x) / float(res.y);
  float sw[4];
  if (given_value(a, e, "screenwindow")) {
    const float* f = a.floats(*a.value(e, "screenwindow"));
    std::memcpy(sw, f, sizeof sw);
  } else if (frame > 1) {
    sw[0] = -frame;
    sw[1] = frame;
    sw[2] = -1;
    sw[3] = 1;
  } else {
    sw[0] = -1;
    sw[1] = 1;
    sw[2] = -1 / frame;
    sw[3] = 1 / frame;
  }
  Transform camera_to_screen;
  if (type_ == Type::kPerspective) {
    float fov = a.get_float(e, "fov", 90);
    float halffov = a.get_float(e, "halffov", -1);
    if (halffov > 0) fov = 2 * halffov;
    camera_to_screen = perspective(fov, 1e-2f, 1000.f);
  } else {
    // pbrt-v3's Orthographic(0, 1): z maps unchanged.
    camera_to_screen = Transform();
  }
  Transform screen_to_raster = scale(float(res.x), float(res.y), 1) *
                               scale(1 / (sw[1] - sw[0]), 1 / (sw[2] - sw[3]), 1) *
                               translate({-sw[0], -sw[3], 0});
  raster_to_camera_ = camera_to_screen.inverse() * screen_to_raster.inverse();
  raster_from_camera_ = raster_to_camera_.inverse();
  Vec3 o = raster_to_camera_.point({0, 0, 0});
  dx_camera_ = raster_to_camera_.point({1, 0, 0}) - o;
  dy_camera_ = raster_to_camera_.point({0, 1, 0}) - o;
  if (type_ == Type::kOrthographic) {
    dx_camera_ = raster_to_camera_.vector({1, 0, 0});
    dy_camera_ = raster_to_camera_.vector({0, 1, 0});
  } else {
    // The corners of the full image projected onto z = 1 (pbrt-v3 takes the full resolution
    // here, not the sample bounds, even for a cropped film or a wide filter).
    Vec3 p_min = raster_to_camera_.point({0, 0, 0});
    Vec3 p_max = raster_to_camera_.point({float(res.x), float(res.y), 0});
    p_min = p_min / p_min.z;
    p_max = p_max / p_max.z;
    image_area_ = std::abs((p_max.x - p_min.x) * (p_max.y - p_min.y));
  }
  still_pinhole_ = type_ == Type::kPerspective && lens_radius_ == 0 && !motion_.animated();
  if (still_pinhole_) {
    dir_x_ = camera_to_world_.vector(dx_camera_);
    dir_y_ = camera_to_world_.vector(dy_camera_);
    dir_0_ = camera_to_world_.vector(o);
  }
  return true;
}

bool Camera::build_realistic(const pbrta::SceneArchive& a, uint32_t e, std::string* error) {
  const pbrta::ValueRecord* data = a.value(e, "lensdata");
  if (!data || data->count == 0) {
    *error = a.where(e) + ": error: the realistic camera has no lens data";
    return false;
  }
  float diagonal =
      film_diagonal_ > 0 ? film_diagonal_ : a.get_float(a.scene().film, "diagonal", 35) * 0.001f;
  simple_weighting_ = a.get_int(e, "simpleweighting", 1) != 0;
  std::string lens_error;
  if (!lens_.build(a.floats(*data), data->count, a.get_float(e, "aperturediameter", 1),
                   a.get_float(e, "focusdistance", 10), diagonal, &lens_error, pupil_samples_)) {
    *error = a.where(e) + ": error: realistic camera: " + lens_error;
    return false;
  }
  // pbrt-v3's Film::GetPhysicalExtent: the diagonal at the image's aspect ratio.
  float aspect = float(resolution_.y) / float(resolution_.x);
  float x = std::sqrt(diagonal * diagonal / (1 + aspect * aspect));
  film_extent_ = {x, aspect * x};
  return true;
}

namespace {

// pbrt-v3 takes camera rays to world space with its ray transform, which moves the origin
// forward along the ray past the bound of the transform's rounding (origin_past_error). The
// move differs from ray to ray, and so does the rounding of what the ray meets far away.
// Without it, every camera ray's origin, taken to a shape's object space, rounds the same way:
// a quadric's hit points then all err to one side, by up to the part of the root's error
// pbrt-v3's interval leaves out (the discriminant's cancellation), and shadow rays leaving them
// hit the surface again at once. textures/constant.pbrt seen from 22 units: 7.7% of the
// paraboloid's shadow rays without the move, 1.6% with it; pbrt-v3's image has about that 1.6%.
Vec3 world_origin(const Transform& w, Vec3 o, Vec3 d_world) {
  Vec3 err;
  const Vec3 ow = w.point(o, &err);
  return origin_past_error(ow, d_world, err);
}

}  // namespace

Ray Camera::realistic_film_ray(const CameraSample& s, float* pupil_area) const {
  Vec2 u{s.p_film.x / float(resolution_.x), s.p_film.y / float(resolution_.y)};
  // The film is seen from behind the lens: x mirrored.
  Vec3 p_film{-lerp(u.x, -film_extent_.x / 2, film_extent_.x / 2),
              lerp(u.y, -film_extent_.y / 2, film_extent_.y / 2), 0};
  Vec3 p_rear = lens_.sample_exit_pupil({p_film.x, p_film.y}, s.p_lens, pupil_area);
  Ray film_ray;
  film_ray.o = p_film;
  film_ray.d = p_rear - p_film;
  film_ray.time = lerp(s.time, shutter_open_, shutter_close_);
  return film_ray;
}

float Camera::realistic_weight(const Ray& film_ray, float pupil_area, Ray* ray) const {
  ray->time = film_ray.time;
  ray->tmax = kInfinity;
  float cos_theta = normalize(film_ray.d).z;
  float cos4 = (cos_theta * cos_theta) * (cos_theta * cos_theta);
  if (simple_weighting_) return cos4 * pupil_area / lens_.pupil_bounds()[0].area();
  float rz = lens_.rear_z();
  return (shutter_close_ - shutter_open_) * (cos4 * pupil_area) / (rz * rz);
}

CameraSampleUse Camera::sample_use(uint64_t effects) const {
  CameraSampleUse use;
  use.time = (effects & pbrta::kEffectMotionBlur) != 0 || motion_.animated();
  use.lens = type_ == Type::kRealistic || lens_radius_ > 0;
  return use;
}

// The same rays as the general path below up to rounding, in a third of its arithmetic: one
// 3x3 product, no perspective divide, one normalisation per direction. (Camera rays took
// 8-14% of the whitted hm-* scenes' time.)
float Camera::still_pinhole_ray(const CameraSample& s, const float* diff_scale,
                                RayDifferential* out) const {
  const Vec3 v = s.p_film.x * dir_x_ + s.p_film.y * dir_y_ + dir_0_;
  const Vec3 d = normalize(v), o = origin_past_error(origin_world_, d, origin_error_);
  out->d = d;
  out->o = o;
  out->tmax = kInfinity;
  out->time = lerp(s.time, shutter_open_, shutter_close_);
  out->has_differentials = differentials_;
  if (differentials_) {
    Vec3 rx_o = origin_world_, ry_o = origin_world_;
    Vec3 rx_d = normalize(v + dir_x_), ry_d = normalize(v + dir_y_);
    if (diff_scale) {  // as RayDifferential::scale_differentials scales them
      rx_o = RayDifferential::scaled(o, rx_o, *diff_scale);
      ry_o = RayDifferential::scaled(o, ry_o, *diff_scale);
      rx_d = RayDifferential::scaled(d, rx_d, *diff_scale);
      ry_d = RayDifferential::scaled(d, ry_d, *diff_scale);
    }
    out->rx_o = rx_o;
    out->ry_o = ry_o;
    out->rx_d = rx_d;
    out->ry_d = ry_d;
  }
  return 1;
}

float Camera::generate_ray_differential(const CameraSample& s, float diff_scale,
                                        RayDifferential* out) const {
  if (still_pinhole_) return still_pinhole_ray(s, &diff_scale, out);
  const float w = generate_ray_differential(s, out);
  out->scale_differentials(diff_scale);
  return w;
}

float Camera::generate_ray_differential(const CameraSample& s, RayDifferential* out) const {
  if (still_pinhole_) return still_pinhole_ray(s, nullptr, out);
  if (type_ == Type::kRealistic) {
    std::optional<Transform> moving;
    const Transform& w = to_world(lerp(s.time, shutter_open_, shutter_close_), &moving);
    auto shifted = [&](int axis, float eps) {
      CameraSample cs = s;
      (axis == 0 ? cs.p_film.x : cs.p_film.y) += eps;
      return cs;
    };
    // The ray and its two neighbours a twentieth of a pixel away (finite differences, made
    // even where no texture reads them, as pbrt-v3 drops a ray whose neighbours the lens
    // stops), traced through the lens together; a neighbour the lens stops is tried on the
    // other side alone.
    Ray film[3], lens[3];
    float area[3];
    bool passed[3];
    film[0] = realistic_film_ray(s, &area[0]);
    film[1] = realistic_film_ray(shifted(0, 0.05f), &area[1]);
    film[2] = realistic_film_ray(shifted(1, 0.05f), &area[2]);
    lens_.trace_from_film(film, 3, lens, passed);
    auto world_ray = [&](int k, Ray* r) {
      if (!passed[k]) return 0.f;
      *r = lens[k];
      float weight = realistic_weight(film[k], area[k], r);
      if (weight > 0) {
        const Vec3 dw = w.vector(r->d);
        r->o = world_origin(w, r->o, dw);
        r->d = normalize(dw);
      }
      return weight;
    };
    Ray central;
    float weight = world_ray(0, &central);
    if (weight == 0) return 0;
    *out = RayDifferential(central);
    for (int axis = 0; axis < 2; ++axis) {
      float shifted_weight = 0;
      for (float eps : {0.05f, -0.05f}) {
        Ray r;
        if (eps > 0) {
          shifted_weight = world_ray(1 + axis, &r);
        } else {
          film[0] = realistic_film_ray(shifted(axis, eps), &area[0]);
          passed[0] = lens_.trace_from_film(film[0], &lens[0]);
          shifted_weight = world_ray(0, &r);
        }
        Vec3 o = central.o + (r.o - central.o) / eps;
        Vec3 d = central.d + (r.d - central.d) / eps;
        (axis == 0 ? out->rx_o : out->ry_o) = o;
        (axis == 0 ? out->rx_d : out->ry_d) = d;
        if (shifted_weight != 0) break;
      }
      if (shifted_weight == 0) return 0;
    }
    out->has_differentials = true;
    return weight;
  }
  RayDifferential r;
  r.time = lerp(s.time, shutter_open_, shutter_close_);
  if (type_ == Type::kEnvironment) {
    float theta = kPi * s.p_film.y / resolution_.y;
    float phi = 2 * kPi * s.p_film.x / resolution_.x;
    Vec3 d{std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)};
    r.o = {0, 0, 0};
    r.d = d;
    r.tmax = kInfinity;
    // pbrt-v3's environment camera has no differentials.
    r.has_differentials = false;
  } else {
    Vec3 p_camera = raster_to_camera_.point({s.p_film.x, s.p_film.y, 0});
    // One lens point for the ray and both differentials.
    const Vec2 pl = lens_radius_ > 0 ? concentric_sample_disk(s.p_lens) * lens_radius_ : Vec2{};
    auto thin_lens = [&](Vec3 o, Vec3 d, Vec3* lo, Vec3* ld) {
      if (lens_radius_ > 0) {
        float ft = focal_distance_ / d.z;
        Vec3 focus = o + d * ft;
        *lo = {o.x + pl.x, o.y + pl.y, o.z};
        // Perspective rays start at the lens centre; orthographic at their raster point.
        *ld = normalize(focus - *lo);
      } else {
        *lo = o;
        *ld = d;
      }
    };
    Vec3 o, d, o_pinhole, d_pinhole;
    if (type_ == Type::kPerspective) {
      o_pinhole = {0, 0, 0};
      d_pinhole = normalize(p_camera);
    } else {
      o_pinhole = p_camera;
      d_pinhole = {0, 0, 1};
    }
    thin_lens(o_pinhole, d_pinhole, &o, &d);
    r.o = o;
    r.d = d;
    r.has_differentials = differentials_;
    if (r.has_differentials && type_ == Type::kPerspective) {
      thin_lens(o_pinhole, normalize(p_camera + dx_camera_), &r.rx_o, &r.rx_d);
      thin_lens(o_pinhole, normalize(p_camera + dy_camera_), &r.ry_o, &r.ry_d);
    } else if (r.has_differentials) {
      thin_lens(p_camera + dx_camera_, d_pinhole, &r.rx_o, &r.rx_d);
      thin_lens(p_camera + dy_camera_, d_pinhole, &r.ry_o, &r.ry_d);
    }
  }
  // To world space: where every ray leaves from the camera-space origin, its world point was
  // taken there once, in build(). (A still pinhole perspective camera never gets here:
  // still_pinhole_ray.)
  const bool fixed_origin = !motion_.animated() && type_ == Type::kEnvironment;
  std::optional<Transform> moving;
  const Transform& w = to_world(r.time, &moving);
  const Vec3 dw = w.vector(r.d);
  out->o =
      fixed_origin ? origin_past_error(origin_world_, dw, origin_error_) : world_origin(w, r.o, dw);
  out->d = normalize(dw);
  out->tmax = kInfinity;
  out->time = r.time;
  out->has_differentials = r.has_differentials;
  if (r.has_differentials) {
    out->rx_o = fixed_origin ? origin_world_ : w.point(r.rx_o);
    out->ry_o = fixed_origin ? origin_world_ : w.point(r.ry_o);
    out->rx_d = normalize(w.vector(r.rx_d));
    out->ry_d = normalize(w.vector(r.ry_d));
  }
  return 1;
}

float Camera::lens_area() const {
  // A pinhole counts as area 1 (pbrt-v3), so its positional pdf is 1 and We per solid angle only.
  return lens_radius_ != 0 ? kPi * lens_radius_ * lens_radius_ : 1;
}

bool Camera::inside_sample_bounds(Vec2 p) const {
  // Half-open, compared in float as the raster point is continuous.
  return p.x >= float(sample_bounds_.min.x) && p.x < float(sample_bounds_.max.x) &&
         p.y >= float(sample_bounds_.min.y) && p.y < float(sample_bounds_.max.y);
}

bool Camera::project_to_raster(const Ray& ray, float* cos_theta, Vec2* p_raster) const {
  // A still camera's inverse and viewing direction are kept (bdpt projects every light
  // subpath vertex): making them per call took most of this function's time.
  if (!motion_.animated())
    return project_through(camera_from_world_, forward_world_, ray, cos_theta, p_raster);
  const Transform w = motion_.at(ray.time);
  return project_through(w.inverse(), normalize(w.vector({0, 0, 1})), ray, cos_theta, p_raster);
}

bool Camera::project_through(const Transform& from_world, Vec3 forward, const Ray& ray,
                             float* cos_theta, Vec2* p_raster) const {
  Vec3 d = normalize(ray.d);
  *cos_theta = dot(d, forward);
  if (*cos_theta <= 0) return false;
  // A thin lens images the plane of focus sharply and a pinhole every depth, so the point where
  // the ray crosses that plane (z = 1 for the pinhole) projects to its raster position; the
  // ray leaves from the lens at z = 0.
  float t = (lens_radius_ > 0 ? focal_distance_ : 1) / *cos_theta;
  Vec3 p_camera = from_world.point(ray.o + d * t);
  Vec3 p = raster_from_camera_.point(p_camera);
  *p_raster = {p.x, p.y};
  return true;
}

Rgb Camera::we(const Ray& ray, Vec2* p_raster) const {
  if (type_ != Type::kPerspective) return Rgb(0);
  float cos_theta;
  Vec2 p;
  if (!project_to_raster(ray, &cos_theta, &p)) return Rgb(0);
  // pbrt-v3 reports the raster point even when it falls outside the image.
  if (p_raster) *p_raster = p;
  if (!inside_sample_bounds(p)) return Rgb(0);
  // Uniform over the area A on z = 1, where dA = dw / cos^3 (at distance 1 / cos, seen at
  // angle theta); dividing by the measurement equation's cos(theta) leaves 1 / (A lens cos^4).
  float cos2 = cos_theta * cos_theta;
  return Rgb(1 / (image_area_ * lens_area() * cos2 * cos2));
}

void Camera::pdf_we(const Ray& ray, float* pdf_pos, float* pdf_dir) const {
  *pdf_pos = *pdf_dir = 0;
  if (type_ != Type::kPerspective) return;
  float cos_theta;
  Vec2 p;
  if (!project_to_raster(ray, &cos_theta, &p) || !inside_sample_bounds(p)) return;
  *pdf_pos = 1 / lens_area();
  // Uniform over the image area A at distance 1 / cos(theta), seen at angle theta.
  *pdf_dir = 1 / (image_area_ * cos_theta * cos_theta * cos_theta);
}

Rgb Camera::sample_wi(const Interaction& ref, Vec2 u, Vec3* wi, float* pdf, Vec2* p_raster,
                      Interaction* lens) const {
  *pdf = 0;
  *wi = {};
  if (type_ != Type::kPerspective) return Rgb(0);
  std::optional<Transform> moving;
  const Transform& w = to_world(ref.time, &moving);
  Vec2 p_lens = concentric_sample_disk(u) * lens_radius_;
  Interaction on_lens;
  on_lens.p = w.point({p_lens.x, p_lens.y, 0});
  on_lens.n = normalize(w.vector({0, 0, 1}));
  on_lens.time = ref.time;
  if (lens) *lens = on_lens;
  Vec3 to_lens = on_lens.p - ref.p;
  float dist = length(to_lens);
  if (dist == 0) return Rgb(0);
  *wi = to_lens / dist;
  Rgb importance = we(Ray{on_lens.p, -*wi, kInfinity, ref.time}, p_raster);
  if (importance.is_black()) return Rgb(0);
  // The lens point is uniform by area; seen from ref, that is dist^2 / (|cos| lens area) per
  // unit solid angle.
  *pdf = dist * dist / (abs_dot(on_lens.n, *wi) * lens_area());
  return importance;
}

}  // namespace rt
