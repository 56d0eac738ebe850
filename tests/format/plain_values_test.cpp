// Tests for format/plain_values.h, the vector filter in front of the entity check's value loop:
// against the value rules written out here once more (an independent oracle), on every type of
// the schema, with each fault at each parameter and each edge a rule has; and it reads no value
// past the entity's last, even when that value ends a page.
#include "format/plain_values.h"

#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstring>
#include <string>
#include <vector>

namespace pbrta {
namespace {

constexpr uint32_t kWords = 1000;

// The value rules (ARCHIVE.md section 6) as the filter must apply them: true for a value that
// needs no closer look.
bool plain(const ValueRecord& v, const ParamSpec& ps) {
  if ((v.flags & ~uint32_t(kValueGiven)) != 0 || v.texture != kNoIndex) return false;
  if (uint64_t(v.offset) + uint64_t(v.count) * kind_width(ps.kind) > kWords) return false;
  if (ps.kind == Kind::kString) return v.count == 0;
  return ps.arity == 0 || v.count == 0 || v.count == ps.arity;
}

// A sound, plain value of ps: arrays of 5, fixed arities in full, strings without words.
ValueRecord sound(const ParamSpec& ps, uint32_t p) {
  const uint32_t count = ps.kind == Kind::kString ? 0 : ps.arity == 0 ? 5 : ps.arity;
  return {p * 3, count, kNoIndex, p % 2 ? uint32_t(kValueGiven) : 0};
}

constexpr Category kAll[] = {
    Category::kShape,           Category::kMaterial,   Category::kFloatTexture,
    Category::kSpectrumTexture, Category::kLight,      Category::kAreaLight,
    Category::kCamera,          Category::kSampler,    Category::kFilm,
    Category::kFilter,          Category::kIntegrator, Category::kMedium,
    Category::kAccelerator};

// Each way one value can be edited: every rule broken, and every rule's edge kept.
using Edit = void (*)(ValueRecord*, const ParamSpec&);
const Edit kEdits[] = {
    [](ValueRecord* v, const ParamSpec&) { v->flags |= 2; },
    [](ValueRecord* v, const ParamSpec&) { v->flags |= 0x80000000u; },
    [](ValueRecord* v, const ParamSpec&) { v->flags = kValueGiven; },
    [](ValueRecord* v, const ParamSpec&) { v->texture = 0; },
    [](ValueRecord* v, const ParamSpec&) { v->texture = kNoIndex - 1; },
    [](ValueRecord* v, const ParamSpec&) { v->count = 0; },
    [](ValueRecord* v, const ParamSpec&) { v->count += 1; },
    [](ValueRecord* v, const ParamSpec&) { v->count = v->count == 0 ? 1 : v->count - 1; },
    [](ValueRecord* v, const ParamSpec&) { v->count = 0xffffffffu; },
    [](ValueRecord* v, const ParamSpec& ps) {  // words end exactly at the table's end
      v->offset = uint32_t(kWords - uint64_t(v->count) * kind_width(ps.kind));
    },
    [](ValueRecord* v, const ParamSpec& ps) {  // one word past it
      v->offset = uint32_t(kWords + 1 - uint64_t(v->count) * kind_width(ps.kind));
    },
    [](ValueRecord* v, const ParamSpec&) { v->offset = 0xffffffffu; },
    [](ValueRecord* v, const ParamSpec&) { v->offset = 0; },
};

TEST(PlainValues, AgreeWithTheValueRulesOnEveryTypeAndParameter) {
  if (!plain_filter_available()) GTEST_SKIP() << "no AVX2: the filter never runs here";
  int refused = 0, passed = 0;
  for (Category c : kAll) {
    const CategorySpec& cs = category_spec(c);
    for (uint32_t t = 0; t < cs.num_types; ++t) {
      const TypeSpec& ts = cs.types[t];
      const std::vector<PlainLanes> lanes = plain_lanes(ts);
      ASSERT_EQ(lanes.size() % 2, 0u);
      std::vector<ValueRecord> values;
      for (uint32_t p = 0; p < ts.num_params; ++p) values.push_back(sound(ts.params[p], p));
      EXPECT_TRUE(plain_values(values.data(), lanes.data(), ts.num_params, kWords)) << ts.name;
      for (uint32_t p = 0; p < ts.num_params; ++p)
        for (Edit edit : kEdits) {
          std::vector<ValueRecord> edited = values;
          edit(&edited[p], ts.params[p]);
          const bool want = plain(edited[p], ts.params[p]);
          EXPECT_EQ(plain_values(edited.data(), lanes.data(), ts.num_params, kWords), want)
              << cs.name << " " << ts.name << " \"" << ts.params[p].name << "\" offset "
              << edited[p].offset << " count " << edited[p].count << " texture "
              << edited[p].texture << " flags " << edited[p].flags;
          (want ? passed : refused) += 1;
        }
    }
  }
  // Both answers were asked for many times, so that neither can pass by always being given.
  EXPECT_GT(refused, 1000);
  EXPECT_GT(passed, 1000);
}

// A type's values ending where the next page is unreadable: an odd count reads its last value
// alone, and a fault in the lane past it (the padding) judges nothing.
TEST(PlainValues, ReadNoValuePastTheLast) {
  if (!plain_filter_available()) GTEST_SKIP() << "no AVX2: the filter never runs here";
  const size_t page = size_t(sysconf(_SC_PAGESIZE));
  void* map = mmap(nullptr, 2 * page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  ASSERT_NE(map, MAP_FAILED);
  ASSERT_EQ(mprotect(static_cast<char*>(map) + page, page, PROT_NONE), 0);
  int odd_types = 0;
  for (Category c : kAll) {
    const CategorySpec& cs = category_spec(c);
    for (uint32_t t = 0; t < cs.num_types; ++t) {
      const TypeSpec& ts = cs.types[t];
      if (ts.num_params == 0 || ts.num_params * sizeof(ValueRecord) > page) continue;
      odd_types += ts.num_params % 2;
      ValueRecord* values =
          reinterpret_cast<ValueRecord*>(static_cast<char*>(map) + page) - ts.num_params;
      for (uint32_t p = 0; p < ts.num_params; ++p) values[p] = sound(ts.params[p], p);
      const std::vector<PlainLanes> lanes = plain_lanes(ts);
      EXPECT_TRUE(plain_values(values, lanes.data(), ts.num_params, kWords)) << ts.name;
      values[ts.num_params - 1].texture = 3;
      EXPECT_FALSE(plain_values(values, lanes.data(), ts.num_params, kWords)) << ts.name;
    }
  }
  EXPECT_GT(odd_types, 5);
  munmap(map, 2 * page);
}

}  // namespace
}  // namespace pbrta
