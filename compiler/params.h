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
  Loc loc;                     // of the declaration string
  Loc value_loc;               // of the first value
  uint32_t offset = 0;         // strings: first index in strings; numbers and bools: pooled array
  uint32_t count = 0;          // number of numbers or strings
  bool string_values = false;  // values are in strings (a "spectrum" may name a .spd file)
  mutable bool looked_up = false;
};

// Numeric and bool values live in one pooled array per parameter, so a bulk
// array (mesh vertices) can be moved into the scene instead of copied; the pool
// keeps a same-sized replacement so the next mesh parses without regrowing.
struct ParamList {
  std::vector<ParsedParam> params;
  std::vector<std::string_view> strings;
  std::vector<Loc> string_locs;
  // Stable storage for unescaped strings (deque: no reallocation moves them).
  std::deque<std::string> owned_strings;

  void clear() {
    params.clear();
    strings.clear();
    string_locs.clear();
    owned_strings.clear();
    used_floats_ = used_ints_ = 0;
  }
  const ParsedParam* find(std::string_view name) const;

  // For the parser: an empty pooled array; *index receives its number.
  std::vector<float>* new_floats(uint32_t* index);
  // Integers and bools are kept as their 32-bit two's-complement bits, so an
  // index array can be moved into a mesh's uint32 indices without a copy.
  std::vector<uint32_t>* new_ints(uint32_t* index);

  // Values of a numeric parameter (floats for float-valued types, ints for
  // integer and bool); p.offset is the pooled array's number.
  const float* floats_of(const ParsedParam& p) const { return float_pool_[p.offset].data(); }
  const int32_t* ints_of(const ParsedParam& p) const {
    return reinterpret_cast<const int32_t*>(int_pool_[p.offset].data());
  }
  // Moves a parameter's values out (the parameter must not be read again).
  std::vector<float> take_floats(const ParsedParam& p) const;
  std::vector<uint32_t> take_uints(const ParsedParam& p) const;

 private:
  mutable std::vector<std::vector<float>> float_pool_;
  mutable std::vector<std::vector<uint32_t>> int_pool_;
  size_t used_floats_ = 0, used_ints_ = 0;
};

}  // namespace pbrtc
