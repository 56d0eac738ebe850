#include "format/schema_digest.h"

#include <new>

#include "format/archive.h"
#include "format/entity_rules.h"

namespace pbrta {

SchemaDigest::SchemaDigest() {
  uint32_t total_types = 0, total_params = 0;
  for (uint32_t c = 0; c < uint32_t(Category::kCount); ++c) {
    const CategorySpec& cs = category_spec(Category(c));
    first_type_[c] = total_types;
    num_types_[c] = cs.num_types;
    total_types += cs.num_types;
    for (uint32_t t = 0; t < cs.num_types; ++t) total_params += cs.types[t].num_params;
  }
  // Allocated once and never freed, like the schema it digests: loads on other threads may still
  // read it while the process exits, after a static destructor would have run.
  types_ = new TypeDigest[total_types];
  ParamDigest* p = new ParamDigest[total_params];
  // 32 per pair of parameters or odd one out: at most 32 per parameter; 32-byte aligned for the
  // vector loads.
  uint32_t* lanes = new (std::align_val_t(32)) uint32_t[32 * total_params]();
  for (uint32_t c = 0; c < uint32_t(Category::kCount); ++c) {
    const CategorySpec& cs = category_spec(Category(c));
    for (uint32_t t = 0; t < cs.num_types; ++t) {
      const TypeSpec& ts = cs.types[t];
      TypeDigest& td = types_[first_type_[c] + t];
      td.params = p;
      td.num_params = ts.num_params;
      td.has_strings = 0;
      td.has_rules = count_rule_of(Category(c), t) != CountRule::kNone;
      for (uint32_t k = 0; k < ts.num_params; ++k, ++p) {
        const ParamSpec& ps = ts.params[k];
        p->arity = ps.arity;
        p->width = uint8_t(kind_width(ps.kind));
        p->texture = ps.kind == Kind::kFloatTex      ? uint8_t(Category::kFloatTexture)
                     : ps.kind == Kind::kSpectrumTex ? uint8_t(Category::kSpectrumTexture)
                                                     : kNoTextureCategory;
        p->is_string = ps.kind == Kind::kString;
        p->reserved = 0;
        td.has_strings |= p->is_string;
      }
      // The pairs' lanes (schema_digest.h), from the parameters just digested: the four vectors
      // of a pair start 8 lanes apart, and a value's fields sit 4 (k % 2) lanes into each.
      enum : uint32_t { kMask = 0, kExpect = 8, kOffset = 16, kWidth = 24 };
      enum : uint32_t { kOffsetField = 0, kCountField = 1, kTextureField = 2, kFlagsField = 3 };
      td.value_lanes = lanes;
      for (uint32_t k = 0; k < ts.num_params; ++k) {
        uint32_t* value = lanes + 32 * (k / 2) + 4 * (k % 2);
        const ParamDigest& pd = td.params[k];
        value[kMask + kTextureField] = ~0u;
        value[kMask + kCountField] = pd.arity != 0 ? ~0u : 0;
        value[kExpect + kCountField] = pd.arity;
        value[kMask + kFlagsField] = ~uint32_t(kValueGiven);
        value[kOffset + kOffsetField] = ~0u;
        // The offset's 64-bit lane: the vector multiply reads the low half of each.
        value[kWidth + kOffsetField] = pd.width;
      }
      lanes += 32 * ((ts.num_params + 1) / 2);
    }
  }
}

const SchemaDigest& schema_digest() {
  static const SchemaDigest digest;
  return digest;
}

}  // namespace pbrta
