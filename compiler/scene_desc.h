// compiler/scene_desc.h — a validated pbrt-v3 scene, resolved to plain data.
//
// This is what the front end produces and the archive writer consumes: every
// directive's meaning already applied (graphics state, named things, transform
// stack, per-shape material overrides), every parameter resolved against the
// schema in format/schema.h to a typed value with pbrt-v3's default filled in,
// and spectra converted to the RGB pbrt-v3's RGB build would use. Entities
// refer to each other by int32 index into the vectors of SceneDesc, with -1
// (kNone) for none; there are no pointers and no names left to look up.
//
// One SceneDesc owns all its data. It is built by SceneBuilder (one thread) and
// read-only after that.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "compiler/image_decoder.h"
#include "compiler/source_files.h"
#include "compiler/transform.h"
#include "format/mesh_arrays.h"
#include "format/schema.h"

namespace pbrtc {

inline constexpr int32_t kNone = -1;

// One resolved parameter of an Entity. Which of floats/ints/strings holds it
// follows the schema kind: kInt and kBool in ints; kString in strings; all
// other kinds in floats (a point3 or rgb is 3 floats). count is the number of
// elements (a point3 counts 1).
struct Value {
  uint32_t offset = 0;
  uint32_t count = 0;
  int32_t texture = kNone;  // kFloatTex/kSpectrumTex: a texture index, or kNone for the constant
  bool given = false;       // false: the schema default (or, for computed defaults, none yet)
};

// An instance of one schema type: one Value per schema parameter, in order.
struct Entity {
  pbrta::Category category = pbrta::Category::kShape;
  int type = -1;  // index into the category's schema types
  std::vector<Value> values;
  std::vector<float> floats;
  std::vector<int32_t> ints;
  std::vector<std::string> strings;
  Loc loc;  // the directive it came from

  const pbrta::TypeSpec& spec() const;
  std::string_view type_name() const;
  int slot(std::string_view param) const;  // -1 if the type has no such parameter
  bool given(std::string_view param) const;
  float get_float(std::string_view param) const;
  int32_t get_int(std::string_view param) const;
  bool get_bool(std::string_view param) const;
  const std::string& get_string(std::string_view param) const;
  const float* get_floats(std::string_view param, uint32_t* count = nullptr) const;
  int32_t get_texture(std::string_view param) const;
};

// An object-to-render transform, possibly animated between two times.
struct AnimatedTransform {
  Matrix4 start, end;
  double start_time = 0, end_time = 1;
  bool animated() const { return start != end; }
};

struct TriangleMesh {
  std::vector<float> P;               // 3 floats per vertex, object space
  std::vector<float> N;               // empty or 3 per vertex
  std::vector<float> S;               // empty or 3 per vertex
  std::vector<float> uv;              // empty or 2 per vertex
  std::vector<uint32_t> indices;      // 3 per triangle
  std::vector<int32_t> face_indices;  // empty or 1 per triangle
  // Refined shapes (compiler/refine.h): loopsubdiv levels, nurbs grid size; 0 otherwise.
  uint32_t refine_level = 0;
  size_t num_vertices() const { return P.size() / 3; }
  size_t num_triangles() const { return indices.size() / 3; }
};

// A mesh as the view the PLY writer and the Draco wrapper take.
inline pbrta::MeshArrays arrays_of(const TriangleMesh& m) {
  pbrta::MeshArrays a;
  a.positions = m.P.data();
  a.normals = m.N.empty() ? nullptr : m.N.data();
  a.uv = m.uv.empty() ? nullptr : m.uv.data();
  a.indices = m.indices.data();
  a.face_indices = m.face_indices.empty() ? nullptr : m.face_indices.data();
  a.num_vertices = m.num_vertices();
  a.num_triangles = m.num_triangles();
  return a;
}

struct TextureDesc {
  std::string name;
  Entity params;  // kFloatTexture or kSpectrumTexture
  Matrix4 world_from_texture;
  int32_t image = kNone;  // imagemap: index into SceneDesc::images
};

struct MaterialDesc {
  std::string name;                 // for named materials; empty otherwise
  Entity params;                    // kMaterial; type "none" for the interface material ""
  int32_t mix[2] = {kNone, kNone};  // mix: the two materials (namedmaterial1, namedmaterial2)
};

struct MediumDesc {
  std::string name;
  Entity params;
  Matrix4 world_from_medium;
};

struct LightDesc {
  Entity params;
  Matrix4 world_from_light;
  int32_t medium = kNone;  // the outside medium at the light's definition
  int32_t image = kNone;   // infinite, projection, goniometric "mapname": index into images
};

// An image decoded at compile time (compiler/scene_images.h): an imagemap texture's or a light's
// map with its MIP pyramid, an environment map's sampling distribution, or a resampled map's
// texels as decoded (one level; what pbrtc --dump writes back out).
struct ImageDesc {
  std::string source;  // the file decoded, as resolved
  DecodedImage image;
  int32_t distribution = kNone;  // environment maps: the image of pbrt-v3's sampling distribution
  int32_t source_image = kNone;  // resampled maps: the image as decoded, before resampling
};

struct ShapeDesc {
  Entity params;               // bulk mesh arrays are moved to meshes[mesh]
  int32_t mesh = kNone;        // trianglemesh, plymesh, refined shapes: index into meshes
  int32_t material = kNone;    // index into materials
  int32_t area_light = kNone;  // index into area_lights, or kNone
  int32_t inside_medium = kNone, outside_medium = kNone;
  int32_t transform = 0;   // index into transforms (world from object)
  int32_t object = kNone;  // the object definition it belongs to, or kNone for the world
  bool reverse_orientation = false;
  bool transform_swaps_handedness = false;
};

struct ObjectDesc {
  std::string name;
  std::vector<int32_t> shapes;
  Loc loc;
};

struct InstanceDesc {
  int32_t object = kNone;
  int32_t transform = 0;  // world from instance
  Loc loc;
};

struct CameraDesc {
  Entity params;
  AnimatedTransform camera_from_world;
  int32_t medium = kNone;
  bool given = false;
};

// What the scene calls for; the runtime simulates only these.
struct Effects {
  bool media = false;
  bool motion_blur = false;
  bool textures = false;  // any non-constant texture is used
  bool area_lights = false;
  bool infinite_lights = false;
  bool subsurface = false;
  bool instancing = false;
  bool alpha = false;
};

struct SceneDesc {
  CameraDesc camera;
  Entity film, filter, sampler, integrator, accelerator;
  std::vector<TextureDesc> textures;
  std::vector<MaterialDesc> materials;
  std::vector<MediumDesc> media;
  std::vector<LightDesc> lights;
  std::vector<Entity> area_lights;
  std::vector<ShapeDesc> shapes;
  std::vector<TriangleMesh> meshes;
  std::vector<AnimatedTransform> transforms;
  std::vector<ObjectDesc> objects;
  std::vector<InstanceDesc> instances;
  std::vector<ImageDesc> images;  // filled by decode_scene_images once the scene is built
  // Every file the compile read (scene files, meshes, spectra), for provenance
  // and cache keys, as display paths.
  std::vector<std::string> input_files;
  Effects effects;
};

struct SceneCounts {
  size_t shapes = 0, triangles = 0, lights = 0, area_lights = 0, materials = 0, textures = 0,
         media = 0, objects = 0, instances = 0;
};
SceneCounts count_scene(const SceneDesc& scene);

}  // namespace pbrtc
