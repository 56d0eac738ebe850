// tests/runtime/material/material_test_scene.h — materials from compiled scene text.
//
// MaterialScene compiles pbrt-v3 text (one shape per material of interest),
// builds its textures and materials, and hands out each shape's material
// index; flat_hit() is a hit on a tilted plane with a full shading frame, so
// BSDF tests exercise the world/local frame change.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "runtime/material/materials.h"
#include "runtime/runtime_test_support.h"
#include "test_support.h"

namespace material_test {

struct MaterialScene {
  pbrta::SceneArchive archive;
  rt::TextureSet textures;
  rt::MaterialSet materials;
  std::string error;

  // False (with `error` set) when textures or materials fail to build.
  bool load(const std::string& name, const std::string& world_body) {
    std::string text = "Camera \"perspective\"\nWorldBegin\n" + world_body + "\nWorldEnd\n";
    if (!testing_support::compile_text(testing_support::scratch_dir(name), text, &archive))
      return false;
    if (!textures.build(archive, &error)) return false;
    return materials.build(archive, textures, &error);
  }
  uint32_t material_of_shape(uint32_t shape) const { return archive.shapes[shape].material; }
};

// A hit on a plane through the origin with normal n (unit), u along a unit
// tangent, at uv (0.5, 0.5), without ray differentials.
inline rt::SurfaceInteraction flat_hit(rt::Vec3 n = rt::normalize(rt::Vec3{0.3f, -0.2f, 0.9f})) {
  rt::SurfaceInteraction si;
  rt::Vec3 s, t;
  rt::coordinate_system(n, &s, &t);
  si.p = rt::Vec3{0, 0, 0};
  si.n = n;
  si.uv = {0.5f, 0.5f};
  si.dpdu = s;
  si.dpdv = t;  // s x t = n: right-handed
  si.shading = {n, s, t, rt::Vec3{}, rt::Vec3{}};
  return si;
}

}  // namespace material_test
