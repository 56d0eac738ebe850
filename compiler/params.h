// compiler/params.h — the parameter list of one directive, as written.
//
// A directive's parameters ("float fov" 45, "rgb Kd" [.5 .5 .5]) are parsed into
// one ParamList whose value arrays are reused from directive to directive: the
// parser clears it, never frees it, so the common path allocates nothing. Each
// ParsedParam records its declared type, name, where its values sit in the
// shared arrays, and a looked_up flag: whatever nothing consumed is reported as
// unused, which is how typos in scene files surface.
//
// Views (type, name, string values) point into the mapped scene file, or into
// ParamList::owned_strings when the lexer had to unescape them; both outlive
// the directive's handling.
#pragma once

#include <cstdint>
#include <deque>
#include <string>
#include <string_view>
#include <vector>

#include "compiler/source_files.h"

namespace pbrtc {

// Declared parameter types, as pbrt-v3 spells them.
enum class ParamType : uint8_t {
  kInteger,
  kFloat,
  kPoint2,
  kVector2,
  kPoint3,
  kVector3,
  kNormal3,
  kBool,
  kString,
  kTexture,
  kRgb,        // "rgb" and "color"
  kXyz,        // "xyz"
  kBlackbody,  // "blackbody": (temperature K, scale) pairs in pbrt-v3
  kSpectrum,   // "spectrum": (lambda, value) pairs or a .spd file name
};

// Parses a declared type; false if unknown.
bool parse_param_type(std::string_view s, ParamType* t);
std::string_view param_type_name(ParamType t);
// Values per element: 3 for point3/rgb, 2 for point2 and spectrum/blackbody pairs.
int param_type_stride(ParamType t);
bool param_type_is_spectrum(ParamType t);
bool param_type_is_numeric(ParamType t);

struct ParsedParam {
  ParamType type;
  std::string_view type_name;  // as written ("color", "point")
  std::string_view name;
  Loc loc;        // of the declaration string
  Loc value_loc;  // of the first value
  uint32_t offset = 0;  // into floats / ints / strings, by type
  uint32_t count = 0;   // number of numbers or strings
  bool string_values = false;  // values are in strings (a "spectrum" may name a .spd file)
  mutable bool looked_up = false;
};

struct ParamList {
  std::vector<ParsedParam> params;
  std::vector<float> floats;
  std::vector<int32_t> ints;  // integers and bools (0/1)
  std::vector<std::string_view> strings;
  std::vector<Loc> string_locs;
  // Stable storage for unescaped strings (deque: no reallocation moves them).
  std::deque<std::string> owned_strings;

  void clear() {
    params.clear();
    floats.clear();
    ints.clear();
    strings.clear();
    string_locs.clear();
    owned_strings.clear();
  }
  const ParsedParam* find(std::string_view name) const;
};

}  // namespace pbrtc
