// SceneArchive: loading an archive (its sections, with validate_records() and
// validate_geometry(), which are in format/scene_validation.cpp) and reading its records
// (format/scene_archive.h).
#include "format/scene_archive.h"

#include <chrono>
#include <cstddef>
#include <cstring>

#include "format/check_threads.h"
#include "format/zstd_frames.h"

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
  int p = find_param(type_of(entity), name);
  // An archive of an older minor version may lack parameters appended since.
  if (p < 0 || uint32_t(p) >= entities[entity].num_values) return nullptr;
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

namespace {
// A mesh with fewer bytes of triangle indices than this has them read back after the load instead
// of checked as they decode: a bound's bookkeeping in the decoder (~100 bytes, copied per frame and
// per shuffle block) outweighs reading a few hundred bytes again. 50k one-triangle meshes spent
// 10 ms of a 26 ms load building, growing and faulting in their bound lists.
constexpr uint64_t kBoundIndexBytes = 4096;

// Adds the seconds since the previous lap to one of phases' fields; does nothing without phases.
class PhaseClock {
 public:
  explicit PhaseClock(LoadPhases* phases) : phases_(phases) {
    if (phases_ != nullptr) last_ = std::chrono::steady_clock::now();
  }
  void lap(double LoadPhases::*field) {
    if (phases_ == nullptr) return;
    const auto now = std::chrono::steady_clock::now();
    phases_->*field += std::chrono::duration<double>(now - last_).count();
    last_ = now;
  }

 private:
  LoadPhases* phases_;
  std::chrono::steady_clock::time_point last_;
};
}  // namespace

bool SceneArchive::load(const std::string& path, int threads, std::string* error,
                        LoadPhases* phases) {
  path_ = path;
  PhaseClock clock(phases);
  if (!reader_.open(path, error)) return false;
  clock.lap(&LoadPhases::open);
  return load_opened(threads, error, phases);
}

bool SceneArchive::load_memory(std::string_view bytes, std::string_view name, int threads,
                               std::string* error) {
  path_ = std::string(name);
  return reader_.open_memory(bytes, name, error) && load_opened(threads, error, nullptr);
}

bool SceneArchive::load_opened(int threads, std::string* error, LoadPhases* phases) {
  // Every section in one parallel pass. The mesh records are taken first: they say which
  // triangle indices the geometry must keep within which vertex counts, checked as the geometry
  // decodes, so the geometry waits for them. The other records come next, and are checked as soon
  // as they are all in, while the transforms (26 MB for 100k shapes), the geometry and the texels
  // still load (below); the meshes and images are checked last.
  std::vector<uint32_t> all;
  ArchiveReader::BoundPlan plan;
  for (uint32_t i = 0; i < reader_.section_count(); ++i) {
    all.push_back(i);
    const uint32_t kind = reader_.entry(i).kind;
    if (kind == uint32_t(SectionKind::kMeshes)) plan.first.push_back(i);
    if (kind == uint32_t(SectionKind::kGeometry)) plan.gated.push_back(i);
    if (read_by_record_checks(kind)) plan.needs.push_back(i);
  }
  IndexChecks checks;
  plan.plan = [&]() -> const std::vector<ArchiveReader::U32Bound>& {
    plan_index_checks(&checks);
    return checks.bounds;
  };
  // The record checks run on the one thread that calls when_loaded(), while the others decode
  // what is left, if that is enough to keep them busy meanwhile (the checks go at about three
  // times the speed of decoding); else they run after the load, on every thread, as when 100k
  // shapes share two transforms. (Given the load's thread count there, the checks' arena only
  // competes with the loading one: 100k shapes took 10.0 ms instead of 9.7, and 13-19 ms when
  // each check opened an arena of its own.)
  uint64_t records_bytes = 0;
  for (uint32_t i : plan.needs) records_bytes += reader_.entry(i).raw_size;
  // Records worth starting on early. Taking small ones first only delays the large sections that
  // should start first: 2d-mappings' 5 KB of records before its 4 MiB of texels cost 10% (0.8 ->
  // 0.9 ms); 100k shapes' 27 MB first gain 0.3 ms of 10.
  plan.needs_first = records_bytes >= kFrameBlock;
  bool records_checked = false, records_ok = false;
  std::string records_error;
  plan.when_loaded = [&](uint64_t bytes_not_started) {
    if (bytes_not_started < records_bytes / 3) return;
    CheckThreads this_thread(1);
    records_ok = validate_records(&this_thread, &records_error);
    records_checked = true;
  };
  PhaseClock clock(phases);
  if (!reader_.load_sections(threads, all, plan, &checks.first, error)) {
    forget_records();  // the checks may have pointed them at sections now unloaded
    return false;
  }
  clock.lap(&LoadPhases::sections);
  CheckThreads check_threads(threads);
  if (!records_checked) records_ok = validate_records(&check_threads, &records_error);
  if (!records_ok) {
    *error = records_error;
    return false;
  }
  const bool ok = validate_geometry(&check_threads, checks, error);
  clock.lap(&LoadPhases::validate);
  return ok;
}

bool SceneArchive::read_by_record_checks(uint32_t kind) {
  return kind != uint32_t(SectionKind::kTransforms) && kind != uint32_t(SectionKind::kGeometry) &&
         kind != uint32_t(SectionKind::kTexels);
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

// From the mesh records as they are, unvalidated, on a loading thread while other sections load:
// a mesh whose indices do not lie on 4-byte boundaries inside a geometry section gets no bound,
// and validate_geometry() rejects its layout before it would look at its indices.
void SceneArchive::plan_index_checks(IndexChecks* checks) const {
  const int s = reader_.find_section(SectionKind::kMeshes);
  if (s < 0) return;
  const uint8_t* data = reader_.section_data(uint32_t(s));
  const uint64_t count = reader_.entry(uint32_t(s)).count;
  if (data == nullptr || reader_.section_size(uint32_t(s)) != count * sizeof(MeshRecord)) return;
  for (uint32_t i = 0; i < count; ++i) {
    // The triangle count alone first: most meshes of a scene of many are small (50k copies of
    // the whole record took 90 µs).
    const uint8_t* record = data + uint64_t(i) * sizeof(MeshRecord);
    uint32_t triangles;
    std::memcpy(&triangles, record + offsetof(MeshRecord, num_triangles), 4);
    const uint64_t bytes = uint64_t(triangles) * 12;
    if (bytes < kBoundIndexBytes) continue;
    MeshRecord m;
    std::memcpy(&m, record, sizeof m);
    if (m.section >= reader_.section_count()) continue;
    const SectionEntry& e = reader_.entry(m.section);
    if (e.kind != uint32_t(SectionKind::kGeometry) || reader_.skipped(m.section) ||
        m.indices % 4 != 0 || m.indices > e.raw_size || bytes > e.raw_size - m.indices)
      continue;
    checks->bounds.push_back({m.section, m.indices, m.indices + bytes, m.num_vertices});
    checks->mesh.push_back(i);
  }
}

}  // namespace pbrta
