// The realistic camera on the real fisheye lens of the shared corpus: the
// lens focuses at the focus distance, the exit pupil bounds hold every ray
// that gets through, rays traced together come out as each alone, and the
// camera's rays carry positive weights.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "runtime/core/rng.h"
#include "runtime/render/camera.h"
#include "runtime/render/lens_system.h"
#include "runtime/runtime_test_support.h"
#include "test_support.h"

namespace rt {
namespace {

std::string lens_file() {
  return testing_support::shared_dir() +
         "/scenes/hm-cameras/pbrt-v3-scenes/sanmiguel/lenses/fisheye.10mm.dat";
}

std::string scene(float aperture, float focus) {
  return "LookAt 0 2 2  0 0 0  0 0 1\nCamera \"realistic\" \"string lensfile\" \"" + lens_file() +
         "\" \"float aperturediameter\" " + std::to_string(aperture) + " \"float focusdistance\" " +
         std::to_string(focus) +
         "\nFilm \"image\" \"integer xresolution\" 40 \"integer yresolution\" 40\n"
         "WorldBegin\nShape \"sphere\"\nWorldEnd\n";
}

// The archive's lens data, built into a lens with a reduced pupil search.
bool build_lens(const std::string& name, float aperture, float focus, LensSystem* lens,
                int pupil_samples = 1 << 14) {
  pbrta::SceneArchive a;
  if (!testing_support::compile_text(testing_support::scratch_dir(name), scene(aperture, focus),
                                     &a))
    return false;
  uint32_t e = a.scene().camera;
  const pbrta::ValueRecord* v = a.value(e, "lensdata");
  if (!v || v->count != 48) return false;
  std::string error;
  bool ok = lens->build(a.floats(*v), v->count, aperture, focus, 0.035f, &error, pupil_samples);
  EXPECT_TRUE(ok) << error;
  return ok;
}

// Rays from one film point through the whole pupil meet the plane z = depth
// (camera space, measured from the film as pbrt-v3's focus distance is):
// the RMS distance of their hits from the hits' mean.
float spread_at(const LensSystem& lens, Vec3 p_film, float depth, int* through) {
  Rng rng(7);
  double sx = 0, sy = 0, sxx = 0, syy = 0;
  int n = 0;
  for (int i = 0; i < 4000; ++i) {
    Vec3 p_rear =
        lens.sample_exit_pupil({p_film.x, p_film.y}, {rng.next_float(), rng.next_float()}, nullptr);
    Ray r{p_film, p_rear - p_film};
    Ray out;
    if (!lens.trace_from_film(r, &out)) continue;
    float t = (depth - out.o.z) / out.d.z;
    Vec3 p = out.at(t);
    sx += p.x;
    sy += p.y;
    sxx += double(p.x) * p.x;
    syy += double(p.y) * p.y;
    ++n;
  }
  *through = n;
  if (n == 0) return -1;
  double vx = sxx / n - (sx / n) * (sx / n), vy = syy / n - (sy / n) * (sy / n);
  return float(std::sqrt(std::max(0.0, vx + vy)));
}

TEST(RealisticCamera, RaysFromOneFilmPointMeetOnThePlaneOfFocus) {
  // A small stop: the paraxial (thick-lens) focus is exact there; the open
  // fisheye's spherical aberration moves its best focus nearer, in pbrt-v3 too.
  LensSystem lens;
  ASSERT_TRUE(build_lens("realistic_focus", 0.5f, 0.55f, &lens));
  // The film moved away from the lens file's own spacing to focus at 0.55 m.
  EXPECT_GT(lens.rear_z(), 0);
  EXPECT_LT(lens.rear_z(), lens.front_z());
  for (Vec3 p_film : {Vec3{0, 0, 0}, Vec3{0.002f, 0.001f, 0}}) {
    int n_focus, n_near, n_far;
    float at_focus = spread_at(lens, p_film, 0.55f, &n_focus);
    float nearer = spread_at(lens, p_film, 0.55f * 0.7f, &n_near);
    float farther = spread_at(lens, p_film, 0.55f * 1.4f, &n_far);
    ASSERT_GT(n_focus, 500);
    ASSERT_GT(n_near, 500);
    ASSERT_GT(n_far, 500);
    // The blur circle shrinks to (near) a point at the focus distance: under
    // ten micrometres there, ten times that at 0.7 and 1.4 times the distance
    // on the axis (three times off it, where the fisheye's field curves).
    float factor = p_film.x == 0 ? 10 : 3;
    EXPECT_LT(at_focus, 1e-5f) << p_film.x;
    EXPECT_GT(nearer, factor * at_focus) << p_film.x;
    EXPECT_GT(farther, factor * at_focus) << p_film.x;
  }
  // Focusing closer moves the film away from the lens.
  LensSystem close;
  ASSERT_TRUE(build_lens("realistic_focus_close", 0.5f, 0.2f, &close));
  EXPECT_GT(close.rear_z(), lens.rear_z());
  int n;
  EXPECT_LT(spread_at(close, {0, 0, 0}, 0.2f, &n), 0.25f * spread_at(close, {0, 0, 0}, 0.55f, &n));
}

TEST(RealisticCamera, ExitPupilBoundsHoldEveryRayThatGetsThrough) {
  LensSystem lens;
  ASSERT_TRUE(build_lens("realistic_pupil", 5.5f, 0.55f, &lens));
  float half_diagonal = 0.035f / 2;
  const auto& bounds = lens.pupil_bounds();
  ASSERT_EQ(bounds.size(), size_t(LensSystem::kPupilIntervals));
  float rear = lens.rear_radius();
  Rng rng(3);
  int through = 0, stopped = 0;
  for (int i = 0; i < 200000; ++i) {
    int interval = int(rng.next_u32(LensSystem::kPupilIntervals));
    float r = (interval + rng.next_float()) / LensSystem::kPupilIntervals * half_diagonal;
    Vec3 p_film{r, 0, 0};
    Vec3 p_rear{(2 * rng.next_float() - 1) * 1.5f * rear, (2 * rng.next_float() - 1) * 1.5f * rear,
                lens.rear_z()};
    Ray ray{p_film, p_rear - p_film};
    if (!lens.trace_from_film(ray, nullptr)) {
      ++stopped;
      continue;
    }
    ++through;
    EXPECT_TRUE(bounds[size_t(interval)].inside({p_rear.x, p_rear.y}))
        << "interval " << interval << " rear " << p_rear.x << " " << p_rear.y;
  }
  EXPECT_GT(through, 1000);
  EXPECT_GT(stopped, 1000);
  // On the axis the pupil is centred; farther out it moves toward +x, and
  // from the film's corners no ray gets through (the whole search square).
  const PupilBounds& axis = bounds.front();
  EXPECT_LT(std::abs(axis.min.x + axis.max.x), 0.05f * (axis.max.x - axis.min.x));
  EXPECT_GT(bounds[40].min.x, axis.min.x + 0.1f * (axis.max.x - axis.min.x));
  EXPECT_FLOAT_EQ(bounds.back().max.x, 1.5f * rear);
}

// Rays traced through the lens together pass or stop as each does alone, and come out with the
// same bits, whatever the others do (random film points and rear points, a third of them outside
// the rear element, so that rays stop at different interfaces).
TEST(RealisticCamera, RaysTracedTogetherComeOutAsEachAlone) {
  LensSystem lens;
  ASSERT_TRUE(build_lens("realistic_batch", 5.5f, 0.55f, &lens));
  const float rear = lens.rear_radius(), half_diagonal = 0.035f / 2;
  Rng rng(17);
  int through = 0, stopped = 0;
  for (int i = 0; i < 20000; ++i) {
    const int n = 1 + int(rng.next_u32(LensSystem::kMaxTraced));
    Ray in[LensSystem::kMaxTraced], out[LensSystem::kMaxTraced];
    bool passed[LensSystem::kMaxTraced];
    for (int k = 0; k < n; ++k) {
      Vec3 p_film{(2 * rng.next_float() - 1) * half_diagonal,
                  (2 * rng.next_float() - 1) * half_diagonal, 0};
      Vec3 p_rear{(2 * rng.next_float() - 1) * 1.5f * rear,
                  (2 * rng.next_float() - 1) * 1.5f * rear, lens.rear_z()};
      in[k] = Ray{p_film, p_rear - p_film};
      in[k].time = rng.next_float();
    }
    lens.trace_from_film(in, n, out, passed);
    for (int k = 0; k < n; ++k) {
      Ray alone;
      const bool ok = lens.trace_from_film(in[k], &alone);
      ASSERT_EQ(passed[k], ok) << "ray " << k << " of " << n;
      if (!ok) {
        ++stopped;
        continue;
      }
      ++through;
      ASSERT_EQ(std::memcmp(&alone, &out[k], sizeof alone), 0) << "ray " << k << " of " << n;
    }
  }
  EXPECT_GT(through, 2000);
  EXPECT_GT(stopped, 2000);
}

TEST(RealisticCamera, CameraRaysLeaveTheFrontElementWithPositiveWeight) {
  pbrta::SceneArchive a;
  ASSERT_TRUE(testing_support::compile_text(testing_support::scratch_dir("realistic_camera"),
                                            scene(5.5f, 0.55f), &a));
  Camera camera;
  camera.set_film_diagonal(0.035f);
  camera.set_pupil_samples(1 << 14);  // pbrt-v3's 2^20 per interval takes seconds
  std::string error;
  ASSERT_TRUE(camera.build(a, {40, 40}, &error)) << error;
  ASSERT_EQ(camera.type(), Camera::Type::kRealistic);
  Rng rng(11);
  int live = 0;
  double centre_weight = 0;
  int centre_n = 0;
  for (int i = 0; i < 20000; ++i) {
    CameraSample s;
    s.p_film = {40 * rng.next_float(), 40 * rng.next_float()};
    s.p_lens = {rng.next_float(), rng.next_float()};
    RayDifferential ray;
    float w = camera.generate_ray_differential(s, &ray);
    ASSERT_GE(w, 0);
    ASSERT_TRUE(std::isfinite(w));
    if (w == 0) continue;
    ++live;
    EXPECT_NEAR(length(ray.d), 1, 1e-4f);
    EXPECT_TRUE(ray.has_differentials);
    // The lens looks from the eye (0 2 2) toward the origin.
    EXPECT_GT(dot(ray.d, normalize(Vec3{0, -2, -2})), 0.0f);
    if (std::abs(s.p_film.x - 20) < 2 && std::abs(s.p_film.y - 20) < 2) {
      centre_weight += w;
      ++centre_n;
    }
  }
  EXPECT_GT(live, 2000);
  // simpleweighting: cos^4 times the pupil area relative to the axis', about 1 near the centre.
  ASSERT_GT(centre_n, 10);
  EXPECT_NEAR(centre_weight / centre_n, 1.0, 0.05);
  // Unknown lens data stops the build with a message.
  LensSystem bad;
  float odd[3] = {1, 2, 3};
  EXPECT_FALSE(bad.build(odd, 3, 1, 1, 0.035f, &error));
  EXPECT_NE(error.find("4 per element"), std::string::npos);
}

}  // namespace
}  // namespace rt
