// The perspective camera's importance (pbrt-v3's We, Pdf_We and Sample_Wi):
// camera rays map back to their film points, W_e is normalised over the
// image and the lens, sample_wi lands where a camera ray through the point
// would start, and the film's sample bounds (not the full image) decide
// what is inside. Cameras are built from pbrt-v3 scene text.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "runtime/core/rng.h"
#include "runtime/core/sampling.h"
#include "runtime/film/film.h"
#include "runtime/render/camera.h"
#include "runtime/runtime_test_support.h"
#include "test_support.h"

namespace rt {
namespace {

constexpr int kWidth = 64, kHeight = 48;
constexpr float kFov = 50;
// Off-axis on purpose, so that world and camera space differ in every axis.
const Vec3 kEye{1, 2, 3}, kLook{0, 0.5f, -1};

std::string scene(const std::string& camera, const std::string& film_extra = "",
                  const std::string& transform = "LookAt 1 2 3  0 0.5 -1  0 1 0\n") {
  return transform + "Camera " + camera + "\nFilm \"image\" \"integer xresolution\" " +
         std::to_string(kWidth) + " \"integer yresolution\" " + std::to_string(kHeight) + " " +
         film_extra + "\nWorldBegin\nShape \"sphere\"\nWorldEnd\n";
}

const std::string kPinhole = "\"perspective\" \"float fov\" 50";
const std::string kThinLens =
    "\"perspective\" \"float fov\" 50 \"float lensradius\" 0.1 \"float focaldistance\" 4";

// Builds the camera as the renderer does: the film first, its sample bounds handed over.
bool build_camera(const std::string& name, const std::string& text, Camera* camera) {
  pbrta::SceneArchive a;
  if (!testing_support::compile_text(testing_support::scratch_dir(name), text, &a)) return false;
  Film film;
  std::string error;
  bool ok = film.build(a, FilmOptions{}, &error);
  if (ok) {
    camera->set_sample_bounds(film.sample_bounds());
    ok = camera->build(a, film.full_resolution(), &error);
  }
  EXPECT_TRUE(ok) << error;
  return ok;
}

Vec3 forward() {
  return normalize(kLook - kEye);
}

// The image's area on the camera-space plane z = 1, from the fov on the shorter axis.
float image_area() {
  float h = std::tan(radians(kFov / 2));
  return (2 * h * float(kWidth) / float(kHeight)) * (2 * h);
}

Vec2 random_film_point(Rng& rng) {
  return {rng.next_float() * kWidth, rng.next_float() * kHeight};
}

Ray camera_ray(const Camera& camera, Vec2 p_film, Vec2 p_lens, float time = 0.5f) {
  RayDifferential r;
  EXPECT_EQ(camera.generate_ray_differential({p_film, p_lens, time}, &r), 1);
  return r;
}

float lens_area(float radius) {
  return radius > 0 ? kPi * radius * radius : 1;
}

void expect_rays_land_on_their_film_points(const Camera& camera, float lens_radius) {
  Rng rng(3);
  for (int i = 0; i < 2000; ++i) {
    Vec2 p_film = random_film_point(rng);
    Ray ray = camera_ray(camera, p_film, {rng.next_float(), rng.next_float()});
    Vec2 p;
    Rgb we = camera.we(ray, &p);
    ASSERT_NEAR(p.x, p_film.x, 1e-3f) << i;
    ASSERT_NEAR(p.y, p_film.y, 1e-3f) << i;
    float cos_theta = dot(ray.d, forward());
    float expected = 1 / (image_area() * lens_area(lens_radius) * std::pow(cos_theta, 4.f));
    ASSERT_GT(we.r, 0);
    ASSERT_NEAR(we.r, expected, 1e-4f * expected) << i;
    EXPECT_EQ(we.g, we.r);
    EXPECT_EQ(we.b, we.r);
    // W_e = pdf_pos pdf_dir / cos(theta): the camera samples its rays in proportion to importance.
    float pdf_pos, pdf_dir;
    camera.pdf_we(ray, &pdf_pos, &pdf_dir);
    ASSERT_NEAR(pdf_pos, 1 / lens_area(lens_radius), 1e-6f / lens_area(lens_radius));
    ASSERT_NEAR(pdf_dir, we.r * lens_area(lens_radius) * cos_theta, 1e-4f * pdf_dir) << i;
  }
}

TEST(CameraImportance, PinholeRaysLandOnTheirFilmPoints) {
  Camera camera;
  ASSERT_TRUE(build_camera("importance_pinhole", scene(kPinhole), &camera));
  EXPECT_TRUE(camera.supports_importance());
  expect_rays_land_on_their_film_points(camera, 0);
}

TEST(CameraImportance, ThinLensRaysLandOnTheirFilmPoints) {
  Camera camera;
  ASSERT_TRUE(build_camera("importance_thin_lens", scene(kThinLens), &camera));
  expect_rays_land_on_their_film_points(camera, 0.1f);
}

// Monte Carlo over lens points (uniform on the disk) and directions (uniform in a cone around
// the viewing direction that holds the whole image): the integral of W_e cos(theta) over lens
// area and solid angle, and of pdf_dir over solid angle from the lens centre. Both are 1.
void expect_normalised(const Camera& camera, float lens_radius) {
  Vec3 z = forward();
  Vec3 x = normalize(cross(Vec3{0, 1, 0}, z));
  Vec3 y = cross(z, x);
  const float cos_max = 0.5f;  // 60 degrees; the image corners are at about 38
  const float cone_pdf = uniform_cone_pdf(cos_max);
  Rng rng(11);
  const int n = 400000;
  double we_sum = 0, pdf_sum = 0;
  for (int i = 0; i < n; ++i) {
    Vec3 c = uniform_sample_cone({rng.next_float(), rng.next_float()}, cos_max);
    Vec3 d = x * c.x + y * c.y + z * c.z;
    Vec2 disk = concentric_sample_disk({rng.next_float(), rng.next_float()}) * lens_radius;
    Vec3 o = kEye + x * disk.x + y * disk.y;
    Ray ray{o, d, kInfinity, 0.5f};
    // The lens pdf is 1 / lens area, and 1 for a pinhole.
    we_sum += camera.we(ray).r * dot(d, z) * lens_area(lens_radius) / cone_pdf;
    float pdf_pos, pdf_dir;
    camera.pdf_we(Ray{kEye, d, kInfinity, 0.5f}, &pdf_pos, &pdf_dir);
    pdf_sum += pdf_dir / cone_pdf;
  }
  EXPECT_NEAR(we_sum / n, 1, 0.01);
  EXPECT_NEAR(pdf_sum / n, 1, 0.01);
}

TEST(CameraImportance, PinholeImportanceIntegratesToOne) {
  Camera camera;
  ASSERT_TRUE(build_camera("importance_norm_pinhole", scene(kPinhole), &camera));
  expect_normalised(camera, 0);
}

TEST(CameraImportance, ThinLensImportanceIntegratesToOne) {
  Camera camera;
  ASSERT_TRUE(build_camera("importance_norm_thin_lens", scene(kThinLens), &camera));
  expect_normalised(camera, 0.1f);
}

// Points along camera rays: sample_wi must find the ray back. The camera ray generated from the
// raster point it reports, through the same lens point, starts at the sampled lens point and
// passes through the reference point.
void expect_sample_wi_finds_the_ray(const Camera& camera, float lens_radius) {
  Rng rng(5);
  int unseen = 0;
  const int n = 2000;
  for (int i = 0; i < n; ++i) {
    Vec2 p_film = random_film_point(rng);
    float time = rng.next_float();
    Ray ray = camera_ray(camera, p_film, {rng.next_float(), rng.next_float()}, time);
    Interaction ref;
    ref.p = ray.at(0.5f + 10 * rng.next_float());
    ref.time = time;
    Vec2 u{rng.next_float(), rng.next_float()};
    Vec3 wi;
    float pdf;
    Vec2 p_raster;
    Interaction lens;
    Rgb we = camera.sample_wi(ref, u, &wi, &pdf, &p_raster, &lens);
    if (lens_radius == 0) {
      // A pinhole sees the point where the ray through it came from.
      EXPECT_NEAR(p_raster.x, p_film.x, 1e-3f) << i;
      EXPECT_NEAR(p_raster.y, p_film.y, 1e-3f) << i;
    }
    // Inside the image, a point is seen from every lens point, except near the image's edges
    // for the thin lens, where a lens point can see it just outside.
    if (we.is_black()) {
      ASSERT_GT(lens_radius, 0) << i;
      EXPECT_EQ(pdf, 0);
      ++unseen;
      continue;
    }
    Ray back = camera_ray(camera, p_raster, u, time);
    EXPECT_LT(distance(back.o, lens.p), 1e-4f) << i;
    EXPECT_LT(distance(back.d, -wi), 1e-4f) << i;
    EXPECT_LT(distance(back.d, normalize(ref.p - back.o)), 1e-4f) << i;
    EXPECT_EQ(we, camera.we(Ray{lens.p, -wi, kInfinity, time}));
    // The lens point: on the lens plane, facing along the view, at the reference's time.
    EXPECT_LT(std::abs(dot(lens.p - kEye, forward())), 1e-4f) << i;
    EXPECT_LE(distance(lens.p, kEye), lens_radius + 1e-4f) << i;
    EXPECT_LT(distance(lens.n, forward()), 1e-5f) << i;
    EXPECT_EQ(lens.time, time);
    EXPECT_EQ(lens.p_error.x, 0);
    EXPECT_EQ(lens.p_error.y, 0);
    EXPECT_EQ(lens.p_error.z, 0);
    // The area density 1 / lens area as a solid angle from ref.
    float d2 = distance_squared(ref.p, lens.p);
    float expected = d2 / (abs_dot(forward(), wi) * lens_area(lens_radius));
    EXPECT_NEAR(pdf, expected, 1e-4f * expected) << i;
    EXPECT_NEAR(length(wi), 1, 1e-5f);
  }
  EXPECT_LT(unseen, n / 20);
}

TEST(CameraImportance, PinholeSampleWiProjectsThePoint) {
  Camera camera;
  ASSERT_TRUE(build_camera("importance_wi_pinhole", scene(kPinhole), &camera));
  expect_sample_wi_finds_the_ray(camera, 0);
}

TEST(CameraImportance, ThinLensSampleWiFindsTheRayThroughThePoint) {
  Camera camera;
  ASSERT_TRUE(build_camera("importance_wi_thin_lens", scene(kThinLens), &camera));
  expect_sample_wi_finds_the_ray(camera, 0.1f);
}

TEST(CameraImportance, ThinLensSampleWiFocusesThePlaneOfFocus) {
  // On the plane of focus every lens point sees a point at the same raster position.
  Camera camera;
  ASSERT_TRUE(build_camera("importance_wi_focus", scene(kThinLens), &camera));
  Rng rng(9);
  for (int i = 0; i < 500; ++i) {
    Vec2 p_film{8 + rng.next_float() * (kWidth - 16), 8 + rng.next_float() * (kHeight - 16)};
    Ray ray = camera_ray(camera, p_film, {0.5f, 0.5f});  // through the lens centre
    Interaction ref;
    ref.p = ray.at(4 / dot(ray.d, forward()));
    ref.time = 0.5f;
    Vec3 wi;
    float pdf;
    Vec2 p_raster;
    Rgb we =
        camera.sample_wi(ref, {rng.next_float(), rng.next_float()}, &wi, &pdf, &p_raster, nullptr);
    EXPECT_FALSE(we.is_black());
    EXPECT_NEAR(p_raster.x, p_film.x, 2e-3f) << i;
    EXPECT_NEAR(p_raster.y, p_film.y, 2e-3f) << i;
  }
}

void expect_nothing(const Camera& camera, Vec3 p) {
  Interaction ref;
  ref.p = p;
  ref.time = 0.5f;
  Vec3 wi;
  float pdf = -1;
  Vec2 p_raster;
  Interaction lens;
  Rgb we = camera.sample_wi(ref, {0.3f, 0.7f}, &wi, &pdf, &p_raster, &lens);
  EXPECT_TRUE(we.is_black());
  EXPECT_EQ(pdf, 0);
}

TEST(CameraImportance, PointsBehindOrOutsideTheFrameSeeNothing) {
  for (const std::string& cam : {kPinhole, kThinLens}) {
    Camera camera;
    ASSERT_TRUE(build_camera("importance_outside", scene(cam), &camera));
    // Behind the camera, and beside it on the lens plane.
    expect_nothing(camera, kEye - forward() * 2);
    expect_nothing(camera, kEye + normalize(cross(forward(), Vec3{0, 1, 0})) * 3);
    // In front but outside the frame: along rays through raster points beyond its edges.
    for (Vec2 p_film : {Vec2{-20, 24}, Vec2{90, 24}, Vec2{32, -20}, Vec2{32, 70}}) {
      Ray ray = camera_ray(camera, p_film, {0.5f, 0.5f});
      expect_nothing(camera, ray.at(3));
      // pbrt-v3 still reports where such a ray lands.
      Vec2 p;
      EXPECT_TRUE(camera.we(ray, &p).is_black());
      EXPECT_NEAR(p.x, p_film.x, 1e-3f);
      EXPECT_NEAR(p.y, p_film.y, 1e-3f);
      float pdf_pos = -1, pdf_dir = -1;
      camera.pdf_we(ray, &pdf_pos, &pdf_dir);
      EXPECT_EQ(pdf_pos, 0);
      EXPECT_EQ(pdf_dir, 0);
    }
    // A ray facing away.
    Ray away{kEye, -forward(), kInfinity, 0.5f};
    EXPECT_TRUE(camera.we(away).is_black());
    float pdf_pos = -1, pdf_dir = -1;
    camera.pdf_we(away, &pdf_pos, &pdf_dir);
    EXPECT_EQ(pdf_pos, 0);
    EXPECT_EQ(pdf_dir, 0);
  }
}

TEST(CameraImportance, SampleBoundsDecideInsideButNotTheImageArea) {
  // A crop to the left half: rays through the right half carry nothing, the left half carries
  // what the whole image would (pbrt-v3 normalises by the full image's area).
  Camera full, cropped;
  ASSERT_TRUE(build_camera("importance_full", scene(kPinhole), &full));
  ASSERT_TRUE(build_camera("importance_crop", scene(kPinhole, "\"float cropwindow\" [0 0.5 0 1]"),
                           &cropped));
  Ray left = camera_ray(full, {10, 20}, {});
  Ray right = camera_ray(full, {50, 20}, {});
  EXPECT_FALSE(cropped.we(left).is_black());
  EXPECT_EQ(cropped.we(left), full.we(left));
  EXPECT_TRUE(cropped.we(right).is_black());
  EXPECT_FALSE(full.we(right).is_black());
  // A wide filter widens the sample bounds past the image (a Gaussian's radius 2 here).
  Camera gaussian;
  ASSERT_TRUE(build_camera("importance_gaussian", "PixelFilter \"gaussian\"\n" + scene(kPinhole),
                           &gaussian));
  Ray beyond = camera_ray(full, {-1, 20}, {});
  EXPECT_TRUE(full.we(beyond).is_black());
  EXPECT_FALSE(gaussian.we(beyond).is_black());
  EXPECT_EQ(gaussian.we(left), full.we(left));
  // Without set_sample_bounds the full image is the bound.
  pbrta::SceneArchive a;
  ASSERT_TRUE(
      testing_support::compile_text(testing_support::scratch_dir("importance_default_bounds"),
                                    "PixelFilter \"gaussian\"\n" + scene(kPinhole), &a));
  Camera unset;
  std::string error;
  ASSERT_TRUE(unset.build(a, {kWidth, kHeight}, &error)) << error;
  EXPECT_TRUE(unset.we(beyond).is_black());
  EXPECT_EQ(unset.we(left), full.we(left));
}

TEST(CameraImportance, MovingCameraUsesTheReferenceTime) {
  const std::string moving =
      "TransformTimes 0 1\nActiveTransform StartTime\nLookAt 1 2 3  0 0.5 -1  0 1 0\n"
      "ActiveTransform EndTime\nLookAt 2 2 3  0 0.5 -1  0 1 0\nActiveTransform All\n";
  Camera camera;
  ASSERT_TRUE(build_camera("importance_moving", scene(kPinhole, "", moving), &camera));
  Rng rng(13);
  for (int i = 0; i < 200; ++i) {
    Vec2 p_film = random_film_point(rng);
    float time = rng.next_float();
    Ray ray = camera_ray(camera, p_film, {}, time);
    Vec2 p;
    EXPECT_FALSE(camera.we(ray, &p).is_black());
    EXPECT_NEAR(p.x, p_film.x, 1e-3f);
    EXPECT_NEAR(p.y, p_film.y, 1e-3f);
    Interaction ref;
    ref.p = ray.at(5);
    ref.time = time;
    Vec3 wi;
    float pdf;
    Interaction lens;
    EXPECT_FALSE(camera.sample_wi(ref, {}, &wi, &pdf, &p, &lens).is_black());
    EXPECT_LT(distance(lens.p, ray.o), 1e-4f);
    EXPECT_NEAR(p.x, p_film.x, 1e-3f);
    EXPECT_NEAR(p.y, p_film.y, 1e-3f);
  }
}

TEST(CameraImportance, OnlyThePerspectiveCameraHasImportance) {
  for (const char* type : {"orthographic", "environment"}) {
    Camera camera;
    ASSERT_TRUE(build_camera(std::string("importance_none_") + type,
                             scene(std::string("\"") + type + "\""), &camera));
    EXPECT_FALSE(camera.supports_importance()) << type;
    Ray ray{kEye, forward(), kInfinity, 0.5f};
    EXPECT_TRUE(camera.we(ray).is_black());
    float pdf_pos = -1, pdf_dir = -1;
    camera.pdf_we(ray, &pdf_pos, &pdf_dir);
    EXPECT_EQ(pdf_pos, 0);
    EXPECT_EQ(pdf_dir, 0);
    Interaction ref;
    ref.p = kEye + forward() * 3;
    Vec3 wi;
    float pdf = -1;
    Vec2 p;
    Interaction lens;
    EXPECT_TRUE(camera.sample_wi(ref, {0.5f, 0.5f}, &wi, &pdf, &p, &lens).is_black());
    EXPECT_EQ(pdf, 0);
  }
}

}  // namespace
}  // namespace rt
