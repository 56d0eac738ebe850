#include "compiler/params.h"

#include <cstdint>

#include "format/huge_pages.h"

namespace pbrtc {

namespace {
struct TypeName {
  std::string_view name;
  ParamType type;
};
constexpr TypeName kTypeNames[] = {
    {"integer", ParamType::kInteger},     {"float", ParamType::kFloat},
    {"point2", ParamType::kPoint2},       {"vector2", ParamType::kVector2},
    {"point3", ParamType::kPoint3},       {"point", ParamType::kPoint3},
    {"vector3", ParamType::kVector3},     {"vector", ParamType::kVector3},
    {"normal", ParamType::kNormal3},      {"normal3", ParamType::kNormal3},
    {"bool", ParamType::kBool},           {"string", ParamType::kString},
    {"texture", ParamType::kTexture},     {"rgb", ParamType::kRgb},
    {"color", ParamType::kRgb},           {"xyz", ParamType::kXyz},
    {"blackbody", ParamType::kBlackbody}, {"spectrum", ParamType::kSpectrum},
};
}  // namespace

bool parse_param_type(std::string_view s, ParamType* t) {
  for (const TypeName& tn : kTypeNames)
    if (tn.name == s) {
      *t = tn.type;
      return true;
    }
  return false;
}

std::string_view param_type_name(ParamType t) {
  switch (t) {
    case ParamType::kInteger:
      return "integer";
    case ParamType::kFloat:
      return "float";
    case ParamType::kPoint2:
      return "point2";
    case ParamType::kVector2:
      return "vector2";
    case ParamType::kPoint3:
      return "point3";
    case ParamType::kVector3:
      return "vector3";
    case ParamType::kNormal3:
      return "normal";
    case ParamType::kBool:
      return "bool";
    case ParamType::kString:
      return "string";
    case ParamType::kTexture:
      return "texture";
    case ParamType::kRgb:
      return "rgb";
    case ParamType::kXyz:
      return "xyz";
    case ParamType::kBlackbody:
      return "blackbody";
    case ParamType::kSpectrum:
      return "spectrum";
  }
  return "?";
}

int param_type_stride(ParamType t) {
  switch (t) {
    case ParamType::kPoint2:
    case ParamType::kVector2:
    case ParamType::kBlackbody:
    case ParamType::kSpectrum:
      return 2;
    case ParamType::kPoint3:
    case ParamType::kVector3:
    case ParamType::kNormal3:
    case ParamType::kRgb:
    case ParamType::kXyz:
      return 3;
    default:
      return 1;
  }
}

bool param_type_is_spectrum(ParamType t) {
  return t == ParamType::kRgb || t == ParamType::kXyz || t == ParamType::kBlackbody ||
         t == ParamType::kSpectrum;
}

bool param_type_is_numeric(ParamType t) {
  return t != ParamType::kBool && t != ParamType::kString && t != ParamType::kTexture;
}

const ParsedParam* ParamList::find(std::string_view name) const {
  for (const ParsedParam& p : params)
    if (p.name == name) return &p;
  return nullptr;
}

std::vector<float>* ParamList::new_floats(uint32_t* index) {
  if (used_floats_ == float_pool_.size()) float_pool_.emplace_back();
  *index = uint32_t(used_floats_);
  std::vector<float>* v = &float_pool_[used_floats_++];
  v->clear();
  return v;
}

std::vector<uint32_t>* ParamList::new_ints(uint32_t* index) {
  if (used_ints_ == int_pool_.size()) int_pool_.emplace_back();
  *index = uint32_t(used_ints_);
  std::vector<uint32_t>* v = &int_pool_[used_ints_++];
  v->clear();
  return v;
}

namespace {
// Moves a pooled array out, leaving a same-sized reservation behind.
template <class T>
std::vector<T> take_pooled(std::vector<T>* slot) {
  std::vector<T> out;
  out.swap(*slot);
  // Reserving is only address space until written: the next mesh of similar
  // size parses without reallocating.
  slot->reserve(out.capacity());
  pbrta::advise_huge_pages(slot->data(), slot->capacity() * sizeof(T));
  // Do not hand the scene much unused capacity.
  if (out.capacity() > out.size() + out.size() / 4 + 1024) out.shrink_to_fit();
  return out;
}
}  // namespace

std::vector<uint32_t> ParamList::take_uints(const ParsedParam& p) const {
  return take_pooled(&int_pool_[p.offset]);
}

std::vector<float> ParamList::take_floats(const ParsedParam& p) const {
  return take_pooled(&float_pool_[p.offset]);
}

}  // namespace pbrtc
