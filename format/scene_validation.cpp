// SceneArchive::validate_records and validate_geometry: every record of a loaded archive checked
// against the schema and against every other record it names, before anything reads it
// (format/scene_archive.h).
// Loading and the accessors are in format/scene_archive.cpp.
#include "format/scene_archive.h"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstring>
#include <string_view>
#include <type_traits>
#include <vector>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "format/archive_names.h"
#include "format/bssrdf_table.h"
#include "format/draco_codec.h"
#include "format/entity_rules.h"
#include "format/fourier_table.h"
#include "format/plain_values.h"
#include "format/texel_format.h"

namespace pbrta {

namespace {

// Collects the first failure with its section; checks read as sentences.
class Checker {
 public:
  Checker(const std::string& path, const ArchiveReader& r) : path_(path), r_(r) {}

  // Sets the section later failures are reported against.
  void in(int section) { section_ = section; }

  bool fail(const std::string& what) {
    if (!failed_) {
      failed_ = true;
      message_ = path_ + ": ";
      if (section_ >= 0)
        message_ += "section '" +
                    std::string(section_kind_name(SectionKind(r_.entry(uint32_t(section_)).kind))) +
                    "' (#" + std::to_string(section_) + "): ";
      message_ += what;
    }
    return false;
  }
  // index < count, or NONE when allowed. Inline: the record loops call it ~10 times per shape.
  bool index(uint32_t i, uint32_t count, const char* record, uint32_t at, const char* field,
             const char* array, bool none_ok) {
    return i < count || (i == kNoIndex && none_ok) ||
           index_failed(i, count, record, at, field, array);
  }
  [[gnu::noinline]] bool index_failed(uint32_t i, uint32_t count, const char* record, uint32_t at,
                                      const char* field, const char* array) {
    return fail(
        std::string(record) + " " + std::to_string(at) + ": " + field + " " +
        (i == kNoIndex ? std::string("is missing") : std::to_string(i)) +
        (i == kNoIndex ? "" : " out of range (" + std::to_string(count) + " " + array + ")"));
  }
  // fail() of the pieces (strings and numbers) joined: the hot checks call this, so that building
  // a message costs them nothing but a call where a check fails.
  template <class... Parts>
  [[gnu::cold, gnu::noinline]] bool fail_with(const Parts&... parts) {
    std::string s;
    (append(&s, parts), ...);
    return fail(s);
  }
  bool failed() const { return failed_; }
  // True when nothing failed; otherwise false, with the message in *error.
  bool done(std::string* error) const { return !failed_ || (*error = message_, false); }
  const std::string& message() const { return message_; }

 private:
  const std::string& path_;
  const ArchiveReader& r_;
  static void append(std::string* s, std::string_view text) { *s += text; }
  template <class T, class = std::enable_if_t<std::is_integral_v<T>>>
  static void append(std::string* s, T v) {
    *s += std::to_string(uint64_t(v));
  }

