// transmittance() between two points outside media, as pbrt-v3's VisibilityTester::Tr: 0 behind
// a surface with a material, 1 through interface surfaces, shadowalpha ignored (Tr finds hits
// as Intersect does, which reads only alpha). Scenes whose shapes are all opaque answer with
// one occluded() query (RenderScene::opaque_shapes); the others walk the hits: both must give
// Tr's answer.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "runtime/film/film.h"
#include "runtime/render/render_scene.h"
#include "runtime/render/visibility.h"
#include "runtime/runtime_test_support.h"
#include "runtime/sampler/sampler.h"
#include "test_support.h"

namespace rt {
namespace {

struct Loaded {
  pbrta::SceneArchive archive;
  RenderScene scene;
  std::unique_ptr<Sampler> sampler;
};

// A wall across z = 0 (|x|, |y| < 1) with the given attributes, and a unit sphere at z = 3.
std::unique_ptr<Loaded> load(const std::string& name, const std::string& material,
                             const std::string& wall_params = "") {
  const std::string text = R"(
LookAt 0 0 -5  0 0 0  0 1 0
Camera "perspective"
Film "image" "integer xresolution" 4 "integer yresolution" 4
Sampler "random" "integer pixelsamples" 1
WorldBegin
AttributeBegin
)" + material + R"(
Shape "trianglemesh" "integer indices" [0 1 2 0 2 3] "point P" [-1 -1 0  1 -1 0  1 1 0  -1 1 0]
  )" + wall_params + R"(
AttributeEnd
AttributeBegin
Material "matte"
Translate 0 0 3
Shape "sphere" "float radius" 1
AttributeEnd
WorldEnd
)";
  auto l = std::make_unique<Loaded>();
  EXPECT_TRUE(testing_support::compile_text(testing_support::scratch_dir(name), text, &l->archive));
  std::string error;
  EXPECT_TRUE(load_render_scene(l->archive, &l->scene, &error)) << error;
  Film film;
  EXPECT_TRUE(film.build(l->archive, {}, &error)) << error;
  l->sampler = make_sampler(l->archive, 0, 0, film.sample_bounds(), &error);
  EXPECT_TRUE(l->sampler) << error;
  return l;
}

Interaction at(Vec3 p) {
  Interaction it;
  it.p = p;
  return it;
}

float tr(Loaded& l, Vec3 from, Vec3 to) {
  RayCounters counters;
  return transmittance(l.scene, at(from), at(to), kNone, *l.sampler, &counters).g;
}

TEST(Visibility, SurfacesWithMaterialsStopRaysWithOrWithoutShadowMasks) {
  for (bool masked : {false, true}) {
    SCOPED_TRACE(masked ? "shadowalpha 0" : "no mask");
    // A shadowalpha of 0 makes the wall no surface for occluded(), yet Tr still stops there.
    auto l = load(masked ? "visibility_masked" : "visibility_opaque", R"(Material "matte")",
                  masked ? R"("float shadowalpha" 0)" : "");
    EXPECT_EQ(l->scene.opaque_shapes, !masked);
    EXPECT_EQ(tr(*l, {0, 0, -1}, {0, 0, 1}), 0.f);
    EXPECT_EQ(tr(*l, {2, 0, -1}, {2, 0, 1}), 1.f);    // past the wall's edge
    EXPECT_EQ(tr(*l, {0, 0, 1}, {0, 0, 5}), 0.f);     // into the sphere
    EXPECT_EQ(tr(*l, {0, 0, 1}, {0, 0, 1.5f}), 1.f);  // short of it
  }
}

TEST(Visibility, InterfaceSurfacesLetRaysThrough) {
  auto glass = load("visibility_interface", R"(Material "")");
  EXPECT_FALSE(glass->scene.opaque_shapes);
  EXPECT_EQ(tr(*glass, {0, 0, -1}, {0, 0, 1}), 1.f);
  EXPECT_EQ(tr(*glass, {0, 0, -1}, {0, 0, 5}), 0.f);     // through the wall, then the sphere
  EXPECT_EQ(tr(*glass, {0, 0, -1}, {0, 0, 1.5f}), 1.f);  // stops short of the sphere
}

}  // namespace
}  // namespace rt
