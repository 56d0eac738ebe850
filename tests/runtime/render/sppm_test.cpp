// pbrt-v3's sppm: its visible-point grid finds exactly the spheres around a point; on a
// diffuse scene its image agrees with the path tracer's (photon density estimation is
// consistent, and with a small radius its bias is far below the tolerance); it renders the
// caustic of a point light through a glass sphere, which the path tracer cannot; its
// parameters are read as pbrt-v3 reads them.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "box_scene.h"
#include "runtime/render/sppm.h"
#include "runtime/render/sppm_grid.h"
#include "runtime/render_text.h"

namespace rt {
namespace {

TEST(SppmGrid, FindsExactlyTheSpheresContainingAPoint) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> pos(-2, 2), rad(0.01f, 0.4f), unit(0, 1);
  std::vector<GridSphere> spheres(500);
  for (GridSphere& s : spheres) {
    s.center = {pos(rng), pos(rng), 0.25f * pos(rng)};  // a flat cloud: unequal axes
    s.radius = unit(rng) < 0.2f ? -1 : rad(rng);        // some absent
  }
  SphereGrid grid;
  grid.build(spheres, 97);  // few buckets: many cells share one
  for (int q = 0; q < 2000; ++q) {
    const Vec3 p{2.5f * pos(rng) / 2, 2.5f * pos(rng) / 2, 0.5f * pos(rng)};
    std::vector<uint32_t> found;
    grid.for_each_containing(p, [&](uint32_t i) { found.push_back(i); });
    std::sort(found.begin(), found.end());
    std::vector<uint32_t> expected;
    for (uint32_t i = 0; i < spheres.size(); ++i)
      if (spheres[i].radius > 0 &&
          distance_squared(spheres[i].center, p) <= spheres[i].radius * spheres[i].radius)
        expected.push_back(i);
    ASSERT_EQ(found, expected) << "query " << q;
  }
}

TEST(SppmGrid, NoSpheresFindNothing) {
  std::vector<GridSphere> spheres(3);  // all absent
  SphereGrid grid;
  grid.build(spheres, 8);
  int calls = 0;
  grid.for_each_containing(Vec3{}, [&](uint32_t) { ++calls; });
  EXPECT_EQ(calls, 0);
}

// The diffuse box lit by its one-sided quad: no caustics, so the path tracer and sppm
// estimate the same image (sppm's direct light and photons meet at the first diffuse vertex;
// maxdepth counts the same scattering events in both).
std::string diffuse_box(const std::string& integrator) {
  return box_scene(integrator, false, false);
}

// The whole 24x24 image and each quadrant (walls, floor, ceiling light, sphere) within 3%.
void expect_regions_agree(const Rendered& path, const Rendered& sppm) {
  for (int q = 0; q < 5; ++q) {
    int x0 = q == 4 ? 0 : (q % 2) * 12, y0 = q == 4 ? 0 : (q / 2) * 12;
    int x1 = q == 4 ? 24 : x0 + 12, y1 = q == 4 ? 24 : y0 + 12;
    double a = mean_luminance(path, x0, x1, y0, y1), b = mean_luminance(sppm, x0, x1, y0, y1);
    EXPECT_NEAR(b / a, 1, 0.03) << "region " << q << ": path " << a << ", sppm " << b;
  }
}

TEST(Sppm, AgreesWithThePathTracerOnADiffuseScene) {
  Rendered path =
      render_text("sppm_box_path", diffuse_box(R"(Integrator "path" "integer maxdepth" [5])"));
  Rendered sppm = render_text("sppm_box_sppm", diffuse_box(R"(Integrator "sppm"
    "integer maxdepth" [5] "integer iterations" [64] "integer photonsperiteration" [30000]
    "float radius" [0.03])"));
  ASSERT_TRUE(path.ok && sppm.ok);
  expect_regions_agree(path, sppm);
  EXPECT_EQ(sppm.stats.nonfinite_samples, 0u);
  EXPECT_EQ(sppm.stats.samples, 24u * 24u * 64u);  // one camera sample per pixel per iteration
}

// The same box with floor, ceiling and back wall of a mix material (matte with plastic: three
// lobes where visible points form): those points keep their BSDF whole beside the two-lobe
// inline ones (sppm.cpp, VisibleBsdf), and the photon pass evaluates it there alike.
TEST(Sppm, AgreesWithThePathTracerWhereVisiblePointsHaveManyLobes) {
  auto mixed_box = [](const std::string& integrator) {
    std::string text = diffuse_box(integrator);
    const std::string grey = R"(Material "matte" "rgb Kd" [0.6 0.6 0.6])";
    const size_t at = text.find(grey);
    EXPECT_NE(at, std::string::npos);
    text.replace(at, grey.size(),
                 R"(MakeNamedMaterial "a" "string type" "matte" "rgb Kd" [0.6 0.6 0.6]
MakeNamedMaterial "b" "string type" "plastic" "rgb Kd" [0.4 0.4 0.4] "rgb Ks" [0.2 0.2 0.2]
  "float roughness" [0.5]
Material "mix" "string namedmaterial1" "a" "string namedmaterial2" "b" "rgb amount" [0.5 0.5 0.5])");
    return text;
  };
  Rendered path =
      render_text("sppm_mix_path", mixed_box(R"(Integrator "path" "integer maxdepth" [5])"));
  Rendered sppm = render_text("sppm_mix_sppm", mixed_box(R"(Integrator "sppm"
    "integer maxdepth" [5] "integer iterations" [64] "integer photonsperiteration" [30000]
    "float radius" [0.03])"));
  ASSERT_TRUE(path.ok && sppm.ok);
  expect_regions_agree(path, sppm);
  EXPECT_EQ(sppm.stats.nonfinite_samples, 0u);
}

// A point light straight above a glass ball (index 1.5, radius 0.5, centre 1 above the
// floor, light 3 above the centre): the ball's focus lands on the floor right under it
// (1/s' = 2(n-1)/(nR) - 1/s = 4/3 - 1/3), which the camera sees past the ball at the image
// centre. Only photons carry light there: the path tracer cannot reach a point light
// through glass, so it sees the ball's shadow.
std::string caustic_scene(const std::string& integrator) {
  return R"(
LookAt 0 2 -4  0 0 0  0 1 0
Camera "perspective" "float fov" [40]
Film "image" "integer xresolution" [32] "integer yresolution" [32]
Sampler "halton" "integer pixelsamples" [16]
)" + integrator +
         R"(
WorldBegin
LightSource "point" "point from" [0 4 0] "rgb I" [10 10 10]
AttributeBegin
  Translate 0 1 0
  Material "glass" "float index" [1.5]
  Shape "sphere" "float radius" [0.5]
AttributeEnd
Material "matte" "rgb Kd" [0.5 0.5 0.5]
Shape "trianglemesh" "point P" [-10 0 -10  10 0 -10  10 0 10  -10 0 10]
  "integer indices" [0 1 2 0 2 3]
WorldEnd
)";
}

TEST(Sppm, RendersTheCausticOfAGlassBall) {
  Rendered path = render_text("sppm_caustic_path",
                              caustic_scene(R"(Integrator "path" "integer maxdepth" [5])"));
  Rendered sppm = render_text("sppm_caustic_sppm", caustic_scene(R"(Integrator "sppm"
    "integer maxdepth" [5] "integer iterations" [32] "integer photonsperiteration" [50000]
    "float radius" [0.05])"));
  ASSERT_TRUE(path.ok && sppm.ok);
  // The floor at the image centre (the focus), and lit floor about a unit to either side.
  const double focus_sppm = mean_luminance(sppm, 15, 17, 15, 17);
  const double focus_path = mean_luminance(path, 15, 17, 15, 17);
  const double lit_sppm =
      (mean_luminance(sppm, 4, 7, 14, 18) + mean_luminance(sppm, 25, 28, 14, 18)) / 2;
  const double lit_path =
      (mean_luminance(path, 4, 7, 14, 18) + mean_luminance(path, 25, 28, 14, 18)) / 2;
  EXPECT_GT(lit_path, 0.01);
  EXPECT_NEAR(lit_sppm / lit_path, 1, 0.1)
      << "directly lit floor: path " << lit_path << ", sppm " << lit_sppm;
  EXPECT_LT(focus_path, 0.05 * lit_path) << "the path tracer sees the ball's shadow";
  EXPECT_GT(focus_sppm, 3 * lit_sppm)
      << "the focus: sppm " << focus_sppm << ", lit floor " << lit_sppm;
}

TEST(Sppm, ReadsPbrtV3Parameters) {
  auto settings_of = [](const std::string& name, const std::string& integrator) {
    pbrta::SceneArchive a;
    IntegratorSettings s;
    std::string error;
    const std::string text = R"(
LookAt 0 0 5  0 0 0  0 1 0
Camera "perspective"
Film "image" "integer xresolution" [40] "integer yresolution" [30]
  "float cropwindow" [0 0.5 0 1]
)" + integrator + R"(
WorldBegin
WorldEnd
)";
    EXPECT_TRUE(testing_support::compile_text(testing_support::scratch_dir(name), text, &a));
    EXPECT_TRUE(read_integrator(a, &s, &error)) << error;
    Film film;
    EXPECT_TRUE(film.build(a, FilmOptions{}, &error)) << error;
    return std::make_pair(s, sppm_photons_per_iteration(sppm_settings(s, 0, 0), film));
  };
  auto [defaults, default_photons] = settings_of("sppm_params_default", R"(Integrator "sppm")");
  EXPECT_EQ(defaults.type, IntegratorType::kSppm);
  EXPECT_EQ(defaults.sppm_iterations, 64);
  EXPECT_EQ(defaults.max_depth, 5);
  EXPECT_FLOAT_EQ(defaults.sppm_radius, 1.f);
  EXPECT_EQ(defaults.sppm_photons_per_iteration, -1);
  EXPECT_EQ(default_photons, 20 * 30) << "one photon per pixel of the cropped film";

  auto [alias, alias_photons] = settings_of("sppm_params_alias", R"(Integrator "sppm"
    "integer numiterations" [500] "integer photonsperiteration" [1234] "float radius" [0.075]
    "integer maxdepth" [7] "integer imagewritefrequency" [10])");
  EXPECT_EQ(alias.sppm_iterations, 500);
  EXPECT_EQ(alias_photons, 1234);
  EXPECT_FLOAT_EQ(alias.sppm_radius, 0.075f);
  EXPECT_EQ(alias.max_depth, 7);
  // --spp replaces the iteration count, as the reference renders used it.
  EXPECT_EQ(sppm_settings(alias, 16, 1).iterations, 16);
  EXPECT_EQ(sppm_settings(alias, 0, 1).iterations, 500);
}

}  // namespace
}  // namespace rt
