// tests/runtime/geometry/scene_geometry_test_support.h — real scene text to a built SceneGeometry.
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <string>

#include "runtime/core/rng.h"
#include "runtime/core/sampling.h"
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
inline void build_geometry(LoadedScene* s, bool watertight, const std::string& embree_config = "",
                           size_t max_placed = SceneGeometry::kDefaultMaxPlaced) {
  if (!s->shapes.build(s->archive, &s->error)) return;
  if (!s->textures.build(s->archive, &s->error)) return;
  s->geometry.set_watertight(watertight);
  s->geometry.set_embree_config(embree_config);
  s->geometry.set_max_placed(max_placed);
  s->built = s->geometry.build(s->archive, s->shapes, &s->textures, &s->error);
}

// Compiles `world` (the text between WorldBegin and WorldEnd) and builds the
// geometry; the archive must compile (the test fails otherwise), build() may
// fail, leaving its message in error.
inline std::unique_ptr<LoadedScene> load_world(
    const std::string& name, const std::string& world, bool watertight = false,
    size_t max_placed = SceneGeometry::kDefaultMaxPlaced) {
  auto s = std::make_unique<LoadedScene>();
  std::string text = "Camera \"perspective\"\nWorldBegin\n" + world + "\nWorldEnd\n";
  bool ok = testing_support::compile_text(testing_support::scratch_dir(name), text, &s->archive);
  EXPECT_TRUE(ok);
  if (!ok) return s;
  build_geometry(s.get(), watertight, "", max_placed);
  return s;
}

inline Ray make_ray(Vec3 o, Vec3 d, float tmax = kInfinity) {
  return Ray{o, d, tmax, 0};
}

// A ray from a uniform point of the box [lo, lo + size] in a uniform direction.
inline Ray random_ray(Rng& rng, Vec3 lo, Vec3 size) {
  const Vec3 o{lo.x + size.x * rng.next_float(), lo.y + size.y * rng.next_float(),
               lo.z + size.z * rng.next_float()};
  return make_ray(o, uniform_sample_sphere({rng.next_float(), rng.next_float()}));
}

// Two instances of one object (a triangle and a sphere), one plain at (2, 1, 0), one mirrored
// at (-2, -1, 0): scene text for tests of hits inside instances.
inline constexpr const char* kTwoInstancesOfAPiece = R"(
ObjectBegin "piece"
  Shape "trianglemesh" "integer indices" [0 1 2] "point P" [-1 -1 0  1 -1 0.2  0 1 0.1]
  Translate 0 0 0.5
  Shape "sphere" "float radius" 0.3
ObjectEnd
AttributeBegin
  Translate 2 1 0
  ObjectInstance "piece"
AttributeEnd
AttributeBegin
  Translate -2 -1 0
  Scale -1 1 1
  ObjectInstance "piece"
AttributeEnd
)";

// Two values alike bit for bit (floats: -0 is not 0, a NaN is itself).
inline bool same_bits(const void* a, const void* b, size_t n) {
  return std::memcmp(a, b, n) == 0;
}
#define EXPECT_SAME_BITS(a, b) EXPECT_TRUE(rt::same_bits(&(a), &(b), sizeof(a))) << #a

// Two interactions of one ray's hit alike where every interaction is filled in: what was hit,
// where (p, its error bound, t), how it faces (n, shading.n) and from where (wo).
inline void expect_same_hit_point(const SurfaceInteraction& a, const SurfaceInteraction& b) {
  EXPECT_EQ(a.shape, b.shape);
  EXPECT_EQ(a.prim, b.prim);
  EXPECT_EQ(a.instance, b.instance);
  EXPECT_EQ(a.face_index, b.face_index);
  EXPECT_SAME_BITS(a.t_hit, b.t_hit);
  EXPECT_SAME_BITS(a.p, b.p);
  EXPECT_SAME_BITS(a.p_error, b.p_error);
  EXPECT_SAME_BITS(a.n, b.n);
  EXPECT_SAME_BITS(a.shading.n, b.shading.n);
  EXPECT_SAME_BITS(a.wo, b.wo);
}

}  // namespace rt
