// tests/runtime/geometry/scene_geometry_test_support.h — real scene text to a built SceneGeometry.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "runtime/geometry/scene_geometry.h"
#include "runtime/runtime_test_support.h"
#include "runtime/texture/textures.h"
#include "test_support.h"

namespace rt {

// Everything a SceneGeometry points into, kept together (not movable: the
// geometry holds pointers into the archive and the tables).
struct LoadedScene {
  pbrta::SceneArchive archive;
  ShapeTable shapes;
  TextureSet textures;
  SceneGeometry geometry;
  std::string error;  // build()'s message when it failed
  bool built = false;
};

// Builds s->archive's (loaded) shape and texture tables and its geometry, with Embree's
// device configuration when one is given; s->built, or s->error saying what failed.
inline void build_geometry(LoadedScene* s, bool watertight, const std::string& embree_config = "") {
  if (!s->shapes.build(s->archive, &s->error)) return;
  if (!s->textures.build(s->archive, &s->error)) return;
  s->geometry.set_watertight(watertight);
  s->geometry.set_embree_config(embree_config);
  s->built = s->geometry.build(s->archive, s->shapes, &s->textures, &s->error);
}

// Compiles `world` (the text between WorldBegin and WorldEnd) and builds the
// geometry; the archive must compile (the test fails otherwise), build() may
// fail, leaving its message in error.
inline std::unique_ptr<LoadedScene> load_world(const std::string& name, const std::string& world,
                                               bool watertight = false) {
  auto s = std::make_unique<LoadedScene>();
  std::string text = "Camera \"perspective\"\nWorldBegin\n" + world + "\nWorldEnd\n";
  bool ok = testing_support::compile_text(testing_support::scratch_dir(name), text, &s->archive);
  EXPECT_TRUE(ok);
  if (!ok) return s;
  build_geometry(s.get(), watertight);
  return s;
}

inline Ray make_ray(Vec3 o, Vec3 d, float tmax = kInfinity) {
  return Ray{o, d, tmax, 0};
}

}  // namespace rt
