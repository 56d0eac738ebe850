// tests/compiler/archive_record_check_test.cpp — SceneArchive's checks of the smaller record
// kinds (textures, media, lights, area lights, objects, object shapes, instances) on a small
// scene: a damaged record is named, and of two damaged records the earlier one is, on 1 and 2
// threads alike. (archive_entity_check_test covers the kinds large scenes check in parallel.)
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "compiled_scene.h"
#include "compiler/archive_builder.h"
#include "format/archive.h"
#include "format/archive_names.h"
#include "format/scene_archive.h"
#include "reseal_and_load.h"
#include "test_support.h"

namespace pbrtc {
namespace {

class RecordCheck : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing_support::scratch_dir(
        std::string("RecordCheck.") +
        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    const std::string scene = testing_support::write_file(dir_ + "/s.pbrt", R"(
LookAt 0 0 5  0 0 0  0 1 0
Camera "perspective"
WorldBegin
Texture "a" "float" "constant"
Texture "b" "spectrum" "constant"
MakeNamedMedium "m1" "string type" "homogeneous"
MakeNamedMedium "m2" "string type" "homogeneous"
LightSource "point"
LightSource "distant"
AttributeBegin
  MediumInterface "m1" "m2"
  AreaLightSource "diffuse"
  Shape "sphere"
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse"
  Shape "disk"
AttributeEnd
ObjectBegin "o1"
  Shape "sphere"
ObjectEnd
ObjectBegin "o2"
  Shape "sphere"
ObjectEnd
ObjectInstance "o1"
ObjectInstance "o2"
WorldEnd
)");
    CompiledScene c;
    compile_scene(scene, &c);
    ASSERT_TRUE(c.ok) << (c.errors.empty() ? "" : c.errors[0]);
    std::string error;
    const std::string path = dir_ + "/good.pbrta";
    ArchiveOptions opt;
    opt.compress = false;
    ASSERT_TRUE(write_archive(c.scene, c.files, directory_of(scene), path, opt, nullptr, &error))
        << error;
    good_ = testing_support::read_file(path);
    ASSERT_TRUE(archive_.load(path, 1, &error)) << error;
    for (uint32_t n : {archive_.textures.size, archive_.media.size, archive_.lights.size,
                       archive_.area_lights.size, archive_.objects.size,
                       archive_.object_shapes.size, archive_.instances.size})
      ASSERT_GE(n, 2u);
  }

  // Damage to record 1 of a section of T records is reported; with record 0 damaged too, record
  // 0 is; each on 1 and 2 threads.
  template <class T, class F>
  void expect_first_wins(pbrta::SectionKind kind, F damage, const std::string& error_1,
                         const std::string& error_0) {
    const uint32_t s = testing_support::section_entry(archive_, kind);
    ASSERT_NE(s, pbrta::kNoIndex);
    const uint64_t offset = archive_.reader().entry(s).offset;
    auto edit = [&](std::string* b, uint32_t i) {
      T r;
      std::memcpy(&r, b->data() + offset + i * sizeof(T), sizeof r);
      damage(&r);
      std::memcpy(&(*b)[offset + i * sizeof(T)], &r, sizeof r);
    };
    const std::string prefix = dir_ + "/bad.pbrta: section '" +
                               std::string(pbrta::section_kind_name(kind)) + "' (#" +
                               std::to_string(s) + "): ";
    std::string b = good_;
    edit(&b, 1);
    EXPECT_EQ(error_of(b), prefix + error_1);
    edit(&b, 0);
    EXPECT_EQ(error_of(b), prefix + error_0);
  }
  std::string error_of(const std::string& bytes) {
    const std::string path = dir_ + "/bad.pbrta";
    const std::string one = testing_support::reseal_and_load(bytes, path, 1);
    EXPECT_EQ(one, testing_support::reseal_and_load(bytes, path, 2));
    return one;
  }
  // "<what> out of range (<count> <array>)", as the index checks word it.
  static std::string out_of_range(const std::string& what, uint32_t count, const char* array) {
    return what + " out of range (" + std::to_string(count) + " " + array + ")";
  }

