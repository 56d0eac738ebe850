// format/schema.h — the parameter schema of every pbrt-v3 entity type.
//
// pbrt-v3 describes every shape, material, texture, light, camera, sampler,
// film, filter, integrator, medium and accelerator by a type name and a list of
// named, typed parameters with defaults. This header is that list as data. The
// compiler checks scene text against it (a misspelled type is an error, an
// unknown parameter a warning) and resolves every parameter to a typed value
// with pbrt-v3's default applied. The archive stores an entity as its type
// index plus one value per schema parameter, in schema order, so a reader needs
// this table (and the spec in format/ARCHIVE.md reproduces it) but never a
// parameter name.
//
// The tables are constant, built at compile time, and safe to read from any
// thread. Appending a parameter at the end of a type's list, or a type at the
// end of a category, is a minor format change; reordering is a major one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <string_view>

namespace pbrta {

// Entity categories. Float and spectrum textures are separate namespaces in
// pbrt-v3 (the same name may be both), and their parameters differ in kind.
enum class Category : uint8_t {
  kShape,
  kMaterial,
  kFloatTexture,
  kSpectrumTexture,
  kLight,
  kAreaLight,
  kCamera,
  kSampler,
  kFilm,
  kFilter,
  kIntegrator,
  kMedium,
  kAccelerator,
  kCount
};

// The element kind of a resolved parameter value.
enum class Kind : uint8_t {
  kInt,          // int32
  kFloat,        // float32
  kBool,         // stored as int32 0/1
  kString,       // UTF-8 text (file names are resolved against the scene directory)
  kPoint2,       // 2 floats
  kVector2,      // 2 floats
  kPoint3,       // 3 floats
  kVector3,      // 3 floats
  kNormal3,      // 3 floats
  kRgb,          // 3 floats: a spectrum (rgb, xyz, blackbody or sampled) as linear RGB
  kFloatTex,     // a float constant, or a reference to a float texture
  kSpectrumTex,  // an RGB constant, or a reference to a spectrum texture
  kCount
};

// Flags on a parameter.
enum ParamFlag : uint8_t {
  kParamNone = 0,
  // Required: the entity is an error without it (trianglemesh "P", imagemap "filename").
  kParamRequired = 1u << 0,
  // The default depends on other parameters or on the scene (sphere "zmin" is
  // -radius, perspective "screenwindow" follows the aspect ratio). The record
  // keeps a "given" bit; the reader computes the default as the note says.
  kParamComputedDefault = 1u << 1,
  // A file name: resolved against the directory of the top-level scene file.
  kParamFilename = 1u << 2,
  // Bulk array data (mesh vertices, indices): the compiler moves it to the
  // geometry sections instead of keeping it in the record.
  kParamBulk = 1u << 3,
  // Derived: filled in by the compiler from a file the scene names (the
  // realistic camera's lens elements); a scene cannot set it.
  kParamDerived = 1u << 4,
};

// A default value. Scalars use v[0]; points, vectors and RGB use v[0..2]; fixed
// arrays (arity > 1) use v[0..arity-1] (at most 4); strings use s.
struct DefaultValue {
  float v[4] = {0, 0, 0, 0};
  const char* s = nullptr;
};

struct ParamSpec {
  std::string_view name;
  Kind kind;
  // 1 for a single value, N > 1 for exactly N values of the kind (the film's
  // "cropwindow" is kFloat with arity 4), 0 for an array of any length.
  uint8_t arity;
  uint8_t flags;
  DefaultValue def;
  // Another spelling pbrt-v3 accepts for the same parameter ("index" for
  // glass "eta", "st" for trianglemesh "uv"), or empty.
  std::string_view alias;
  // Why the default is what it is, when kParamComputedDefault is set.
  std::string_view note;
};

struct TypeSpec {
  std::string_view name;
  const ParamSpec* params;
  uint16_t num_params;
  // Another spelling pbrt-v3 accepts for this type ("lowdiscrepancy" for
  // "02sequence", "area" for "diffuse", "exinfinite" for "infinite"), or empty.
  std::string_view alias;
};

struct CategorySpec {
  std::string_view name;  // "shape", "material", ... as in messages
  const TypeSpec* types;
  uint16_t num_types;
};

// The whole schema, indexed by Category.
const CategorySpec& category_spec(Category c);

// Finds a type by name or alias; returns its index or -1.
int find_type(Category c, std::string_view name);

// Finds a parameter of a type by name or alias; returns its index or -1.
int find_param(const TypeSpec& t, std::string_view name);

// Where a resolved value of a kind is kept, and how many 32-bit words (or
// floats) one element takes: an Entity stores ints and bools as int32,
// strings as text (in an archive: a string index), everything else as floats.
enum class KindStore : uint8_t { kFloat, kInt, kString };
constexpr KindStore kind_store(Kind k) {
  return k == Kind::kInt || k == Kind::kBool ? KindStore::kInt
         : k == Kind::kString                ? KindStore::kString
                                             : KindStore::kFloat;
}
// A table, not a chain of compares: the reader looks it up for every value of every entity.
inline constexpr uint8_t kKindWidths[] = {1, 1, 1, 1, 2, 2, 3, 3, 3, 3, 1, 3};  // in Kind order
static_assert(std::size(kKindWidths) == size_t(Kind::kCount));
constexpr int kind_width(Kind k) {
  return kKindWidths[uint8_t(k)];
}

// Names for messages.
std::string_view kind_name(Kind k);
std::string_view category_name(Category c);

}  // namespace pbrta
