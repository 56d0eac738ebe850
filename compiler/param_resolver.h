// compiler/param_resolver.h — parsed parameters to typed, defaulted Entity values.
//
// Given a directive's type name and ParamList, the resolver finds the type in
// the schema (an unknown type is an error naming the category), fills every
// schema slot with pbrt-v3's default, then assigns each parameter the type
// knows: checking the declared type against the schema kind, the value count
// against the arity, resolving file names against the top-level scene's
// directory (a missing file is an error), spectra to RGB, and texture names to
// texture indices in the scope given. Parameters it consumes are marked
// looked_up; report_unused() warns about the rest, as pbrt-v3 does.
//
// Wrong declared types are warnings and the parameter is ignored (pbrt-v3 does
// not find it either and renders the default); wrong counts, undefined
// textures and missing files are errors (pbrt-v3 carries on with a default, a
// render that silently differs from the scene).
#pragma once

#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "compiler/diagnostics.h"
#include "compiler/params.h"
#include "compiler/scene_desc.h"

namespace pbrtc {

using NameMap = std::unordered_map<std::string, int32_t>;

// The named textures visible at a directive.
struct TextureScope {
  const NameMap* float_textures = nullptr;
  const NameMap* spectrum_textures = nullptr;
};

class ParamResolver {
 public:
  ParamResolver(Diagnostics* diag, std::string base_dir, std::vector<std::string>* input_files);

  // Finds type (name or alias) in category c and fills e with defaults.
  // Reports "unknown <category> type" at loc and returns false if unknown.
  bool begin(pbrta::Category c, std::string_view type, Loc loc, Entity* e);

  // Assigns every parameter of params the type knows. With skip_bulk, bulk
  // array parameters are only marked given (the caller copies them).
  void assign_all(Entity* e, const ParamList& params, const TextureScope& scope, bool skip_bulk);

  // Assigns one parsed parameter to slot (an existing value is replaced).
  // Returns false if it was rejected (already reported).
  bool assign(Entity* e, int slot, const ParsedParam& p, const ParamList& params,
              const TextureScope& scope);

  // Reports required parameters that were not given. False if any. A
  // parameter present in params but rejected was already reported.
  bool check_required(const Entity& e, Loc loc, const ParamList* params = nullptr);

  // Warns about every parameter nothing looked up. what: "sphere shape".
  void report_unused(const ParamList& params, const Entity* e);

  const std::string& base_dir() const { return base_dir_; }
  // True once a pbrt-v4 type name was reported: later messages may say the scene is pbrt-v4's.
  bool saw_pbrt_v4_names() const { return !v4_names_seen_.empty(); }
  // Records a file the compile read (deduplicated, in first-read order).
  void note_input(const std::string& path);

 private:
  bool spectrum_to_rgb(const ParsedParam& p, const ParamList& params, std::vector<float>* rgb);
  void warn_wrong_type(const Entity& e, const pbrta::ParamSpec& ps, const ParsedParam& p);

  Diagnostics* diag_;
  std::string base_dir_;
  std::vector<std::string>* input_files_;
  std::unordered_map<std::string, std::array<float, 3>> spd_cache_;
  std::unordered_set<std::string> v4_names_seen_;  // "material diffuse": hinted once each
};

// "sphere shape", "matte material": how messages name an entity's type.
std::string describe_type(const Entity& e);

}  // namespace pbrtc
