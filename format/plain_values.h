// A vector filter in front of the entity check's value loop (format/scene_validation.cpp). A
// value is plain when it has no unknown flag and no texture, its words lie within the words
// section, its count is the schema's arity or 0 (any for an array), and it is no string with
// words. Plain values pass every value rule, so an entity whose values are all plain skips the
// loop; any other takes it, for the rules and their messages. The one vector path format/ keeps:
// 6-8 us of the teapot's 81 us raw load (issue 39 allows one that saves over 5% of a real load).
#pragma once

#include <cstdint>
#include <vector>

#include "format/archive.h"
#include "format/schema.h"

namespace pbrta {

// One parameter as the filter reads it, laid out against a ValueRecord's 16 bytes.
struct PlainLanes {
  uint32_t width;      // words per value (kind_width)
  uint32_t arity;      // the count allowed besides 0 (0 for a string: none)
  uint32_t any_count;  // all ones for an array of any length
  uint32_t unused;
};

// A type's parameters as lanes, padded to an even count (the filter reads two at a time).
std::vector<PlainLanes> plain_lanes(const TypeSpec& type);
// True when this CPU runs the filter (AVX2); otherwise every entity takes the loop.
bool plain_filter_available();
// True when the n values at `values` are all plain against `lanes` (plain_lanes of their type)
// among num_words words. Reads no value past the n-th. Only with plain_filter_available().
bool plain_values(const ValueRecord* values, const PlainLanes* lanes, uint32_t n,
                  uint64_t num_words);

}  // namespace pbrta
