// tests/compiler/archive_entity_check_test.cpp — SceneArchive's record checks on a large scene:
// whatever the thread count, the error names the first bad record in order, and a damaged record
// early in an array wins over one far later. Entities (damage in the record itself and in one of
// its values, a texture index among them), texture bindings (checked with their entity), materials,
// shapes, mesh layouts and the small meshes' triangle indices.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "compiled_scene.h"
#include "compiler/archive_builder.h"
#include "format/archive.h"
#include "format/scene_archive.h"
#include "reseal_and_load.h"
#include "test_support.h"

namespace pbrtc {
namespace {

// Scene text compiled to an uncompressed archive (its records are edited in place), dir/good.pbrta.
void compile_uncompressed(const std::string& dir, const std::string& text) {
  const std::string scene = testing_support::write_file(dir + "/s.pbrt", text);
  CompiledScene c;
  compile_scene(scene, &c);
  ASSERT_TRUE(c.ok) << (c.errors.empty() ? "" : c.errors[0]);
  ArchiveOptions opt;
  opt.compress = false;
  std::string error;
  ASSERT_TRUE(write_archive(c.scene, c.files, directory_of(scene), dir + "/good.pbrta", opt,
                            nullptr, &error))
      << error;
}

// Record i of a section of T records in archive bytes b (laid out as a's), edited by f.
template <class T, class F>
void edit_record(const pbrta::SceneArchive& a, std::string* b, pbrta::SectionKind kind, uint32_t i,
                 F f) {
  const uint32_t s = testing_support::section_entry(a, kind);
  ASSERT_NE(s, pbrta::kNoIndex);
  T r;
  const uint64_t at = a.reader().entry(s).offset + uint64_t(i) * sizeof(T);
  std::memcpy(&r, b->data() + at, sizeof r);
  f(&r);
  std::memcpy(&(*b)[at], &r, sizeof r);
}

// The error loading bytes (resealed) gives, the same on 1 and 2 threads.
std::string error_on_every_thread_count(const std::string& dir, const std::string& bytes) {
  const std::string path = dir + "/bad.pbrta";
  const std::string one = testing_support::reseal_and_load(bytes, path, 1);
  const std::string two = testing_support::reseal_and_load(bytes, path, 2);
  EXPECT_EQ(one, two);
  return two;
}

// The error loading bytes (resealed) from memory on 2 threads gives; "" when they load.
std::string resealed_load_error(const std::string& bytes) {
  std::vector<uint8_t> sealed(bytes.begin(), bytes.end());
  fuzz_support::reseal(&sealed);
  pbrta::SceneArchive a;
  std::string error;
  if (a.load_memory(std::string_view(reinterpret_cast<const char*>(sealed.data()), sealed.size()),
                    "edited", 2, &error))
    return "";
  return error.empty() ? "refused without a message" : error;
}

// Each value fault at every parameter of entity e of archive a (whose bytes are good): refused,
// naming the entity, the type and the parameter; and each value's words moved to end exactly at
// the table's end: sound. Values are filtered two at a time where the CPU allows
// (format/plain_values.h), so each lane must refuse what the one-at-a-time check refuses
// and accept its exact edges, and a lane past the entity's count must not judge it.
void expect_every_value_fault_refused(const pbrta::SceneArchive& a, const std::string& good,
                                      const std::string& dir, uint32_t e) {
  const uint32_t words = a.words.size;
  const std::string type(a.type_name(e));
  const pbrta::TypeSpec& ts = a.type_of(e);
  for (uint32_t p = 0; p < ts.num_params; ++p) {
    const std::string name(ts.params[p].name);
    SCOPED_TRACE(type + " " + name);
    const uint32_t at = a.entities[e].first_value + p;
    const pbrta::ValueRecord v = a.values[at];
    const std::string where = "entity " + std::to_string(e) + ": " + type + " \"" + name + "\": ";
    auto refused = [&](void (*damage)(pbrta::ValueRecord*, uint32_t), const std::string& why) {
      std::string b = good;
      edit_record<pbrta::ValueRecord>(a, &b, pbrta::SectionKind::kValues, at,
                                      [&](pbrta::ValueRecord* r) { damage(r, words); });
      const std::string error = error_on_every_thread_count(dir, b);
      EXPECT_NE(error.find(where), std::string::npos) << error;
      EXPECT_NE(error.find(why), std::string::npos) << error;
    };
    refused([](pbrta::ValueRecord* r, uint32_t) { r->flags |= 2; }, "unknown value flags");
    refused([](pbrta::ValueRecord* r, uint32_t w) { r->offset = w + 1 - (r->count > 0); },
            "words out of range");
    if (ts.params[p].arity > 0)
      refused(  // its words at the start, so that only the count is wrong
          [](pbrta::ValueRecord* r, uint32_t) {
            r->count += r->count == 0 ? 2 : 1;
            r->offset = 0;
          },
          "values, the schema says");
    const uint64_t width = pbrta::kind_width(ts.params[p].kind);
    std::string b = good;
    edit_record<pbrta::ValueRecord>(
        a, &b, pbrta::SectionKind::kValues, at,
        [&](pbrta::ValueRecord* r) { r->offset = uint32_t(words - r->count * width); });
    if (v.count > 0 && ts.params[p].kind != pbrta::Kind::kString) {
      EXPECT_EQ(resealed_load_error(b), "");
    }
  }
}

class EntityCheck : public ::testing::Test {
 protected:
  // 40000 one-triangle meshes, each with its own material bound to a spectrum texture: tens of
  // thousands of records of each kind.
  static constexpr int kShapes = 40000;

