// format/scene_archive.h — a loaded, fully validated scene archive.
//
// SceneArchive::load() opens a .pbrta with ArchiveReader (header, table,
// checksums, decoding, in parallel), and then checks what it all means: every record as
// ARCHIVE.md section 10 requires: each index below the count of the array it
// names, each entity's category, type and value range known to this reader's
// schema, each value's words in range, the string table well formed, every
// mesh array inside its geometry section and every triangle index below its
// mesh's vertex count. Only after load() returns true may anything read the
// arrays; from then on the object is read-only and may be shared between
// threads. pbrtc --verify and pbrtrun both load through this one path.
//
// Errors name the file, the section and the reason:
//   "scene.pbrta: section 'shapes' (#11): shape 3: material 9 out of range (4 materials)".
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "format/archive.h"
#include "format/archive_reader.h"
#include "format/mesh_arrays.h"
#include "format/schema.h"

namespace pbrta {

template <class T>
struct Span {
  const T* data = nullptr;
  uint32_t size = 0;
  const T& operator[](uint32_t i) const { return data[i]; }
  const T* begin() const { return data; }
  const T* end() const { return data + size; }
};

class SceneArchive {
 public:
  [[nodiscard]] bool load(const std::string& path, int threads, std::string* error);
  // The same checks on an archive already in memory (tests, fuzzing), named `name` in errors.
  // The bytes must outlive this object: a 16-byte aligned image is used in place.
  [[nodiscard]] bool load_memory(std::string_view bytes, std::string_view name, int threads,
                                 std::string* error);

  // For renderers, before load(): texels sections that only source images name (renderers never
  // read them: ARCHIVE.md, ImageRecord) are left undecoded, their checksums unchecked.
  void skip_source_texels() { skip_sources_ = true; }

  const ArchiveReader& reader() const { return reader_; }
  const Header& header() const { return reader_.header(); }
  const SceneRecord& scene() const { return scene_; }

  Span<EntityRecord> entities;
  Span<ValueRecord> values;
  Span<uint32_t> words;
  Span<TransformRecord> transforms;
  Span<TextureRecord> textures;
  Span<MaterialRecord> materials;
  Span<MediumRecord> media;
  Span<LightRecord> lights;
  Span<uint32_t> area_lights;
  Span<ShapeRecord> shapes;
  Span<ObjectRecord> objects;
  Span<uint32_t> object_shapes;
  Span<InstanceRecord> instances;
  Span<MeshRecord> meshes;
  Span<ImageRecord> images;
  Span<ProvenanceRecord> provenance;

  uint32_t num_strings() const { return num_strings_; }
  std::string_view string(uint32_t i) const;

  // Entity access by schema parameter name (cold paths: loading, tools).
  const TypeSpec& type_of(uint32_t entity) const;
  std::string_view type_name(uint32_t entity) const;
  // The value of parameter `name`, or nullptr if the type has none.
  const ValueRecord* value(uint32_t entity, std::string_view name) const;
  // The scene wrote parameter `name` (its value is not the schema default);
  // readers of computed defaults (sphere "zmin", camera "screenwindow") ask this.
  bool given(uint32_t entity, std::string_view name) const;
  float get_float(uint32_t entity, std::string_view name, float fallback = 0) const;
  int32_t get_int(uint32_t entity, std::string_view name, int32_t fallback = 0) const;
  std::string_view get_string(uint32_t entity, std::string_view name) const;
  // Words of a value as floats (point3, rgb, ... are consecutive floats).
  const float* floats(const ValueRecord& v) const;

  // A mesh's arrays (nullptr when absent).
  const float* positions(uint32_t mesh) const;
  const float* normals(uint32_t mesh) const;
  const float* tangents(uint32_t mesh) const;
  const float* uvs(uint32_t mesh) const;
  const uint32_t* indices(uint32_t mesh) const;
  const int32_t* face_indices(uint32_t mesh) const;
  // All of a mesh's arrays as one view (for the PLY writer and the Draco wrapper).
  MeshArrays mesh_arrays(uint32_t mesh) const;

  // Provenance: where a record came from. index is an entity index, or an
  // ObjectRecord's / InstanceRecord's provenance field.
  // "file:line" for messages such as "not supported yet".
  std::string where(uint32_t index) const;
  // The name the scene gave (texture, material, medium, object), or "".
  std::string_view name_of(uint32_t index) const;
  // The file a file-name parameter named (a PLY mesh, an image), or "".
  std::string_view path_of(uint32_t index) const;
  std::string_view provenance_string(uint32_t i) const;

 private:
  // load()'s work once the reader has opened the archive.
  bool load_opened(int threads, std::string* error);
  // Every record view back to empty, as before a load.
  void forget_records();
  // What the records say, checked against the schema and each other.
  bool validate_records(std::string* error);
  // The sections load_opened() decodes once the records are checked: every one left, or with
  // skip_source_texels() the texels sections that an image other than a source names.
  std::vector<bool> wanted_texels() const;
  // Then the meshes' layouts and triangle indices (with up to `threads` threads), and the images.
  bool validate_geometry(int threads, std::string* error);

  ArchiveReader reader_;
  bool skip_sources_ = false;
  std::string path_;
  SceneRecord scene_{};
  const uint32_t* string_offsets_ = nullptr;
  const char* string_data_ = nullptr;
  uint32_t num_strings_ = 0;
  const uint32_t* pstring_offsets_ = nullptr;
  const char* pstring_data_ = nullptr;
  uint32_t num_pstrings_ = 0;
};

}  // namespace pbrta
