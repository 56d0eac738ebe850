// format/schema_digest.h — the schema reduced to what the reader's per-value checks read.
//
// SceneArchive::validate checks every value of every entity (a million in a large scene). The
// schema (format/schema.h) is laid out for the compiler: names, defaults, aliases, a category
// lookup through a function. This digest keeps, per type and parameter, only the few numbers the
// checks compare against, flat and ready to index, so the hot loop touches nothing else.
// Built once, on first use; constant and safe to share between threads after that.
#pragma once

#include <cstdint>

#include "format/schema.h"

namespace pbrta {

struct ParamDigest {
  uint32_t arity;     // ParamSpec::arity: 0 (any count) or the exact count
  uint8_t width;      // 32-bit words per element: kind_width(kind)
  uint8_t texture;    // the Category a bound texture must have, or kNoTextureCategory
  uint8_t is_string;  // its words are string indices
  uint8_t reserved;
};
inline constexpr uint8_t kNoTextureCategory = 0xFF;

struct TypeDigest {
  const ParamDigest* params;
  uint16_t num_params;
  uint8_t has_strings;  // some parameter is a string: its words need the string-table check
  // Counts tied together across parameters (format/entity_rules.h): curve, heterogeneous, and a
  // fourier material's table.
  uint8_t has_rules;
  // What a vector check of two ValueRecords at once (offset, count, texture, flags; the same)
  // compares parameters 2k and 2k + 1 with: 32 uint32 per pair (an odd count's last parameter
  // pairs with padding), 32-byte aligned, in four vectors of eight lanes:
  //   mask and expect: a value passes when, lane by lane, (v & mask) == 0 or v == expect, with the
  //     texture lanes xored with kNoIndex first: mask ~0 and expect 0 there (no texture), ~0 and
  //     the arity on the counts (0 or the arity; mask 0 when the arity is 0: any count),
  //     ~kValueGiven and 0 on the flags;
  //   offset and width: the words it spans, (v & offset) + (v >> 32) * width in the two 64-bit
  //     lanes that hold an offset and its count (~0 on the offset, the width); 0 elsewhere.
  // A padding parameter's lanes are all 0: whatever its value, it passes.
  const uint32_t* value_lanes;
};

class SchemaDigest {
 public:
  uint32_t num_types(uint8_t category) const {
    return category < uint8_t(Category::kCount) ? num_types_[category] : 0;
  }
  // category < Category::kCount and type < num_types(category).
  const TypeDigest& type(uint8_t category, uint32_t type) const {
    return types_[first_type_[category] + type];
  }

 private:
  friend const SchemaDigest& schema_digest();
  SchemaDigest();
  uint32_t first_type_[uint32_t(Category::kCount)];
  uint32_t num_types_[uint32_t(Category::kCount)];
  TypeDigest* types_;
};

const SchemaDigest& schema_digest();

}  // namespace pbrta