  int section_ = -1;
  bool failed_ = false;
  std::string message_;
};

// From this many bytes of triangle indices on, the meshes are checked on every thread.
constexpr uint64_t kParallelIndexBytes = uint64_t{8} << 20;

// The record flags this reader knows; any other bit refuses the record.
constexpr uint32_t kKnownShapeFlags = kShapeReverseOrientation | kShapeSwapsHandedness;
constexpr uint32_t kKnownMeshFlags = kMeshNormals | kMeshTangents | kMeshUV | kMeshFaceIndices;

// The index of the first of n values that is >= limit, or n (a mesh's first bad triangle index).
// Branch-free within blocks of 1024 so the compiler vectorizes it (with plain SSE2 too, which has
// no unsigned compare): every index of every mesh is read here.
inline uint64_t first_at_or_above(const uint32_t* v, uint64_t n, uint32_t limit) {
  if (n <= 12) {  // a few triangles (the teapot's 2292 one-triangle meshes): no block loop
    for (uint64_t k = 0; k < n; ++k)
      if (v[k] >= limit) return k;
    return n;
  }
  constexpr uint64_t kBlock = 1024;
  for (uint64_t at = 0; at < n; at += kBlock) {
    const uint64_t end = std::min(n, at + kBlock);
    uint32_t any = 0;
    for (uint64_t k = at; k < end; ++k) any |= static_cast<uint32_t>(v[k] >= limit);
    if (any != 0)
      for (uint64_t k = at; k < end; ++k)
        if (v[k] >= limit) return k;
  }
  return n;
}

// What is wrong with one of a mesh record's arrays, and its message.
enum ArrayFault { kArrayOk, kArrayFlagClear, kArrayUnaligned, kArrayOutside };
[[gnu::cold, gnu::noinline]] bool array_failed(Checker& c, ArrayFault fault, uint32_t mesh,
                                               const char* name, uint64_t offset, uint64_t bytes,
                                               uint64_t size) {
  if (fault == kArrayFlagClear)
    return c.fail_with("mesh ", mesh, ": ", name, " offset set but flag clear");
  if (fault == kArrayUnaligned)
    return c.fail_with("mesh ", mesh, ": ", name, " offset is not 16-byte aligned");
  return c.fail_with("mesh ", mesh, ": ", name, " (", bytes, " bytes at ", offset,
                     ") lies outside its section (", size, " bytes)");
}

// A string table's n + 1 offsets (n >= 1) over data_size bytes of characters, as ARCHIVE.md
// section 6 has both tables (strings, provenance): from 0, never decreasing, ending at the
// data's end, and string 0 empty.
bool check_string_offsets(const uint32_t* offsets, uint32_t n, uint64_t data_size, Checker& c) {
  if (offsets[0] != 0) return c.fail("first string offset is not 0");
  for (uint32_t i = 0; i < n; ++i)
    if (offsets[i + 1] < offsets[i])
      return c.fail("string offsets decrease at string " + std::to_string(i));
  if (offsets[n] != data_size)
    return c.fail("string data is " + std::to_string(data_size) + " bytes, offsets say " +
                  std::to_string(offsets[n]));
  return offsets[1] == 0 || c.fail("string 0 is not empty");
}

// The first record i in [0, n) that check(i, c) refuses, or n; 0, checking nothing, when c has
// already failed. The checks of one record kind, in record order, so that the error is always
// the first bad record's.
template <class Check>
uint32_t first_failure(uint32_t n, Checker& c, Check check) {
  if (c.failed()) return 0;
  for (uint32_t i = 0; i < n; ++i)
    if (!check(i, c)) return i;
  return n;
}

}  // namespace

bool SceneArchive::validate_records(std::string* error) {
  Checker c(path_, reader_);
  const ArchiveReader& r = reader_;
  // Which section holds each kind (once, except geometry and texels).
  int where_kind[uint32_t(SectionKind::kCount)];
  for (int& w : where_kind) w = -1;
  for (uint32_t i = 0; i < r.section_count(); ++i) {
    uint32_t k = r.entry(i).kind;
    if (k == 0 || k >= uint32_t(SectionKind::kCount)) continue;  // newer minor: ignored
    if (k == uint32_t(SectionKind::kGeometry) || k == uint32_t(SectionKind::kTexels)) continue;
    if (where_kind[k] >= 0) {
      c.in(int(i));
      c.fail("appears twice (first as #" + std::to_string(where_kind[k]) + ")");
      return c.done(error);
    }
    where_kind[k] = int(i);
  }
  auto sec = [&](SectionKind k) { return where_kind[uint32_t(k)]; };
  if (sec(SectionKind::kScene) < 0 || sec(SectionKind::kStrings) < 0) {
    *error = path_ + ": no " + std::string(sec(SectionKind::kScene) < 0 ? "scene" : "strings") +
             " section";
    return false;
  }
  // The scene record.
  c.in(sec(SectionKind::kScene));
  {
    uint32_t s = uint32_t(sec(SectionKind::kScene));
    if (r.section_size(s) != sizeof(SceneRecord) || r.entry(s).count != 1) {
      c.fail("size " + std::to_string(r.section_size(s)) + " is not one SceneRecord (" +
             std::to_string(sizeof(SceneRecord)) + " bytes)");
      return c.done(error);
    }
    std::memcpy(&scene_, r.section_data(s), sizeof scene_);
    for (uint32_t v : scene_.reserved)
      if (v != 0) {
        c.fail("reserved field is not zero");
        return c.done(error);
      }
  }
  // Strings.
  {
    uint32_t s = uint32_t(sec(SectionKind::kStrings));
    c.in(int(s));
    const uint8_t* d = r.section_data(s);
    uint64_t size = r.section_size(s);
    uint32_t n = 0;
    if (size >= 4) std::memcpy(&n, d, 4);
    uint64_t head = 4 + (uint64_t(n) + 1) * 4;
    if (size < 4 || head > size) {
      c.fail("string table header does not fit (" + std::to_string(size) + " bytes)");
    } else if (n != scene_.num_strings || n != r.entry(s).count || n == 0) {
      c.fail("string count " + std::to_string(n) + " does not match the scene's " +
             std::to_string(scene_.num_strings));
    } else {
      // Offsets must be aligned in memory to read them as uint32: they start
      // at byte 4 of a 16-byte aligned section.
      string_offsets_ = reinterpret_cast<const uint32_t*>(d + 4);
      string_data_ = reinterpret_cast<const char*>(d + head);
      check_string_offsets(string_offsets_, n, size - head, c);
      num_strings_ = n;
    }
    if (c.failed()) return c.done(error);
  }
  // Typed arrays: size and count agree with the scene record.
  auto array = [&](SectionKind k, auto* span, uint32_t expected, bool required) -> bool {
    using T = std::remove_const_t<std::remove_pointer_t<decltype(span->data)>>;
    int s = sec(k);
    if (s < 0) {
      if (expected != 0 || required) {
        c.in(-1);
        return c.fail("no " + std::string(section_kind_name(k)) + " section, but the scene has " +
                      std::to_string(expected) + " of them");
      }
      span->data = nullptr;
      span->size = 0;
      return true;
    }
    c.in(s);
    uint32_t count = r.entry(uint32_t(s)).count;
    if (count != expected)
      return c.fail("holds " + std::to_string(count) + " records, the scene says " +
                    std::to_string(expected));
    if (r.section_size(uint32_t(s)) != uint64_t(count) * sizeof(T))
      return c.fail("size " + std::to_string(r.section_size(uint32_t(s))) + " is not " +
                    std::to_string(count) + " records of " + std::to_string(sizeof(T)) + " bytes");
    span->data = reinterpret_cast<const T*>(r.section_data(uint32_t(s)));
    span->size = count;
    return true;
  };
  const SceneRecord& sr = scene_;
  bool ok = array(SectionKind::kEntities, &entities, sr.num_entities, true) &&
            array(SectionKind::kValues, &values, sr.num_values, false) &&
            array(SectionKind::kWords, &words, sr.num_words, false) &&
            array(SectionKind::kTransforms, &transforms, sr.num_transforms, true) &&
            array(SectionKind::kTextures, &textures, sr.num_textures, false) &&
            array(SectionKind::kMaterials, &materials, sr.num_materials, false) &&
            array(SectionKind::kMedia, &media, sr.num_media, false) &&
            array(SectionKind::kLights, &lights, sr.num_lights, false) &&
            array(SectionKind::kAreaLights, &area_lights, sr.num_area_lights, false) &&
            array(SectionKind::kShapes, &shapes, sr.num_shapes, false) &&
            array(SectionKind::kObjects, &objects, sr.num_objects, false) &&
            array(SectionKind::kObjectShapes, &object_shapes, sr.num_object_shapes, false) &&
            array(SectionKind::kInstances, &instances, sr.num_instances, false) &&
            array(SectionKind::kMeshes, &meshes, sr.num_meshes, false) &&
            array(SectionKind::kImages, &images, sr.num_images, false);
  if (ok) {
    // Provenance: u32 records, u32 strings, records, string offsets, characters.
    int s = sec(SectionKind::kProvenance);
    uint32_t expected = sr.num_entities + sr.num_objects + sr.num_instances;
    if (s < 0) {
      c.in(-1);
      c.fail("no provenance section");
    } else {
      c.in(s);
      const uint8_t* d = r.section_data(uint32_t(s));
      uint64_t size = r.section_size(uint32_t(s));
      uint32_t nrec = 0, nstr = 0;
      if (size >= 8) {
        std::memcpy(&nrec, d, 4);
        std::memcpy(&nstr, d + 4, 4);
      }
      uint64_t records_end = 8 + uint64_t(nrec) * sizeof(ProvenanceRecord);
      uint64_t head = records_end + (uint64_t(nstr) + 1) * 4;
      if (size < 8 || head > size) {
        c.fail("provenance tables do not fit (" + std::to_string(size) + " bytes)");
      } else if (nrec != r.entry(uint32_t(s)).count || nrec < expected || nstr == 0) {
        c.fail("has " + std::to_string(nrec) + " records, needs " + std::to_string(expected));
      } else {
        provenance.data = reinterpret_cast<const ProvenanceRecord*>(d + 8);
        provenance.size = nrec;
        pstring_offsets_ = reinterpret_cast<const uint32_t*>(d + records_end);
        pstring_data_ = reinterpret_cast<const char*>(d + head);
        num_pstrings_ = nstr;
        check_string_offsets(pstring_offsets_, nstr, size - head, c);
        first_failure(nrec, c, [&](uint32_t i, Checker& c) {
          const ProvenanceRecord& p = provenance[i];
          return (p.file < nstr && p.name < nstr && p.path < nstr) ||
                 c.fail("record " + std::to_string(i) + ": string out of range (" +
                        std::to_string(nstr) + " strings)");
        });
      }
    }
  }
  if (c.failed()) return c.done(error);

  // Textures first: an entity's texture bindings, checked with its values, read them.
  c.in(sec(SectionKind::kTextures));
  first_failure(textures.size, c, [&](uint32_t i, Checker& c) {
    const TextureRecord& t = textures[i];
    if (!c.index(t.entity, entities.size, "texture", i, "entity", "entities", false)) return false;
    uint8_t cat = entities[t.entity].category;
    if (cat != uint8_t(Category::kFloatTexture) && cat != uint8_t(Category::kSpectrumTexture))
      return c.fail("texture " + std::to_string(i) + ": entity is not a texture");
    return (t.reserved == 0 ||
            c.fail("texture " + std::to_string(i) + ": reserved field is not zero")) &&
           c.index(t.transform, transforms.size, "texture", i, "transform", "transforms", false) &&
           c.index(t.image, images.size, "texture", i, "image", "images", true);
  });
  // Entities and their values: one entity's checks, false (with the reason in c) on failure.
  // The schema's specs and each type's count rule are looked up once, not per entity: the
  // loop runs over every entity of the scene (2304 on the teapot, one per triangle).
  const uint16_t minor = r.header().minor;
  const CategorySpec* specs[uint32_t(Category::kCount)];
  for (uint32_t k = 0; k < uint32_t(Category::kCount); ++k) specs[k] = &category_spec(Category(k));
  struct TypeChecks {
    CountRule count_rule;
    std::vector<PlainLanes> lanes;
  };
  static const std::vector<std::vector<TypeChecks>> type_checks = [] {
    std::vector<std::vector<TypeChecks>> by_category(static_cast<size_t>(Category::kCount));
    for (uint32_t k = 0; k < uint32_t(Category::kCount); ++k)
      for (uint32_t t = 0; t < category_spec(Category(k)).num_types; ++t)
        by_category[k].push_back(
            {count_rule_of(Category(k), t), plain_lanes(category_spec(Category(k)).types[t])});
    return by_category;
  }();
  const bool filter = plain_filter_available();
  const int values_section = sec(SectionKind::kValues);
  const int entities_section = sec(SectionKind::kEntities);
  auto check_entity = [&](uint32_t i, Checker & c) __attribute__((always_inline))->bool {
    const EntityRecord& e = entities[i];
    const char* at = "entity ";
    if (e.category >= uint8_t(Category::kCount))
      return c.fail_with(at, i, ": category ", e.category, " unknown");
    const CategorySpec& cs = *specs[e.category];
    if (e.type >= cs.num_types)
      return c.fail_with(at, i, ": ", cs.name, " type ", e.type, " unknown (", cs.num_types,
                         " types)");
    const TypeSpec& ts = cs.types[e.type];
    if (e.reserved0 || e.reserved1) return c.fail_with(at, i, ": reserved field is not zero");
    // Parameters are only ever appended to a type (a minor change): a newer minor may have
    // more than this reader knows, which it ignores.
    if (minor > kMinorVersion ? e.num_values < ts.num_params : e.num_values != ts.num_params)
      return c.fail_with(at, i, ": ", ts.name, " has ", ts.num_params, " parameters, the record ",
                         e.num_values, " (archive version ", r.header().major, ".", minor, ")");
    if (uint64_t(e.first_value) + e.num_values > values.size)
      return c.fail_with(at, i, ": values ", e.first_value, "+", e.num_values, " out of range (",
                         values.size, " values)");
    const ValueRecord* vs = values.data + e.first_value;
    const uint64_t num_words = words.size;
    const TypeChecks& checks = type_checks[e.category][e.type];
    const bool plain = filter && plain_values(vs, checks.lanes.data(), ts.num_params, num_words);
    for (uint32_t p = 0; p < (plain ? 0 : ts.num_params); ++p) {
      const ValueRecord& v = vs[p];
      const ParamSpec& ps = ts.params[p];
      if (v.flags & ~uint32_t(kValueGiven))
        return c.fail_with(at, i, ": ", ts.name, " \"", ps.name, "\": unknown value flags");
      if (uint64_t(v.offset) + uint64_t(v.count) * uint64_t(kind_width(ps.kind)) > num_words)
        return c.fail_with(at, i, ": ", ts.name, " \"", ps.name, "\": words out of range");
      if (ps.arity > 0 && v.count != 0 && v.count != ps.arity)
        return c.fail_with(at, i, ": ", ts.name, " \"", ps.name, "\": ", v.count,
                           " values, the schema says ", ps.arity);
      if (v.texture != kNoIndex) {
        if (ps.kind != Kind::kFloatTex && ps.kind != Kind::kSpectrumTex)
          return c.fail_with(at, i, ": ", ts.name, " \"", ps.name,
                             "\": a texture on a parameter that takes none");
        if (v.texture >= textures.size)
          return c.fail_with(at, i, ": ", ts.name, " \"", ps.name, "\": texture ", v.texture,
                             " out of range (", textures.size, " textures)");
        // The binding must match the parameter's class (the textures were checked above, so
        // their entities are in range). A binding is a value's fault.
        const Category want =
            ps.kind == Kind::kFloatTex ? Category::kFloatTexture : Category::kSpectrumTexture;
        if (entities[textures[v.texture].entity].category != uint8_t(want)) {
          c.in(values_section);
          c.fail_with(at, i, " \"", ps.name, "\": texture ", v.texture, " is not a ",
                      category_name(want));
          c.in(entities_section);
          return false;
        }
      }
      if (ps.kind == Kind::kString)
        for (uint32_t k = 0; k < v.count; ++k)
          if (words[v.offset + k] >= num_strings_)
            return c.fail_with(at, i, ": ", ts.name, " \"", ps.name, "\": string ",
                               words[v.offset + k], " out of range");
    }
    // Counts tied to other parameters (format/entity_rules.h), now that every value is sound.
    const CountRule count_rule = checks.count_rule;
    if (count_rule == CountRule::kNone) return true;
    RuleViolation rule;
    if (count_rule == CountRule::kCurve) {
      CurveCounts cc;
      cc.degree = get_int(i, "degree", 3);
      cc.basis = get_string(i, "basis");
      const ValueRecord* P = value(i, "P");
      const ValueRecord* N = value(i, "N");
      cc.control_points = P ? P->count : 0;
      cc.type = get_string(i, "type");
      cc.normals_given = given(i, "N");
      cc.normals = N ? N->count : 0;
      if (!check_curve_rules(cc, &rule)) return c.fail_with(at, i, ": ", rule.message);
    } else if (count_rule == CountRule::kDensity) {
      const ValueRecord* d = value(i, "density");
      if (!check_density_rule(get_int(i, "nx", 1), get_int(i, "ny", 1), get_int(i, "nz", 1),
                              d ? d->count : 0, &rule))
        return c.fail_with(at, i, ": ", rule.message);
    } else if (count_rule == CountRule::kFourierTable) {
      // The renderer indexes the table (derived from the material's file) without checks, so its
      // arrays must agree. One without a table (no file given) the renderer reports.
      const ValueRecord* mu = value(i, "bsdfmu");
      FourierTableView t;
      std::string why;
      if (mu != nullptr && mu->count != 0 &&
          (!fourier_table_of(*this, i, &t, &why) || !check_fourier_table(t, &why)))
        return c.fail_with(at, i, ": fourier table ", why);
    } else if (count_rule == CountRule::kBssrdfTable && minor >= 1) {
      // 2.0 archives have no table (their subsurface materials cannot be rendered); from 2.1 on
      // pbrtc always writes one, and the renderer interpolates it without checks.
      BssrdfTableView t;
      std::string why;
      if (!bssrdf_table_of(*this, i, &t, &why) || !check_bssrdf_table(t, &why))
        return c.fail_with(at, i, ": BSSRDF table ", why);
    }
    return true;
  };
  c.in(entities_section);
  first_failure(entities.size, c, check_entity);
  // Render options point at entities of the right category.
  c.in(sec(SectionKind::kScene));
  auto entity_of = [&](Checker& c, uint32_t e, Category cat, const char* record, uint32_t at,
                       const char* field) {
    if (e < entities.size && entities[e].category == uint8_t(cat)) return true;
    if (!c.index(e, entities.size, record, at, field, "entities", false)) return false;
    return c.fail_with(record, " ", at, ": ", field, " entity ", e, " is a ",
                       category_name(Category(entities[e].category)), ", not a ",
                       category_name(cat));
  };
  if (!c.failed()) {
    entity_of(c, sr.camera, Category::kCamera, "scene", 0, "camera") &&
        entity_of(c, sr.film, Category::kFilm, "scene", 0, "film") &&
        entity_of(c, sr.filter, Category::kFilter, "scene", 0, "filter") &&
        entity_of(c, sr.sampler, Category::kSampler, "scene", 0, "sampler") &&
        entity_of(c, sr.integrator, Category::kIntegrator, "scene", 0, "integrator") &&
        entity_of(c, sr.accelerator, Category::kAccelerator, "scene", 0, "accelerator") &&
        c.index(sr.camera_transform, transforms.size, "scene", 0, "camera transform", "transforms",
                false) &&
        c.index(sr.camera_medium, media.size, "scene", 0, "camera medium", "media", true);
  }
  c.in(sec(SectionKind::kMaterials));
  auto check_material = [&](uint32_t i, Checker& c) {
    const MaterialRecord& m = materials[i];
    return entity_of(c, m.entity, Category::kMaterial, "material", i, "entity") &&
           (m.reserved == 0 ||
            c.fail("material " + std::to_string(i) + ": reserved field is not zero")) &&
           c.index(m.mix[0], materials.size, "material", i, "mix material 1", "materials", true) &&
           c.index(m.mix[1], materials.size, "material", i, "mix material 2", "materials", true);
  };
  first_failure(materials.size, c, check_material);
  c.in(sec(SectionKind::kMedia));
  first_failure(media.size, c, [&](uint32_t i, Checker& c) {
    const MediumRecord& m = media[i];
    return entity_of(c, m.entity, Category::kMedium, "medium", i, "entity") &&
           c.index(m.transform, transforms.size, "medium", i, "transform", "transforms", false) &&
           ((m.reserved[0] | m.reserved[1]) == 0 ||
            c.fail("medium " + std::to_string(i) + ": reserved field is not zero"));
  });
  c.in(sec(SectionKind::kLights));
  first_failure(lights.size, c, [&](uint32_t i, Checker& c) {
    const LightRecord& l = lights[i];
    return entity_of(c, l.entity, Category::kLight, "light", i, "entity") &&
           c.index(l.transform, transforms.size, "light", i, "transform", "transforms", false) &&
           c.index(l.medium, media.size, "light", i, "medium", "media", true) &&
           c.index(l.image, images.size, "light", i, "image", "images", true);
  });
  c.in(sec(SectionKind::kAreaLights));
  first_failure(area_lights.size, c, [&](uint32_t i, Checker& c) {
    return entity_of(c, area_lights[i], Category::kAreaLight, "area light", i, "entity");
  });
  c.in(sec(SectionKind::kShapes));
  auto check_shape = [&](uint32_t i, Checker& c) {
    const ShapeRecord& s = shapes[i];
    return entity_of(c, s.entity, Category::kShape, "shape", i, "entity") &&
           c.index(s.mesh, meshes.size, "shape", i, "mesh", "meshes", true) &&
           c.index(s.material, materials.size, "shape", i, "material", "materials", false) &&
           c.index(s.area_light, area_lights.size, "shape", i, "area light", "area lights", true) &&
           c.index(s.inside_medium, media.size, "shape", i, "inside medium", "media", true) &&
           c.index(s.outside_medium, media.size, "shape", i, "outside medium", "media", true) &&
           c.index(s.transform, transforms.size, "shape", i, "transform", "transforms", false) &&
           c.index(s.object, objects.size, "shape", i, "object", "objects", true) &&
           ((s.flags & ~kKnownShapeFlags) == 0 ||
            c.fail("shape " + std::to_string(i) + ": unknown flags")) &&
           (s.reserved == 0 ||
            c.fail("shape " + std::to_string(i) + ": reserved field is not zero"));
  };
  first_failure(shapes.size, c, check_shape);
  c.in(sec(SectionKind::kObjects));
  first_failure(objects.size, c, [&](uint32_t i, Checker& c) {
    const ObjectRecord& o = objects[i];
    return (o.reserved == 0 ||
            c.fail("object " + std::to_string(i) + ": reserved field is not zero")) &&
           c.index(o.provenance, provenance.size, "object", i, "provenance", "records", false) &&
           (uint64_t(o.first_shape) + o.num_shapes <= object_shapes.size ||
            c.fail("object " + std::to_string(i) + ": shapes out of range"));
  });
  c.in(sec(SectionKind::kObjectShapes));
  first_failure(object_shapes.size, c, [&](uint32_t i, Checker& c) {
    return c.index(object_shapes[i], shapes.size, "entry", i, "shape", "shapes", false);
  });
  c.in(sec(SectionKind::kInstances));
  first_failure(instances.size, c, [&](uint32_t i, Checker& c) {
    const InstanceRecord& in = instances[i];
    return c.index(in.object, objects.size, "instance", i, "object", "objects", false) &&
           c.index(in.transform, transforms.size, "instance", i, "transform", "transforms",
                   false) &&
           c.index(in.provenance, provenance.size, "instance", i, "provenance", "records", false) &&
           (in.reserved == 0 ||
            c.fail("instance " + std::to_string(i) + ": reserved field is not zero"));
  });
  return c.done(error);
}

bool SceneArchive::validate_geometry(int threads, std::string* error) {
  Checker c(path_, reader_);
  const ArchiveReader& r = reader_;
  auto sec = [&](SectionKind k) { return r.find_section(k); };  // each once: validate_records()
  c.in(sec(SectionKind::kMeshes));
  // A mesh's layout, and then its triangle indices against its vertex count (the largest part of
  // validation: every index of every mesh is read).
  // Inlined (GCC leaves these lambdas as calls): teapot-like scenes have a mesh per triangle.
  auto check_mesh = [&](uint32_t i, Checker & c) __attribute__((always_inline)) {
    const MeshRecord& m = meshes[i];
    const char* at = "mesh ";
    if (m.section >= r.section_count() ||
        r.entry(m.section).kind != uint32_t(SectionKind::kGeometry))
      return c.fail_with(at, i, ": section ", m.section, " is not a geometry section");
    if (m.flags & ~kKnownMeshFlags) return c.fail_with(at, i, ": unknown flags");
    if (r.entry(m.section).codec == uint32_t(Codec::kDraco)) {
      // A Draco section decodes to exactly one mesh's layout: the record must describe it.
      MeshRecord expect = m;
      if ((m.flags & kMeshTangents) || single_mesh_layout(&expect) != r.section_size(m.section) ||
          std::memcmp(&expect, &m, sizeof m) != 0)
        return c.fail_with(at, i, ": does not match the layout of its draco section");
      // Other counts may lay out alike (8 vertices and 4 triangles, 4 and 8): only the stream's
      // own say what the bytes are.
      const uint32_t dv = r.decoded_vertices(m.section), dt = r.decoded_triangles(m.section);
      if (m.num_vertices != dv || m.num_triangles != dt)
        return c.fail_with(at, i, ": ", m.num_vertices, " vertices and ", m.num_triangles,
                           " triangles, but its draco section (#", m.section, ") decodes to ", dv,
                           " and ", dt);
    }
    const uint64_t size = r.section_size(m.section);
    // The fault's message is made apart, from values, so that the passing path keeps them in
    // registers (teapot-like scenes check thousands of meshes).
    auto array_ok = [ size, i, &c ](bool present, uint64_t offset, uint64_t bytes, const char* name)
        __attribute__((always_inline)) {
      const ArrayFault fault = !present           ? (offset == 0 ? kArrayOk : kArrayFlagClear)
                               : offset % 16 != 0 ? kArrayUnaligned
                               : offset > size || bytes > size - offset ? kArrayOutside
                                                                        : kArrayOk;
      return fault == kArrayOk || array_failed(c, fault, i, name, offset, bytes, size);
    };
    const uint64_t nv = m.num_vertices, nt = m.num_triangles;
    return array_ok(true, m.positions, nv * 12, "positions") &&
           array_ok(m.flags & kMeshNormals, m.normals, nv * 12, "normals") &&
           array_ok(m.flags & kMeshTangents, m.tangents, nv * 12, "tangents") &&
           array_ok(m.flags & kMeshUV, m.uv, nv * 8, "uv") &&
           array_ok(true, m.indices, nt * 12, "indices") &&
           array_ok(m.flags & kMeshFaceIndices, m.face_indices, nt * 4, "face indices") &&
           c.index(m.source_shape, shapes.size, "mesh", i, "source shape", "shapes", true);
  };
  auto mesh_ok = [&](uint32_t i, Checker& c) {
    if (!check_mesh(i, c)) return false;
    const uint64_t n = uint64_t(meshes[i].num_triangles) * 3;
    const uint32_t* v =
        reinterpret_cast<const uint32_t*>(r.section_data(meshes[i].section) + meshes[i].indices);
    const uint64_t k = first_at_or_above(v, n, meshes[i].num_vertices);
    return k == n || c.fail_with("mesh ", i, ": triangle ", k / 3, " has vertex index ", v[k], " (",
                                 meshes[i].num_vertices, " vertices)");
  };
  // Every index of every mesh is read: where there are many, the meshes are checked on every
  // thread (mesh200's 54 MB of indices took 1.4 ms on one), and the first bad one in order is
  // then checked again here for its message.
  uint64_t index_bytes = 0;
  for (const MeshRecord& m : meshes) index_bytes += uint64_t(m.num_triangles) * 12;
  if (threads == 1 || index_bytes < kParallelIndexBytes || meshes.size < 2) {
    first_failure(meshes.size, c, mesh_ok);
  } else {
    std::atomic<uint32_t> first_bad{meshes.size};
    tbb::task_arena arena(threads > 0 ? threads : int(tbb::task_arena::automatic));
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<uint32_t>(0, meshes.size, 1),
                        [&](const tbb::blocked_range<uint32_t>& range) {
                          Checker local(path_, reader_);
                          for (uint32_t i = range.begin(); i < range.end(); ++i) {
                            if (i >= first_bad.load(std::memory_order_relaxed)) return;
                            if (mesh_ok(i, local)) continue;
                            for (uint32_t seen = first_bad.load();
                                 i < seen && !first_bad.compare_exchange_weak(seen, i);) {
                            }
                            return;
                          }
                        });
    });
    if (first_bad.load() < meshes.size) mesh_ok(first_bad.load(), c);
  }
  // A Draco section holds one mesh (ARCHIVE.md section 8): no two records may name it. Only
  // archives with Draco sections pay for the pass.
  bool any_draco = false;
  for (uint32_t s = 0; s < r.section_count(); ++s)
    any_draco |= r.entry(s).codec == uint32_t(Codec::kDraco);
  if (any_draco && !c.failed()) {
    std::vector<uint32_t> owner(r.section_count(), kNoIndex);
    for (uint32_t i = 0; i < meshes.size; ++i) {
      const uint32_t s = meshes[i].section;  // checked above: a geometry section
      if (r.entry(s).codec != uint32_t(Codec::kDraco)) continue;
      if (owner[s] != kNoIndex) {
        c.fail("mesh " + std::to_string(i) + ": its draco section (#" + std::to_string(s) +
               ") holds mesh " + std::to_string(owner[s]) + " already");
        break;
      }
      owner[s] = i;
    }
  }
  c.in(sec(SectionKind::kImages));
  for (uint32_t i = 0; i < images.size && !c.failed(); ++i) {
    const ImageRecord& im = images[i];
    std::string at = "image " + std::to_string(i) + ": ";
    if (im.section >= r.section_count() ||
        r.entry(im.section).kind != uint32_t(SectionKind::kTexels)) {
      c.fail(at + "section is not a texels section");
      break;
    }
    if ((im.channels != 1 && im.channels != 3) || im.levels == 0 || im.levels > 32 ||
        im.format > uint32_t(PixelFormat::kUnorm8) || im.wrap > 2 || im.width == 0 ||
        im.height == 0 || im.source_width == 0 || im.source_height == 0) {
      c.fail(at + "malformed header");
      break;
    }
    const uint64_t bytes_per = texel_bytes(im.format);  // 4, 2 or 1: the format was checked
    uint64_t off = im.offset, size = r.section_size(im.section);
    for (uint32_t l = 0; l < im.levels && !c.failed(); ++l) {
      uint64_t w = std::max<uint64_t>(1, uint64_t(im.width) >> l);
      uint64_t h = std::max<uint64_t>(1, uint64_t(im.height) >> l);
      uint64_t bytes = w * h * im.channels * bytes_per;
      if (off % 16 != 0 || off > size || bytes > size - off) {
        c.fail(at + "level " + std::to_string(l) + " lies outside its section");
        break;
      }
      off = (off + bytes + 15) & ~uint64_t(15);
    }
    if (c.failed()) break;
    if ((im.reserved[0] | im.reserved[1] | im.reserved[2]) != 0) {
      c.fail(at + "reserved field is not zero");
      break;
    }
    if (!c.index(im.distribution, images.size, "image", i, "distribution", "images", true) ||
        !c.index(im.source_image, images.size, "image", i, "source image", "images", true))
      break;
    // A sampling distribution is a pdf: pbrtc keeps it f32 whatever --texture-precision says.
    if (im.distribution != kNoIndex &&
        images[im.distribution].format != uint32_t(PixelFormat::kFloat32)) {
      c.fail(at + "distribution image " + std::to_string(im.distribution) + " is " +
             texel_format_name(images[im.distribution].format) + ", not f32");
      break;
    }
    if (im.source_image != kNoIndex) {
      // Only a resampled image names its texels as decoded; a source is at its own size, so
      // this also keeps sources from naming sources (no chains).
      if (im.width == im.source_width && im.height == im.source_height) {
        c.fail(at + "level 0 is already the source size, " + std::to_string(im.width) + " x " +
               std::to_string(im.height) + ", yet it names source image " +
               std::to_string(im.source_image));
        break;
      }
      // The texels as decoded: one level at the source size, with no source of its own.
      const ImageRecord& src = images[im.source_image];
      if (im.source_image == i || src.source_image != kNoIndex || src.levels != 1 ||
          src.width != im.source_width || src.height != im.source_height ||
          src.channels != im.channels || src.format != im.format || src.wrap != im.wrap) {
        c.fail(at + "source image " + std::to_string(im.source_image) + " is not " +
               std::to_string(im.source_width) + " x " + std::to_string(im.source_height) + " x " +
               std::to_string(im.channels) +
               " in the same format and wrap, with one level and no source of its own");
        break;
      }
    }
  }
  // What a texture or a light looks up is a whole pyramid, as pbrt-v3's MIPMap builds it: the
  // renderer picks levels by pbrt-v3's arithmetic, which a shorter one would silently change.
  // A sampling distribution is one level.
  auto expect_levels = [&](uint32_t image, bool whole_pyramid, const char* as, uint32_t owner,
                           const char* role) {
    if (image == kNoIndex) return true;
    const ImageRecord& im = images[image];
    const uint32_t want = whole_pyramid ? full_pyramid_levels(im.width, im.height) : 1;
    if (im.levels == want) return true;
    return c.fail("image " + std::to_string(image) + ": " + std::to_string(im.levels) +
                  " levels, but as " + as + " " + std::to_string(owner) + "'s " + role +
                  " it has " + std::to_string(want));
  };
  for (uint32_t i = 0; i < textures.size && !c.failed(); ++i)
    expect_levels(textures[i].image, true, "texture", i, "pyramid");
  for (uint32_t i = 0; i < lights.size && !c.failed(); ++i)
    expect_levels(lights[i].image, true, "light", i, "pyramid");
  for (uint32_t i = 0; i < images.size && !c.failed(); ++i)
    expect_levels(images[i].distribution, false, "image", i, "distribution");
  return c.done(error);
}

}  // namespace pbrta
