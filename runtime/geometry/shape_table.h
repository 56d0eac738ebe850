// runtime/geometry/shape_table.h — every archived shape as plain render data.
//
// One ShapeInfo per archive ShapeRecord (same index): its kind, its
// world-from-object transform (for shapes inside an object definition: the
// object-from-shape transform; the instance adds its own), orientation flags,
// the quadric's parameters with pbrt-v3's computed defaults applied, a curve's
// Bézier segments (curve.h), and for
// triangle meshes pointers straight into the archive's geometry arrays
// (object space; never copied). Intersection (runtime/geometry), area-light
// sampling (runtime/light) and materials read this table; it is built once
// at load and then read-only.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "format/scene_archive.h"
#include "runtime/core/animated_transform.h"
#include "runtime/core/transform.h"
#include "runtime/geometry/curve.h"

namespace rt {

enum class ShapeKind : uint8_t {
  kTriangles,  // trianglemesh, plymesh, and shapes pbrtc refined (loopsubdiv, nurbs, heightfield)
  kSphere,
  kCylinder,
  kDisk,
  kCone,
  kParaboloid,
  kHyperboloid,
  kCurve,
};

struct QuadricParams {
  float radius = 1, zmin = -1, zmax = 1, phimax = 2 * kPi;  // phimax in radians
  float height = 0, inner_radius = 0;                       // disk, cone (height)
  Vec3 p1, p2;                                              // hyperboloid
};

struct MeshView {
  uint32_t num_vertices = 0, num_triangles = 0;
  const float* positions = nullptr;   // 3 per vertex, object space
  const float* normals = nullptr;     // 3 per vertex or nullptr
  const float* tangents = nullptr;    // 3 per vertex or nullptr
  const float* uv = nullptr;          // 2 per vertex or nullptr
  const uint32_t* indices = nullptr;  // 3 per triangle
  const int32_t* face_indices = nullptr;
  Vec3 position(uint32_t v) const {
    return {positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]};
  }
};

struct ShapeInfo {
  ShapeKind kind = ShapeKind::kTriangles;
  uint32_t entity = kNone;
  Transform object_to_world;  // see the header comment for shapes in objects
  bool reverse_orientation = false;
  bool swaps_handedness = false;
  bool animated = false;  // the record's transform differs at start and end
  // Animated shapes: the transform over the shutter (object_to_world is its
  // start). pbrt-v3 makes such a shape with the identity transform and moves
  // it as a whole, so its orientation never counts the transform's handedness.
  const AnimatedTransform* motion = nullptr;
  uint32_t material = kNone;
  // No material or the interface one (a medium's boundary): rays only pass through it. Set by
  // the renderer once materials are known (load_render_scene); false until then.
  bool passes_through = false;
  uint32_t area_light = kNone;  // index into the archive's area lights
  uint32_t object = kNone;      // object definition, or kNone for the world
  // Media on either side (index into the archive's media, or kNone). Only a
  // shape whose two differ changes the medium of a ray crossing it.
  uint32_t inside_medium = kNone, outside_medium = kNone;
  bool medium_transition() const { return inside_medium != outside_medium; }
  QuadricParams q;
  MeshView mesh;
  const CurveShape* curve = nullptr;  // kCurve: its Bézier segments
  // alpha / shadowalpha: constant value or texture index (kNone = constant).
  float alpha = 1, shadow_alpha = 1;
  uint32_t alpha_texture = kNone, shadow_alpha_texture = kNone;
  // pbrt-v3 flips normals of quadrics and normal-less meshes when this is set.
  bool flip_normals() const { return reverse_orientation != swaps_handedness; }
  bool has_alpha() const {
    return alpha_texture != kNone || shadow_alpha_texture != kNone || alpha != 1 ||
           shadow_alpha != 1;
  }
  // Masks that can drop a hit (a hit is dropped only where the value is exactly 0).
  bool has_alpha_mask() const { return alpha_texture != kNone || alpha == 0; }
  bool has_shadow_mask() const { return shadow_alpha_texture != kNone || shadow_alpha == 0; }
};

class ShapeTable {
 public:
  // Reads every shape record; false with "file:line: ..." messages for data
  // the runtime cannot use (a projective or singular transform).
  [[nodiscard]] bool build(const pbrta::SceneArchive& archive, std::string* error);
  uint32_t size() const { return uint32_t(shapes_.size()); }
  const ShapeInfo& operator[](uint32_t i) const { return shapes_[i]; }
  void set_passes_through(uint32_t i, bool v) { shapes_[i].passes_through = v; }

 private:
  std::vector<ShapeInfo> shapes_;
  std::vector<AnimatedTransform> motions_;  // sized once: shapes point into it
  std::vector<CurveShape> curves_;          // likewise
};

}  // namespace rt
