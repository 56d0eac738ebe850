// compiler/pbrt_v4_names.h — pbrt-v4's type names, and what pbrt-v3 calls the nearest thing.
//
// pbrt-v4 is what most people download today, and its scenes reach pbrtc as pbrt-v3 scenes with
// unknown types (Film "rgb", Material "diffuse", Sampler "zsobol"). An "unknown type" error alone
// leaves the user guessing; naming the pbrt-v4 origin and pbrt-v3's equivalent says what to
// change. The table lists only names pbrt-v4 has and pbrt-v3 lacks (from pbrt-v4's scene-file
// documentation and its type registries); names both share never reach it.
//
// Thread safety: a constant table; reentrant.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "format/schema.h"

namespace pbrtc {

// One name pbrt-v4 has and pbrt-v3 lacks.
struct PbrtV4Name {
  pbrta::Category category;  // textures are listed once, as spectrum textures
  std::string_view v4;
  std::string_view v3;   // pbrt-v3's nearest type; "" when it has none
  std::string_view how;  // what differs, when the equivalent is only near ("" when the same)
};

// The whole table, for tests that check every pbrt-v3 name in it is one pbrtc knows.
const PbrtV4Name* pbrt_v4_names(size_t* count);

// If type is a pbrt-v4 name in category c that pbrt-v3 lacks: true, and *hint is the
// parenthetical for the error, e.g. `a pbrt-v4 name; pbrt-v3 calls it "matte"` or
// `a pbrt-v4 name; pbrt-v3 has no equivalent`. False otherwise (*hint untouched).
bool pbrt_v4_type_hint(pbrta::Category c, std::string_view type, std::string* hint);

}  // namespace pbrtc
