#include "compiler/scene_desc.h"

namespace pbrtc {

namespace {
const std::string kEmpty;
}

const pbrta::TypeSpec& Entity::spec() const {
  return pbrta::category_spec(category).types[type];
}

std::string_view Entity::type_name() const {
  return type < 0 ? "" : spec().name;
}

int Entity::slot(std::string_view param) const {
  if (type < 0) return -1;
  return pbrta::find_param(spec(), param);
}

bool Entity::given(std::string_view param) const {
  int s = slot(param);
  return s >= 0 && values[size_t(s)].given;
}

float Entity::get_float(std::string_view param) const {
  int s = slot(param);
  if (s < 0 || values[size_t(s)].count == 0) return 0;
  return floats[values[size_t(s)].offset];
}

int32_t Entity::get_int(std::string_view param) const {
  int s = slot(param);
  if (s < 0 || values[size_t(s)].count == 0) return 0;
  return ints[values[size_t(s)].offset];
}

bool Entity::get_bool(std::string_view param) const {
  return get_int(param) != 0;
}

const std::string& Entity::get_string(std::string_view param) const {
  int s = slot(param);
  if (s < 0 || values[size_t(s)].count == 0) return kEmpty;
  return strings[values[size_t(s)].offset];
}

const float* Entity::get_floats(std::string_view param, uint32_t* count) const {
  int s = slot(param);
  if (s < 0 || values[size_t(s)].count == 0) {
    if (count) *count = 0;
    return nullptr;
  }
  if (count) *count = values[size_t(s)].count;
  return floats.data() + values[size_t(s)].offset;
}

int32_t Entity::get_texture(std::string_view param) const {
  int s = slot(param);
  return s < 0 ? kNone : values[size_t(s)].texture;
}

SceneCounts count_scene(const SceneDesc& scene) {
  SceneCounts c;
  c.shapes = scene.shapes.size();
  for (const ShapeDesc& s : scene.shapes) {
    if (s.mesh != kNone) c.triangles += scene.meshes[size_t(s.mesh)].num_triangles();
    if (s.area_light != kNone) ++c.area_lights;
  }
  c.lights = scene.lights.size();
  c.materials = scene.materials.size();
  c.textures = scene.textures.size();
  c.media = scene.media.size();
  c.objects = scene.objects.size();
  c.instances = scene.instances.size();
  return c;
}

}  // namespace pbrtc
