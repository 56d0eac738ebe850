#include "format/schema_digest.h"

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
  uint32_t* lanes = new uint32_t[8 * total_params]();  // 16 per pair: at most 8 per parameter
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
      // The pairs' lanes, from the parameters just digested.
      td.pair_lanes = lanes;
      for (uint32_t k = 0; k + 1 < td.num_params; k += 2, lanes += 16)
        for (uint32_t j = 0; j < 2; ++j) {
          lanes[1 + 4 * j] = td.params[k + j].arity;
          lanes[8 + 4 * j] = td.params[k + j].width;
        }
    }
  }
}

const SchemaDigest& schema_digest() {
  static const SchemaDigest digest;
  return digest;
}

}  // namespace pbrta
