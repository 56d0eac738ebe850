// Camera rays carry differentials only where a texture can read them: the same camera in a
// scene with a texture and in one without makes the same rays, with differentials in the
// first only (what the archive's textures effect bit decides). The realistic camera makes
// them always: pbrt-v3 drops a ray whose shifted neighbours the lens stops.
#include <gtest/gtest.h>

#include <string>

#include "runtime/core/rng.h"
#include "runtime/render/camera.h"
#include "runtime/runtime_test_support.h"
#include "test_support.h"

namespace rt {
namespace {

std::string scene(const std::string& camera, bool textured) {
  const std::string material =
      textured
          ? "Texture \"c\" \"spectrum\" \"checkerboard\"\nMaterial \"matte\" \"texture Kd\" \"c\"\n"
          : "Material \"matte\" \"rgb Kd\" [.5 .5 .5]\n";
  return "LookAt 0 2 2  0 0 0  0 0 1\n" + camera +
         "\nFilm \"image\" \"integer xresolution\" 40 \"integer yresolution\" 30\n"
         "WorldBegin\n" +
         material + "Shape \"sphere\"\nWorldEnd\n";
}

bool build_camera(const std::string& name, const std::string& text, pbrta::SceneArchive* a,
                  Camera* camera) {
  if (!testing_support::compile_text(testing_support::scratch_dir(name), text, a)) return false;
  std::string error;
  bool ok = camera->build(*a, {40, 30}, &error);
  EXPECT_TRUE(ok) << error;
  return ok;
}

void expect_same_rays(const std::string& name, const std::string& camera_text,
                      bool differentials_without_textures) {
  pbrta::SceneArchive a_tex, a_plain;
  Camera tex, plain;
  ASSERT_TRUE(build_camera(name + "_tex", scene(camera_text, true), &a_tex, &tex));
  ASSERT_TRUE(build_camera(name + "_plain", scene(camera_text, false), &a_plain, &plain));
  Rng rng(11);
  int made = 0;
  for (int i = 0; i < 500; ++i) {
    CameraSample cs;
    cs.p_film = {40 * rng.next_float(), 30 * rng.next_float()};
    cs.p_lens = {rng.next_float(), rng.next_float()};
    cs.time = rng.next_float();
    RayDifferential r_tex, r_plain;
    const float w_tex = tex.generate_ray_differential(cs, &r_tex);
    const float w_plain = plain.generate_ray_differential(cs, &r_plain);
    ASSERT_EQ(w_tex, w_plain);
    if (w_tex == 0) continue;
    ++made;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(r_tex.o[k], r_plain.o[k]);
      EXPECT_EQ(r_tex.d[k], r_plain.d[k]);
    }
    EXPECT_EQ(r_tex.time, r_plain.time);
    EXPECT_TRUE(r_tex.has_differentials);
    EXPECT_EQ(r_plain.has_differentials, differentials_without_textures);
    // The textured scene's differentials are rays one pixel away: not the ray itself.
    EXPECT_GT(length(r_tex.rx_d - r_tex.d) + length(r_tex.rx_o - r_tex.o), 0);
    EXPECT_GT(length(r_tex.ry_d - r_tex.d) + length(r_tex.ry_o - r_tex.o), 0);
  }
  EXPECT_GT(made, 100);
}

TEST(CameraDifferentials, PinholeMakesThemOnlyForTextures) {
  expect_same_rays("diff_pinhole", "Camera \"perspective\" \"float fov\" 40", false);
}

// A still pinhole's differential rays are its rays through the points one pixel over in x
// and in y, from the same origin (Camera::still_pinhole_ray makes all three from one map).
TEST(CameraDifferentials, PinholeDifferentialsAreTheRaysOnePixelOver) {
  pbrta::SceneArchive a;
  Camera camera;
  ASSERT_TRUE(build_camera("diff_pinhole_over",
                           scene("Camera \"perspective\" \"float fov\" 40", true), &a, &camera));
  Rng rng(5);
  for (int i = 0; i < 200; ++i) {
    CameraSample cs;
    cs.p_film = {39 * rng.next_float(), 29 * rng.next_float()};
    RayDifferential r, rx, ry;
    ASSERT_EQ(camera.generate_ray_differential(cs, &r), 1);
    CameraSample sx = cs, sy = cs;
    sx.p_film.x += 1;
    sy.p_film.y += 1;
    ASSERT_EQ(camera.generate_ray_differential(sx, &rx), 1);
    ASSERT_EQ(camera.generate_ray_differential(sy, &ry), 1);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(r.rx_d[k], rx.d[k], 1e-6f);
      EXPECT_NEAR(r.ry_d[k], ry.d[k], 1e-6f);
      EXPECT_NEAR(r.rx_o[k], r.o[k], 1e-5f);
      EXPECT_EQ(r.rx_o[k], r.ry_o[k]);
    }
  }
}

TEST(CameraDifferentials, ThinLensMakesThemOnlyForTextures) {
  expect_same_rays(
      "diff_lens",
      "Camera \"perspective\" \"float fov\" 40 \"float lensradius\" .1 \"float focaldistance\" 2",
      false);
}

TEST(CameraDifferentials, OrthographicMakesThemOnlyForTextures) {
  expect_same_rays("diff_ortho", "Camera \"orthographic\"", false);
}

TEST(CameraDifferentials, RealisticMakesThemAlways) {
  const std::string lens = testing_support::shared_dir() +
                           "/scenes/hm-cameras/pbrt-v3-scenes/sanmiguel/lenses/fisheye.10mm.dat";
  expect_same_rays("diff_realistic",
                   "Camera \"realistic\" \"string lensfile\" \"" + lens +
                       "\" \"float aperturediameter\" 1 \"float focusdistance\" 2",
                   true);
}

// Rays asked for with their differentials scaled are the rays scaled afterwards, bit for bit:
// the still pinhole scales them itself, every other camera through scale_differentials.
TEST(CameraDifferentials, ScaledAsScaleDifferentialsScales) {
  for (const char* camera_text :
       {"Camera \"perspective\" \"float fov\" 40",
        "Camera \"perspective\" \"float fov\" 40 \"float lensradius\" 0.05 "
        "\"float focaldistance\" 2",
        "Camera \"orthographic\""}) {
    SCOPED_TRACE(camera_text);
    pbrta::SceneArchive a;
    Camera camera;
    ASSERT_TRUE(build_camera("diff_scaled", scene(camera_text, true), &a, &camera));
    Rng rng(3);
    for (int i = 0; i < 200; ++i) {
      CameraSample cs;
      cs.p_film = {40 * rng.next_float(), 30 * rng.next_float()};
      cs.p_lens = {rng.next_float(), rng.next_float()};
      const float scale = 0.05f + rng.next_float();
      RayDifferential scaled, after;
      const float w = camera.generate_ray_differential(cs, scale, &scaled);
      ASSERT_EQ(w, camera.generate_ray_differential(cs, &after));
      after.scale_differentials(scale);
      ASSERT_TRUE(scaled.has_differentials);
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(scaled.o[k], after.o[k]);
        EXPECT_EQ(scaled.d[k], after.d[k]);
        EXPECT_EQ(scaled.rx_o[k], after.rx_o[k]);
        EXPECT_EQ(scaled.ry_o[k], after.ry_o[k]);
        EXPECT_EQ(scaled.rx_d[k], after.rx_d[k]);
        EXPECT_EQ(scaled.ry_d[k], after.ry_d[k]);
      }
    }
  }
}

}  // namespace
}  // namespace rt
