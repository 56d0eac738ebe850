// libFuzzer target for the scene archive's record validation (format/scene_archive.h), the check
// that stands between an archive's bytes and the renderer. The input is resealed
// (archive_reseal.h) so that mutated records get past the checksums, then loaded through
// SceneArchive::load_memory, the path pbrtc --verify and pbrtrun take. When the load succeeds,
// every reference a renderer would follow is checked again here, written independently of
// validate(): an index out of range, a mesh array outside its section or a triangle index past
// the vertex count traps, as would any crash, sanitizer report or hang.
//
// The sections of a loaded archive sit packed in one buffer, so reading past one section's end
// lands in the next, where AddressSanitizer sees nothing: hence the explicit checks.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "archive_reseal.h"
#include "format/archive.h"
#include "format/isolated_jobs.h"
#include "format/scene_archive.h"
#include "format/schema.h"
#include "format/texel_format.h"

namespace {

using namespace pbrta;

void require(bool ok) {
  if (!ok) __builtin_trap();
}
// Below n, or kNoIndex where the record allows none.
bool in_range(uint32_t i, uint32_t n, bool none_ok) {
  return i < n || (none_ok && i == kNoIndex);
}

volatile uint32_t sink;
volatile float float_sink;

bool entity_is(const SceneArchive& a, uint32_t e, Category c) {
  return e < a.entities.size && a.entities[e].category == uint8_t(c);
}

void check_entities(const SceneArchive& a) {
  for (uint32_t e = 0; e < a.entities.size; ++e) {
    const EntityRecord& r = a.entities[e];
    require(r.category < uint8_t(Category::kCount));
    const TypeSpec& t = a.type_of(e);
    sink = uint32_t(a.type_name(e).size());
    const uint32_t known = r.num_values < t.num_params ? r.num_values : t.num_params;
    require(uint64_t(r.first_value) + r.num_values <= a.values.size);
    for (uint32_t p = 0; p < known; ++p) {
      const ParamSpec& ps = t.params[p];
      const ValueRecord* v = &a.values[r.first_value + p];
      const uint64_t words = uint64_t(v->count) * uint64_t(kind_width(ps.kind));
      require(uint64_t(v->offset) + words <= a.words.size);
      for (uint64_t k = 0; k < words; ++k) sink = a.words[uint32_t(v->offset + k)];
      if (ps.kind == Kind::kString)
        for (uint32_t k = 0; k < v->count; ++k) require(a.words[v->offset + k] < a.num_strings());
      require(in_range(v->texture, a.textures.size, true));
    }
    sink = uint32_t(a.where(e).size() + a.name_of(e).size() + a.path_of(e).size());
  }
}

void check_records(const SceneArchive& a) {
  const SceneRecord& s = a.scene();
  require(entity_is(a, s.camera, Category::kCamera) && entity_is(a, s.film, Category::kFilm) &&
          entity_is(a, s.filter, Category::kFilter) &&
          entity_is(a, s.sampler, Category::kSampler) &&
          entity_is(a, s.integrator, Category::kIntegrator) &&
          entity_is(a, s.accelerator, Category::kAccelerator));
  require(in_range(s.camera_transform, a.transforms.size, false));
  require(in_range(s.camera_medium, a.media.size, true));
  for (const TextureRecord& t : a.textures) {
    require(entity_is(a, t.entity, Category::kFloatTexture) ||
            entity_is(a, t.entity, Category::kSpectrumTexture));
    require(in_range(t.transform, a.transforms.size, false));
    require(in_range(t.image, a.images.size, true));
  }
  for (const MaterialRecord& m : a.materials) {
    require(entity_is(a, m.entity, Category::kMaterial));
    require(in_range(m.mix[0], a.materials.size, true) &&
            in_range(m.mix[1], a.materials.size, true));
  }
  for (const MediumRecord& m : a.media) {
    require(entity_is(a, m.entity, Category::kMedium));
    require(in_range(m.transform, a.transforms.size, false));
  }
  for (const LightRecord& l : a.lights) {
    require(entity_is(a, l.entity, Category::kLight));
    require(in_range(l.transform, a.transforms.size, false));
    require(in_range(l.medium, a.media.size, true) && in_range(l.image, a.images.size, true));
  }
  for (uint32_t e : a.area_lights) require(entity_is(a, e, Category::kAreaLight));
  for (const ShapeRecord& s : a.shapes) {
    require(entity_is(a, s.entity, Category::kShape));
    require(in_range(s.mesh, a.meshes.size, true));
    require(in_range(s.material, a.materials.size, false));
    require(in_range(s.area_light, a.area_lights.size, true));
    require(in_range(s.inside_medium, a.media.size, true) &&
            in_range(s.outside_medium, a.media.size, true));
    require(in_range(s.transform, a.transforms.size, false));
    require(in_range(s.object, a.objects.size, true));
  }
  for (const ObjectRecord& o : a.objects) {
    require(uint64_t(o.first_shape) + o.num_shapes <= a.object_shapes.size);
    sink = uint32_t(a.where(o.provenance).size());
  }
  for (uint32_t shape : a.object_shapes) require(shape < a.shapes.size);
  for (const InstanceRecord& in : a.instances) {
    require(in_range(in.object, a.objects.size, false));
    require(in_range(in.transform, a.transforms.size, false));
  }
}

// [offset, offset + bytes) lies inside the section.
bool inside(const SceneArchive& a, uint32_t section, uint64_t offset, uint64_t bytes) {
  const uint64_t size = a.reader().section_size(section);
  return offset <= size && bytes <= size - offset;
}

void check_meshes(const SceneArchive& a) {
  for (uint32_t m = 0; m < a.meshes.size; ++m) {
    const MeshRecord& r = a.meshes[m];
    require(r.section < a.reader().section_count());
    const uint64_t nv = r.num_vertices, nt = r.num_triangles;
    require(inside(a, r.section, r.positions, nv * 12) && inside(a, r.section, r.indices, nt * 12));
    if (r.flags & kMeshNormals) require(inside(a, r.section, r.normals, nv * 12));
    if (r.flags & kMeshTangents) require(inside(a, r.section, r.tangents, nv * 12));
    if (r.flags & kMeshUV) require(inside(a, r.section, r.uv, nv * 8));
    if (r.flags & kMeshFaceIndices) require(inside(a, r.section, r.face_indices, nt * 4));
    require(in_range(r.source_shape, a.shapes.size, true));
    const MeshArrays v = a.mesh_arrays(m);
    for (uint64_t k = 0; k < nt * 3; ++k) {
      require(v.indices[k] < r.num_vertices);
      float_sink = v.positions[3 * uint64_t(v.indices[k])];
    }
  }
}

void check_images(const SceneArchive& a) {
  for (const ImageRecord& im : a.images) {
    require(im.section < a.reader().section_count());
    require(im.levels >= 1 && im.levels <= 32 && (im.channels == 1 || im.channels == 3));
    require(in_range(im.distribution, a.images.size, true) &&
            in_range(im.source_image, a.images.size, true));
    const uint8_t* texels = a.reader().section_data(im.section);
    uint64_t at = im.offset;
    for (uint32_t l = 0; l < im.levels; ++l) {
      const uint64_t w = im.width >> l ? im.width >> l : 1, h = im.height >> l ? im.height >> l : 1;
      const uint64_t bytes = w * h * im.channels * texel_bytes(im.format);
      require(bytes > 0 && inside(a, im.section, at, bytes));
      sink = texels[at] + texels[at + bytes - 1];
      at = (at + bytes + 15) / 16 * 16;
    }
  }
}

void try_load(std::string_view bytes) {
  SceneArchive a;
  std::string error;
  if (!a.load_memory(bytes, "fuzz.pbrta", 1, &error)) {
    require(error.compare(0, 10, "fuzz.pbrta") == 0);  // every error names the file
    return;
  }
  check_entities(a);
  check_records(a);
  check_meshes(a);
  check_images(a);
}

}  // namespace

// Draco runs in this process, not in a budgeted child (format/isolated_jobs.h): libFuzzer's
// coverage counters and crash reports live here, and its -timeout stands in for the budget.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  pbrta::set_isolation_enabled(false);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<uint8_t> copy(data, data + size);
  fuzz_support::reseal(&copy);
  try_load(std::string_view(reinterpret_cast<const char*>(copy.data()), copy.size()));
  return 0;
}
