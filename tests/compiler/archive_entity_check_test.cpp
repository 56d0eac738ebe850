// tests/compiler/archive_entity_check_test.cpp — SceneArchive's entity checks on a scene large
// enough that they run in blocks on several threads: whatever the thread count, the error names
// the first bad entity in entity order (the one a serial check finds), for damage in the record
// itself and in one of its values, and a damaged entity in an early block wins over one in a
// later block.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "archive_reseal.h"
#include "compiled_scene.h"
#include "compiler/archive_builder.h"
#include "format/archive.h"
#include "format/scene_archive.h"
#include "test_support.h"

namespace pbrtc {
namespace {

class EntityCheck : public ::testing::Test {
 protected:
  // 40000 spheres: more than the 4 blocks of 8192 entities from which the check runs in parallel.
  static constexpr int kShapes = 40000;

  void SetUp() override {
    dir_ = testing_support::scratch_dir(
        std::string("EntityCheck.") +
        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::string text = "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n";
    for (int i = 0; i < kShapes; ++i)
      text += "Shape \"sphere\" \"float radius\" " + std::to_string(1 + i % 7) + "\n";
    text += "WorldEnd\n";
    const std::string scene = testing_support::write_file(dir_ + "/s.pbrt", text);
    CompiledScene c;
    compile_scene(scene, &c);
    ASSERT_TRUE(c.ok) << (c.errors.empty() ? "" : c.errors[0]);
    ArchiveOptions opt;
    opt.compress = false;
    std::string error;
    const std::string path = dir_ + "/good.pbrta";
    ASSERT_TRUE(write_archive(c.scene, c.files, directory_of(scene), path, opt, nullptr, &error))
        << error;
    good_ = testing_support::read_file(path);
    ASSERT_TRUE(archive_.load(path, 2, &error)) << error;
    ASSERT_GT(archive_.entities.size, 4u * 8192u);
    entities_ = testing_support::section_entry(archive_, pbrta::SectionKind::kEntities);
    values_ = testing_support::section_entry(archive_, pbrta::SectionKind::kValues);
    ASSERT_NE(entities_, pbrta::kNoIndex);
    ASSERT_NE(values_, pbrta::kNoIndex);
  }

  uint64_t offset_of(uint32_t section) const { return archive_.reader().entry(section).offset; }
  // Byte `field` of entity i's record set to v.
  void set_entity_byte(std::string* b, uint32_t i, size_t field, uint8_t v) const {
    (*b)[offset_of(entities_) + i * sizeof(pbrta::EntityRecord) + field] = char(v);
  }
  // The same error on 1 and 2 threads (after resealing the edited sections).
  std::string error_of(std::string bytes, uint32_t section) {
    const std::string path = dir_ + "/bad.pbrta";
    const std::string one = testing_support::reseal_and_load(bytes, section, path, 1);
    const std::string two = testing_support::reseal_and_load(bytes, section, path, 2);
    EXPECT_EQ(one, two);
    return two;
  }

  std::string dir_, good_;
  pbrta::SceneArchive archive_;
  uint32_t entities_ = 0, values_ = 0;
};

TEST_F(EntityCheck, FirstBadEntityInOrderOnEveryThreadCount) {
  // The shapes' entities are the last ones; these lie in different 8192-entity blocks.
  const uint32_t n = archive_.entities.size;
  const uint32_t early = n - 30001, late = n - 5;
  std::string b = good_;
  set_entity_byte(&b, late, offsetof(pbrta::EntityRecord, category), 200);
  const std::string late_only = error_of(b, entities_);
  EXPECT_NE(late_only.find("entity " + std::to_string(late) + ": category 200 unknown"),
            std::string::npos)
      << late_only;
  set_entity_byte(&b, early, offsetof(pbrta::EntityRecord, reserved0), 1);
  const std::string both = error_of(b, entities_);
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
  const std::string error = error_of(b, values_);
  EXPECT_NE(error.find("entity " + std::to_string(i) + ": sphere"), std::string::npos) << error;
  EXPECT_NE(error.find("unknown value flags"), std::string::npos) << error;
}

}  // namespace
}  // namespace pbrtc