  void SetUp() override {
    dir_ = testing_support::scratch_dir(
        std::string("EntityCheck.") +
        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::string text =
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
        "Texture \"f\" \"float\" \"constant\"\nTexture \"s\" \"spectrum\" \"constant\"\n";
    for (int i = 0; i < kShapes; ++i)
      text += "Material \"matte\" \"texture Kd\" \"s\" \"float sigma\" " + std::to_string(i % 7) +
              "\nShape \"trianglemesh\" \"point P\" [0 0 0 1 0 0 0 1 " + std::to_string(i) +
              "] \"integer indices\" [0 1 2]\n";
    text += "WorldEnd\n";
    ASSERT_NO_FATAL_FAILURE(compile_uncompressed(dir_, text));
    std::string error;
    const std::string path = dir_ + "/good.pbrta";
    good_ = testing_support::read_file(path);
    ASSERT_TRUE(archive_.load(path, 2, &error)) << error;
    ASSERT_GT(archive_.entities.size, 4u * 8192u);
    ASSERT_GT(archive_.materials.size, 4u * 8192u);
    ASSERT_EQ(archive_.shapes.size, uint32_t(kShapes));
    ASSERT_EQ(archive_.meshes.size, uint32_t(kShapes));
    entities_ = testing_support::section_entry(archive_, pbrta::SectionKind::kEntities);
    values_ = testing_support::section_entry(archive_, pbrta::SectionKind::kValues);
    ASSERT_NE(entities_, pbrta::kNoIndex);
    ASSERT_NE(values_, pbrta::kNoIndex);
  }

  uint64_t offset_of(uint32_t section) const { return archive_.reader().entry(section).offset; }
  // Record i of a section of T records, edited by f, into b.
  template <class T, class F>
  void edit(std::string* b, pbrta::SectionKind kind, uint32_t i, F f) const {
    edit_record<T>(archive_, b, kind, i, f);
  }
  // Byte `field` of entity i's record set to v.
  void set_entity_byte(std::string* b, uint32_t i, size_t field, uint8_t v) const {
    (*b)[offset_of(entities_) + i * sizeof(pbrta::EntityRecord) + field] = char(v);
  }
  // Damage to a late record is reported; then, with an early one damaged too, the early one.
  template <class T, class F, class G>
  void expect_first_wins(pbrta::SectionKind kind, uint32_t late, F damage_late,
                         const std::string& late_error, uint32_t early, G damage_early,
                         const std::string& early_error) {
    std::string b = good_;
    edit<T>(&b, kind, late, damage_late);
    std::string error = error_of(b);
    EXPECT_NE(error.find(late_error), std::string::npos) << error;
    edit<T>(&b, kind, early, damage_early);
    error = error_of(b);
    EXPECT_NE(error.find(early_error), std::string::npos) << error;
  }
  // The float texture: bound where a spectrum texture belongs, it is the wrong class.
  uint32_t float_texture() const {
    for (uint32_t t = 0; t < archive_.textures.size; ++t)
      if (archive_.entities[archive_.textures[t].entity].category ==
          uint8_t(pbrta::Category::kFloatTexture))
        return t;
    return pbrta::kNoIndex;
  }
  // Entity e's "Kd", bound to the spectrum texture, bound to texture t instead, in b.
  void rebind_kd(std::string* b, uint32_t e, uint32_t t) const {
    const pbrta::ValueRecord* kd = archive_.value(e, "Kd");
    ASSERT_NE(kd, nullptr);
    ASSERT_NE(kd->texture, pbrta::kNoIndex);
    edit<pbrta::ValueRecord>(b, pbrta::SectionKind::kValues, uint32_t(kd - archive_.values.data),
                             [&](pbrta::ValueRecord* v) { v->texture = t; });
  }
  // The same error on 1 and 2 threads (after resealing the edited sections).
  std::string error_of(const std::string& bytes) {
    return error_on_every_thread_count(dir_, bytes);
  }

  std::string dir_, good_;
  pbrta::SceneArchive archive_;
  uint32_t entities_ = 0, values_ = 0;
};

TEST_F(EntityCheck, FirstBadEntityInOrderOnEveryThreadCount) {
  // The shapes' entities are the last ones; these lie far apart.
  const uint32_t n = archive_.entities.size;
  const uint32_t early = n - 30001, late = n - 5;
  std::string b = good_;
  set_entity_byte(&b, late, offsetof(pbrta::EntityRecord, category), 200);
  const std::string late_only = error_of(b);
  EXPECT_NE(late_only.find("entity " + std::to_string(late) + ": category 200 unknown"),
            std::string::npos)
      << late_only;
  set_entity_byte(&b, early, offsetof(pbrta::EntityRecord, reserved0), 1);
  const std::string both = error_of(b);
  EXPECT_NE(both.find("entity " + std::to_string(early) + ": reserved field is not zero"),
            std::string::npos)
      << both;
  EXPECT_NE(both.find("section 'entities'"), std::string::npos) << both;
}

TEST_F(EntityCheck, BadValueNamesItsEntity) {
  const uint32_t i = archive_.entities.size - 12345;
  const pbrta::EntityRecord& e = archive_.entities[i];
  ASSERT_GT(e.num_values, 0u);
  std::string b = good_;
  // The value's flags: only kValueGiven is defined.
  const uint64_t at = offset_of(values_) + uint64_t(e.first_value) * sizeof(pbrta::ValueRecord) +
                      offsetof(pbrta::ValueRecord, flags);
  b[at + 3] = char(0x80);
  const std::string error = error_of(b);
  EXPECT_NE(error.find("entity " + std::to_string(i) + ": " + std::string(archive_.type_name(i))),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("unknown value flags"), std::string::npos) << error;
}

// Each value fault at every parameter of a mesh (8) and a material (3, one bound to a texture).
TEST_F(EntityCheck, EveryValueFaultAtEveryParameter) {
  for (const char* type : {"trianglemesh", "matte"}) {
    uint32_t e = archive_.entities.size;
    while (e-- > 0 && archive_.type_name(e) != type) {
    }
    ASSERT_LT(e, archive_.entities.size) << type;
    expect_every_value_fault_refused(archive_, good_, dir_, e);
  }
}

// A material's "Kd" bound to the float texture instead of the spectrum one.
TEST_F(EntityCheck, FirstWrongTextureBindingInOrder) {
  const uint32_t float_tex = float_texture();
  ASSERT_NE(float_tex, pbrta::kNoIndex);
  const uint32_t early = archive_.materials[2000].entity, late = archive_.materials[39000].entity;
  std::string b = good_;
  for (uint32_t e : {late, early}) {
    ASSERT_NO_FATAL_FAILURE(rebind_kd(&b, e, float_tex));
    const std::string error = error_of(b);
    EXPECT_NE(error.find("entity " + std::to_string(e) + " \"Kd\": texture " +
                         std::to_string(float_tex) + " is not a"),
              std::string::npos)
        << error;
    EXPECT_NE(error.find("section 'values'"), std::string::npos) << error;
  }
}

// Bindings are checked with the rest of each entity, so the first bad entity in order is named
// whichever of its checks it fails: a wrong binding before a bad record, and a bad record before
// a wrong binding.
TEST_F(EntityCheck, ABindingAndARecordFaultReportTheEarlierEntity) {
  const uint32_t float_tex = float_texture();
  ASSERT_NE(float_tex, pbrta::kNoIndex);
  const uint32_t early = archive_.materials[3000].entity, late = archive_.materials[36000].entity;
  ASSERT_LT(early + 8192, late);  // far apart, the early one first
  std::string b = good_;
  ASSERT_NO_FATAL_FAILURE(rebind_kd(&b, early, float_tex));
  set_entity_byte(&b, late, offsetof(pbrta::EntityRecord, reserved1), 1);
  std::string error = error_of(b);
  EXPECT_NE(error.find("section 'values'"), std::string::npos) << error;
  EXPECT_NE(error.find("entity " + std::to_string(early) + " \"Kd\": texture"), std::string::npos)
      << error;
  b = good_;
  ASSERT_NO_FATAL_FAILURE(rebind_kd(&b, late, float_tex));
  set_entity_byte(&b, early, offsetof(pbrta::EntityRecord, reserved1), 1);
  error = error_of(b);
  EXPECT_NE(error.find("section 'entities'"), std::string::npos) << error;
  EXPECT_NE(error.find("entity " + std::to_string(early) + ": reserved field is not zero"),
            std::string::npos)
      << error;
}

// A texture index past the textures, then (earlier, so it wins) a texture on a parameter that
// takes none. Both must stop the load: the entity check once went on to the next entity after
// such a failure, and the binding check behind it then read past the textures.
TEST_F(EntityCheck, TextureOutOfRangeOrOnAPlainParameterIsRefused) {
  const uint32_t early = archive_.shapes[1000].entity, late = archive_.shapes[39000].entity;
  const pbrta::ValueRecord* alpha = archive_.value(late, "alpha");
  const pbrta::ValueRecord* indices = archive_.value(early, "indices");
  ASSERT_NE(alpha, nullptr);
  ASSERT_NE(indices, nullptr);
  ASSERT_EQ(indices->texture, pbrta::kNoIndex);
  std::string b = good_;
  edit<pbrta::ValueRecord>(&b, pbrta::SectionKind::kValues, uint32_t(alpha - archive_.values.data),
                           [](pbrta::ValueRecord* v) { v->texture = 99999; });
  std::string error = error_of(b);
  EXPECT_NE(error.find("entity " + std::to_string(late) +
                       ": trianglemesh \"alpha\": texture 99999 out of range (2 textures)"),
            std::string::npos)
      << error;
  edit<pbrta::ValueRecord>(&b, pbrta::SectionKind::kValues,
                           uint32_t(indices - archive_.values.data),
                           [](pbrta::ValueRecord* v) { v->texture = 0; });
  error = error_of(b);
  EXPECT_NE(error.find("entity " + std::to_string(early) +
                       ": trianglemesh \"indices\": a texture on a parameter that takes none"),
            std::string::npos)
      << error;
}

TEST_F(EntityCheck, FirstBadMaterialInOrder) {
  expect_first_wins<pbrta::MaterialRecord>(
      pbrta::SectionKind::kMaterials, 39000, [](pbrta::MaterialRecord* m) { m->reserved = 1; },
      "material 39000: reserved field is not zero", 3000,
      [](pbrta::MaterialRecord* m) { m->mix[0] = 123456789; },
      "material 3000: mix material 1 123456789 out of range");
}

// Provenance records name strings of the section's own table (ARCHIVE.md section 6); 80k of
// them are checked, and the first bad one in order is reported.
TEST_F(EntityCheck, FirstBadProvenanceRecordInOrder) {
  const uint32_t s = testing_support::section_entry(archive_, pbrta::SectionKind::kProvenance);
  ASSERT_NE(s, pbrta::kNoIndex);
  ASSERT_GT(archive_.provenance.size, 4u * 8192u);
  uint32_t strings;  // the section opens with the record count, then this
  std::memcpy(&strings, good_.data() + offset_of(s) + 4, 4);
  // Record i's field (file, name or path) set to v, after the two counts.
  auto set = [&](std::string* b, uint32_t i, size_t field, uint32_t v) {
    std::memcpy(&(*b)[offset_of(s) + 8 + uint64_t(i) * sizeof(pbrta::ProvenanceRecord) + field], &v,
                4);
  };
  const uint32_t late = archive_.provenance.size - 3, early = 9000;
  std::string b = good_;
  set(&b, late, offsetof(pbrta::ProvenanceRecord, path), strings);
  const std::string only_late = error_of(b);
  EXPECT_NE(only_late.find("section 'provenance' (#" + std::to_string(s) + "): record " +
                           std::to_string(late) + ": string out of range (" +
                           std::to_string(strings) + " strings)"),
            std::string::npos)
      << only_late;
  set(&b, early, offsetof(pbrta::ProvenanceRecord, file), 0xFFFFFFFFu);
  const std::string both = error_of(b);
  EXPECT_NE(both.find("record " + std::to_string(early) + ": string out of range"),
            std::string::npos)
      << both;
}

// Each of a shape's eight index fields past its table, or missing where it is required, and its
// entity of the wrong category: refused, naming the field. The shape checks take the eight
// fields as one vector where the CPU allows (format/scene_validation.cpp).
TEST_F(EntityCheck, EveryShapeIndexFieldIsChecked) {
  const uint32_t i = 25000;
  struct Field {
    size_t offset;
    const char* name;
    uint32_t bound;
    bool may_be_missing;
  };
  const Field fields[] = {
      {offsetof(pbrta::ShapeRecord, entity), "entity", archive_.entities.size, false},
      {offsetof(pbrta::ShapeRecord, mesh), "mesh", archive_.meshes.size, true},
      {offsetof(pbrta::ShapeRecord, material), "material", archive_.materials.size, false},
      {offsetof(pbrta::ShapeRecord, area_light), "area light", archive_.area_lights.size, true},
      {offsetof(pbrta::ShapeRecord, inside_medium), "inside medium", archive_.media.size, true},
      {offsetof(pbrta::ShapeRecord, outside_medium), "outside medium", archive_.media.size, true},
      {offsetof(pbrta::ShapeRecord, transform), "transform", archive_.transforms.size, false},
      {offsetof(pbrta::ShapeRecord, object), "object", archive_.objects.size, true},
  };
  const std::string at = "shape " + std::to_string(i) + ": ";
  for (const Field& f : fields) {
    SCOPED_TRACE(f.name);
    auto with = [&](uint32_t v) {
      std::string b = good_;
      edit<pbrta::ShapeRecord>(&b, pbrta::SectionKind::kShapes, i, [&](pbrta::ShapeRecord* s) {
        std::memcpy(reinterpret_cast<char*>(s) + f.offset, &v, 4);
      });
      return b;
    };
    std::string error = error_of(with(f.bound));
    EXPECT_NE(error.find(at + f.name + " " + std::to_string(f.bound) + " out of range"),
              std::string::npos)
        << error;
    if (f.may_be_missing) {
      EXPECT_EQ(resealed_load_error(with(pbrta::kNoIndex)), "");
    } else {
      error = error_of(with(pbrta::kNoIndex));
      EXPECT_NE(error.find(at + f.name + " is missing"), std::string::npos) << error;
    }
  }
  // A material's entity where the shape's belongs.
  std::string b = good_;
  const uint32_t material_entity = archive_.materials[7].entity;
  edit<pbrta::ShapeRecord>(&b, pbrta::SectionKind::kShapes, i,
                           [&](pbrta::ShapeRecord* s) { s->entity = material_entity; });
  const std::string error = error_of(b);
  EXPECT_NE(error.find(at + "entity entity " + std::to_string(material_entity) +
                       " is a material, not a shape"),
            std::string::npos)
      << error;
}

TEST_F(EntityCheck, FirstBadShapeInOrder) {
  expect_first_wins<pbrta::ShapeRecord>(
      pbrta::SectionKind::kShapes, 38000, [](pbrta::ShapeRecord* s) { s->reserved = 7; },
      "shape 38000: reserved field is not zero", 100,
      [](pbrta::ShapeRecord* s) { s->flags |= 0x100; }, "shape 100: unknown flags");
}

// A mesh's bad layout; the meshes before it have their indices checked, the ones after do not.
TEST_F(EntityCheck, FirstBadMeshLayoutInOrder) {
  expect_first_wins<pbrta::MeshRecord>(
      pbrta::SectionKind::kMeshes, 39999, [](pbrta::MeshRecord* m) { m->indices += 4; },
      "mesh 39999: indices offset is not 16-byte aligned", 20000,
      [](pbrta::MeshRecord* m) { m->section = 999; },
      "mesh 20000: section 999 is not a geometry section");
}

// A small mesh's indices are read in the same parallel pass as the layouts: the first mesh in
// order with either fault is the one reported, on every thread count.
TEST_F(EntityCheck, FirstBadMeshIndexOrLayoutInOrder) {
  // Mesh i's first triangle index set to v (each mesh has 3 vertices), in b.
  auto set_index = [&](std::string* b, uint32_t i, uint32_t v) {
    const pbrta::MeshRecord& m = archive_.meshes[i];
    std::memcpy(&(*b)[archive_.reader().entry(m.section).offset + m.indices], &v, 4);
  };
  auto bad_layout = [](pbrta::MeshRecord* m) { m->indices += 4; };
  std::string b = good_;
  set_index(&b, 39000, 3);
  EXPECT_NE(error_of(b).find("mesh 39000: triangle 0 has vertex index 3 (3 vertices)"),
            std::string::npos);
  edit<pbrta::MeshRecord>(&b, pbrta::SectionKind::kMeshes, 20000, bad_layout);
  EXPECT_NE(error_of(b).find("mesh 20000: indices offset is not 16-byte aligned"),
            std::string::npos);
  set_index(&b, 5000, 0xFFFFFFFFu);
  EXPECT_NE(error_of(b).find("mesh 5000: triangle 0 has vertex index 4294967295 (3 vertices)"),
            std::string::npos);
}

// A record fault is reported on any thread count, a damaged section wins over a record fault
// (sections are checked before records), and a failed load leaves no record views behind.
TEST(RecordChecks, ADamagedSectionWinsAndAFailedLoadLeavesNoRecords) {
  const std::string dir = testing_support::scratch_dir("RecordChecks.DamagedSectionWins");
  std::string text = "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n";
  for (int i = 0; i < 300; ++i)
    text += "AttributeBegin\nTranslate " + std::to_string(i) +
            " 0 0\nMaterial \"matte\"\nShape \"trianglemesh\" \"point P\" [0 0 0 1 0 0 0 1 0] "
            "\"integer indices\" [0 1 2]\nAttributeEnd\n";
  text += "WorldEnd\n";
  ASSERT_NO_FATAL_FAILURE(compile_uncompressed(dir, text));
  std::string error;
  const std::string path = dir + "/good.pbrta";
  pbrta::SceneArchive good;
  ASSERT_TRUE(good.load(path, 2, &error)) << error;
  const pbrta::ArchiveReader& r = good.reader();
  const uint32_t transforms = testing_support::section_entry(good, pbrta::SectionKind::kTransforms);
  const uint32_t entities = testing_support::section_entry(good, pbrta::SectionKind::kEntities);
  ASSERT_NE(transforms, pbrta::kNoIndex);
  ASSERT_NE(entities, pbrta::kNoIndex);

  std::string bytes = testing_support::read_file(path);
  const uint32_t late = good.entities.size - 2;
  bytes[r.entry(entities).offset + uint64_t(late) * sizeof(pbrta::EntityRecord) + 1] = 1;
  for (int threads : {1, 2})
    EXPECT_NE(testing_support::reseal_and_load(bytes, dir + "/bad.pbrta", threads)
                  .find("entity " + std::to_string(late) + ": reserved field is not zero"),
              std::string::npos);
  // The same fault, resealed, then a transform's bytes damaged.
  std::vector<uint8_t> sealed(bytes.begin(), bytes.end());
  fuzz_support::reseal(&sealed);
  sealed[r.entry(transforms).offset + 100] ^= 0x40;
  const std::string both =
      testing_support::write_file(dir + "/both.pbrta", std::string(sealed.begin(), sealed.end()));
  for (int threads : {1, 2}) {
    pbrta::SceneArchive a;
    EXPECT_FALSE(a.load(both, threads, &error));
    EXPECT_NE(
        error.find("section 'transforms' (#" + std::to_string(transforms) + "): checksum mismatch"),
        std::string::npos)
        << error;
    EXPECT_EQ(a.entities.size, 0u);
    EXPECT_EQ(a.entities.data, nullptr);
    EXPECT_EQ(a.num_strings(), 0u);
  }
}

// The counts format/entity_rules.h ties together are checked by the reader too: a curve whose
// degree, or a heterogeneous medium whose grid size, an archive was edited to break is refused,
// so a renderer may index control points and density grids by them.
TEST(EntityRules, TheReaderRefusesACurveOrDensityGridThatBreaksThem) {
  const std::string dir = testing_support::scratch_dir("EntityRules");
  ASSERT_NO_FATAL_FAILURE(compile_uncompressed(
      dir,
      "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
      "MakeNamedMedium \"smoke\" \"string type\" \"heterogeneous\" \"integer nx\" 2 "
      "\"float density\" [0.5 1]\n"
      "Shape \"curve\" \"point P\" [0 0 0 1 1 0 2 1 0 3 0 0] \"float width\" 0.1\n"
      "WorldEnd\n"));
  std::string error;
  const std::string path = dir + "/good.pbrta";
  pbrta::SceneArchive a;
  ASSERT_TRUE(a.load(path, 1, &error)) << error;
  const std::string good = testing_support::read_file(path);
  const uint32_t words = testing_support::section_entry(a, pbrta::SectionKind::kWords);
  ASSERT_NE(words, pbrta::kNoIndex);
  uint32_t curve = pbrta::kNoIndex, medium = pbrta::kNoIndex;
  for (uint32_t e = 0; e < a.entities.size; ++e) {
    if (a.type_name(e) == "curve") curve = e;
    if (a.type_name(e) == "heterogeneous") medium = e;
  }
  ASSERT_NE(curve, pbrta::kNoIndex);
  ASSERT_NE(medium, pbrta::kNoIndex);
  // The archive with entity e's int parameter `name` set to v.
  auto with = [&](uint32_t e, const char* name, int32_t v) {
    std::string b = good;
    const uint64_t at = a.reader().entry(words).offset + uint64_t(a.value(e, name)->offset) * 4;
    std::memcpy(&b[at], &v, 4);
    return b;
  };
  const std::string prefix =
      path + ": section 'entities' (#" +
      std::to_string(testing_support::section_entry(a, pbrta::SectionKind::kEntities)) + "): ";
  EXPECT_EQ(testing_support::reseal_and_load(with(curve, "degree", 5), path),
            prefix + "entity " + std::to_string(curve) +
                ": curve \"degree\" 5: only degree 2 and 3 curves are supported");
  EXPECT_EQ(testing_support::reseal_and_load(with(curve, "degree", 2), path),
            prefix + "entity " + std::to_string(curve) +
                ": curve has 4 control points: a degree 2 Bezier curve needs 2 n + 3 for some n "
                ">= 0");
  EXPECT_EQ(testing_support::reseal_and_load(with(medium, "nx", 3), path),
            prefix + "entity " + std::to_string(medium) +
                ": heterogeneous medium has 2 density values; nx * ny * nz = 3 * 1 * 1 = 3");
}

}  // namespace
}  // namespace pbrtc