  std::string dir_, good_;
  pbrta::SceneArchive archive_;
};

constexpr uint32_t kHuge = 123456789;

TEST_F(RecordCheck, Textures) {
  expect_first_wins<pbrta::TextureRecord>(
      pbrta::SectionKind::kTextures, [](pbrta::TextureRecord* t) { t->reserved = 1; },
      "texture 1: reserved field is not zero", "texture 0: reserved field is not zero");
}

TEST_F(RecordCheck, Media) {
  expect_first_wins<pbrta::MediumRecord>(
      pbrta::SectionKind::kMedia, [](pbrta::MediumRecord* m) { m->reserved[1] = 1; },
      "medium 1: reserved field is not zero", "medium 0: reserved field is not zero");
}

TEST_F(RecordCheck, Lights) {
  expect_first_wins<pbrta::LightRecord>(
      pbrta::SectionKind::kLights, [](pbrta::LightRecord* l) { l->transform = kHuge; },
      out_of_range("light 1: transform 123456789", archive_.transforms.size, "transforms"),
      out_of_range("light 0: transform 123456789", archive_.transforms.size, "transforms"));
}

TEST_F(RecordCheck, AreaLights) {
  expect_first_wins<uint32_t>(
      pbrta::SectionKind::kAreaLights, [](uint32_t* e) { *e = kHuge; },
      out_of_range("area light 1: entity 123456789", archive_.entities.size, "entities"),
      out_of_range("area light 0: entity 123456789", archive_.entities.size, "entities"));
}

TEST_F(RecordCheck, Objects) {
  expect_first_wins<pbrta::ObjectRecord>(
      pbrta::SectionKind::kObjects, [](pbrta::ObjectRecord* o) { o->num_shapes = kHuge; },
      "object 1: shapes out of range", "object 0: shapes out of range");
}

TEST_F(RecordCheck, ObjectShapes) {
  expect_first_wins<uint32_t>(
      pbrta::SectionKind::kObjectShapes, [](uint32_t* s) { *s = kHuge; },
      out_of_range("entry 1: shape 123456789", archive_.shapes.size, "shapes"),
      out_of_range("entry 0: shape 123456789", archive_.shapes.size, "shapes"));
}

TEST_F(RecordCheck, Instances) {
  expect_first_wins<pbrta::InstanceRecord>(
      pbrta::SectionKind::kInstances, [](pbrta::InstanceRecord* in) { in->reserved = 1; },
      "instance 1: reserved field is not zero", "instance 0: reserved field is not zero");
}

// ARCHIVE.md: the provenance strings' string 0 is empty, as the main table's is. Moving string
// 1's start onto its end makes string 0 hold string 1's bytes, all else still in order.
TEST_F(RecordCheck, ProvenanceStringZeroIsEmpty) {
  const uint32_t s = testing_support::section_entry(archive_, pbrta::SectionKind::kProvenance);
  ASSERT_NE(s, pbrta::kNoIndex);
  const uint64_t at = archive_.reader().entry(s).offset;
  uint32_t nrec = 0, nstr = 0;
  std::memcpy(&nrec, good_.data() + at, 4);
  std::memcpy(&nstr, good_.data() + at + 4, 4);
  ASSERT_GE(nstr, 3u);
  const uint64_t offsets = at + 8 + uint64_t(nrec) * sizeof(pbrta::ProvenanceRecord);
  uint32_t end_of_1 = 0;
  std::memcpy(&end_of_1, good_.data() + offsets + 8, 4);
  ASSERT_GT(end_of_1, 0u);
  std::string b = good_;
  std::memcpy(&b[offsets + 4], &end_of_1, 4);
  EXPECT_EQ(error_of(b), dir_ + "/bad.pbrta: section 'provenance' (#" + std::to_string(s) +
                             "): string 0 is not empty");
}

}  // namespace
}  // namespace pbrtc
