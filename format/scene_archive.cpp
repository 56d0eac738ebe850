// SceneArchive: loading an archive (its sections, with validate_records() and
// validate_geometry(), which are in format/scene_validation.cpp) and reading its records
// (format/scene_archive.h).
#include "format/scene_archive.h"

#include <cstddef>
#include <cstring>

namespace pbrta {

std::string_view SceneArchive::string(uint32_t i) const {
  if (i >= num_strings_) return {};
  return std::string_view(string_data_ + string_offsets_[i],
                          string_offsets_[i + 1] - string_offsets_[i]);
}

const TypeSpec& SceneArchive::type_of(uint32_t entity) const {
  const EntityRecord& e = entities[entity];
  return category_spec(Category(e.category)).types[e.type];
}

std::string_view SceneArchive::type_name(uint32_t entity) const {
  return type_of(entity).name;
}

const ValueRecord* SceneArchive::value(uint32_t entity, std::string_view name) const {
  const int p = find_param(type_of(entity), name);
  if (p < 0) return nullptr;  // validate_records(): every parameter of the type has its value
  return &values[entities[entity].first_value + uint32_t(p)];
}

bool SceneArchive::given(uint32_t entity, std::string_view name) const {
  const ValueRecord* v = value(entity, name);
  return v && (v->flags & kValueGiven);
}

const float* SceneArchive::floats(const ValueRecord& v) const {
  return reinterpret_cast<const float*>(words.data + v.offset);
}

float SceneArchive::get_float(uint32_t entity, std::string_view name, float fallback) const {
  const ValueRecord* v = value(entity, name);
  return v && v->count ? floats(*v)[0] : fallback;
}

int32_t SceneArchive::get_int(uint32_t entity, std::string_view name, int32_t fallback) const {
  const ValueRecord* v = value(entity, name);
  return v && v->count ? int32_t(words[v->offset]) : fallback;
}

std::string_view SceneArchive::get_string(uint32_t entity, std::string_view name) const {
  const ValueRecord* v = value(entity, name);
  return v && v->count ? string(words[v->offset]) : std::string_view();
}

namespace {
template <class T>
const T* at(const ArchiveReader& r, uint32_t section, uint64_t offset) {
  return reinterpret_cast<const T*>(r.section_data(section) + offset);
}
}  // namespace

const float* SceneArchive::positions(uint32_t m) const {
  return at<float>(reader_, meshes[m].section, meshes[m].positions);
}
const float* SceneArchive::normals(uint32_t m) const {
  return meshes[m].flags & kMeshNormals ? at<float>(reader_, meshes[m].section, meshes[m].normals)
                                        : nullptr;
}
const float* SceneArchive::tangents(uint32_t m) const {
  return meshes[m].flags & kMeshTangents ? at<float>(reader_, meshes[m].section, meshes[m].tangents)
                                         : nullptr;
}
const float* SceneArchive::uvs(uint32_t m) const {
  return meshes[m].flags & kMeshUV ? at<float>(reader_, meshes[m].section, meshes[m].uv) : nullptr;
}
const uint32_t* SceneArchive::indices(uint32_t m) const {
  return at<uint32_t>(reader_, meshes[m].section, meshes[m].indices);
}
const int32_t* SceneArchive::face_indices(uint32_t m) const {
  return meshes[m].flags & kMeshFaceIndices
             ? at<int32_t>(reader_, meshes[m].section, meshes[m].face_indices)
             : nullptr;
}

std::string_view SceneArchive::provenance_string(uint32_t i) const {
  if (i >= num_pstrings_) return {};
  return std::string_view(pstring_data_ + pstring_offsets_[i],
                          pstring_offsets_[i + 1] - pstring_offsets_[i]);
}

MeshArrays SceneArchive::mesh_arrays(uint32_t m) const {
  MeshArrays v;
  v.positions = positions(m);
  v.normals = normals(m);
  v.uv = uvs(m);
  v.indices = indices(m);
  v.face_indices = face_indices(m);
  v.num_vertices = meshes[m].num_vertices;
  v.num_triangles = meshes[m].num_triangles;
  return v;
}

std::string SceneArchive::where(uint32_t index) const {
  if (index >= provenance.size) return "?";
  const ProvenanceRecord& p = provenance[index];
  if (p.line == 0) return "default";
  return std::string(provenance_string(p.file)) + ":" + std::to_string(p.line);
}

std::string_view SceneArchive::name_of(uint32_t index) const {
  return index < provenance.size ? provenance_string(provenance[index].name) : std::string_view();
}

std::string_view SceneArchive::path_of(uint32_t index) const {
  return index < provenance.size ? provenance_string(provenance[index].path) : std::string_view();
}

bool SceneArchive::load(const std::string& path, int threads, std::string* error) {
  path_ = path;
  return reader_.open(path, error) && load_opened(threads, error);
}

bool SceneArchive::load_memory(std::string_view bytes, std::string_view name, int threads,
                               std::string* error) {
  path_ = std::string(name);
  return reader_.open_memory(bytes, name, error) && load_opened(threads, error);
}

bool SceneArchive::load_opened(int threads, std::string* error) {
  // The records first: they say which texels sections a renderer needs.
  std::vector<bool> records(reader_.section_count());
  for (uint32_t i = 0; i < records.size(); ++i)
    records[i] = reader_.entry(i).kind != uint32_t(SectionKind::kTexels);
  if (reader_.load_sections(threads, error, records) && validate_records(error) &&
      reader_.load_sections(threads, error, wanted_texels()) && validate_geometry(threads, error))
    return true;
  forget_records();  // nothing may read records that failed their checks
  return false;
}

std::vector<bool> SceneArchive::wanted_texels() const {
  if (!skip_sources_) return {};
  std::vector<bool> source(images.size, false), wanted(reader_.section_count(), false);
  for (const ImageRecord& im : images)
    if (im.source_image < images.size) source[im.source_image] = true;
  for (uint32_t i = 0; i < images.size; ++i)  // validate_geometry() checks the sections later
    if (!source[i] && images[i].section < wanted.size()) wanted[images[i].section] = true;
  return wanted;
}

void SceneArchive::forget_records() {
  scene_ = SceneRecord{};
  entities = {};
  values = {};
  words = {};
  transforms = {};
  textures = {};
  materials = {};
  media = {};
  lights = {};
  area_lights = {};
  shapes = {};
  objects = {};
  object_shapes = {};
  instances = {};
  meshes = {};
  images = {};
  provenance = {};
  string_offsets_ = pstring_offsets_ = nullptr;
  string_data_ = pstring_data_ = nullptr;
  num_strings_ = num_pstrings_ = 0;
}

}  // namespace pbrta
