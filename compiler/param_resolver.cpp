#include "compiler/param_resolver.h"

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "compiler/parser.h"
#include "compiler/pbrt_v4_names.h"
#include "compiler/spectrum.h"

namespace pbrtc {

using pbrta::Category;
using pbrta::Kind;
using pbrta::ParamSpec;
using pbrta::TypeSpec;

namespace {

bool file_exists(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

std::string param_desc(const ParsedParam& p) {
  return "\"" + std::string(p.type_name) + " " + std::string(p.name) + "\"";
}

using Store = pbrta::KindStore;
constexpr Store store_of(Kind k) {
  return pbrta::kind_store(k);
}
constexpr int width_of(Kind k) {
  return pbrta::kind_width(k);
}

size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] != b[j - 1])});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

// pbrt-v4's built-in spectrum names; pbrt-v3 only reads .spd files.
bool looks_like_v4_named_spectrum(std::string_view s) {
  for (std::string_view prefix : {"metal-", "glass-", "stdillum-", "illum-", "canon_", "nikon_",
                                  "sony_", "aces_", "ntsc", "srgb"})
    if (s.substr(0, prefix.size()) == prefix) return true;
  return false;
}

// Whether a parameter declared as t is what pbrt-v3 looks up for ps.
bool type_fits(const ParamSpec& ps, ParamType t) {
  switch (ps.kind) {
    case Kind::kInt:
      return t == ParamType::kInteger;
    case Kind::kFloat:
      return t == ParamType::kFloat;
    case Kind::kBool:
      return t == ParamType::kBool;
    case Kind::kString:
      return t == ParamType::kString;
    case Kind::kPoint2:
    case Kind::kVector2:
      // trianglemesh "float uv" / "float st": a flat list of pairs.
      return t == ParamType::kPoint2 || t == ParamType::kVector2 ||
             (ps.arity == 0 && t == ParamType::kFloat);
    case Kind::kPoint3:
      return t == ParamType::kPoint3;
    case Kind::kVector3:
      return t == ParamType::kVector3;
    case Kind::kNormal3:
      return t == ParamType::kNormal3;
    case Kind::kRgb:
      return param_type_is_spectrum(t);
    case Kind::kFloatTex:
      return t == ParamType::kFloat || t == ParamType::kTexture;
    case Kind::kSpectrumTex:
      return param_type_is_spectrum(t) || t == ParamType::kTexture;
    default:
      return false;
  }
}

// How a scene file declares a parameter of kind k ("integer", not "int").
std::string declared_as(Kind k) {
  switch (k) {
    case Kind::kInt:
      return "integer";
    case Kind::kFloatTex:
      return "float or texture";
    case Kind::kSpectrumTex:
      return "rgb, spectrum or texture";
    case Kind::kRgb:
      return "rgb or spectrum";
    default:
      return std::string(pbrta::kind_name(k));
  }
}

}  // namespace

void ParamResolver::warn_wrong_type(const Entity& e, const ParamSpec& ps, const ParsedParam& p) {
  diag_->warning(p.loc, "parameter " + param_desc(p) + " of " + describe_type(e) + " should be " +
                            declared_as(ps.kind) +
                            "; it is ignored (pbrt-v3 does not use it either)");
}

std::string describe_type(const Entity& e) {
  std::string t = std::string(e.type_name());
  return (t.empty() ? std::string("\"\"") : t) + " " +
         std::string(pbrta::category_name(e.category));
}

ParamResolver::ParamResolver(Diagnostics* diag, std::string base_dir,
                             std::vector<std::string>* input_files)
    : diag_(diag), base_dir_(std::move(base_dir)), input_files_(input_files) {}

void ParamResolver::note_input(const std::string& path) {
  if (!input_files_) return;
  if (std::find(input_files_->begin(), input_files_->end(), path) == input_files_->end())
    input_files_->push_back(path);
}

bool ParamResolver::begin(Category c, std::string_view type, Loc loc, Entity* e) {
  int t = pbrta::find_type(c, type);
  if (t < 0) {
    std::string msg =
        "unknown " + std::string(pbrta::category_name(c)) + " type \"" + std::string(type) + "\"";
    std::string v4_hint;
    if (pbrt_v4_type_hint(c, type, &v4_hint)) {
      // Each pbrt-v4 name is explained where it first appears; its later uses only say whence.
      const std::string key = std::string(pbrta::category_name(c)) + " " + std::string(type);
      const bool first = v4_names_seen_.insert(key).second;
      msg += " (" + (first ? v4_hint : std::string("a pbrt-v4 name")) + ")";
      diag_->error(loc, msg);
      return false;
    }
    // A near miss is almost always a typo: name it.
    const pbrta::CategorySpec& cs = pbrta::category_spec(c);
    std::string_view best;
    size_t best_d = 3;
    for (uint16_t i = 0; i < cs.num_types; ++i) {
      size_t d = edit_distance(type, cs.types[i].name);
      if (d < best_d) best_d = d, best = cs.types[i].name;
    }
    if (!best.empty()) msg += " (did you mean \"" + std::string(best) + "\"?)";
    diag_->error(loc, msg);
    return false;
  }
  e->category = c;
  e->type = t;
  e->loc = loc;
  e->floats.clear();
  e->ints.clear();
  e->strings.clear();
  const TypeSpec& ts = e->spec();
  e->values.assign(ts.num_params, Value{});
  for (uint16_t i = 0; i < ts.num_params; ++i) {
    const ParamSpec& ps = ts.params[i];
    Value& v = e->values[i];
    if (ps.arity == 0 || (ps.flags & pbrta::kParamRequired)) continue;  // no default array
    int n = ps.arity;
    switch (store_of(ps.kind)) {
      case Store::kInt:
        v.offset = uint32_t(e->ints.size());
        for (int k = 0; k < n; ++k) e->ints.push_back(int32_t(ps.def.v[k]));
        break;
      case Store::kString:
        v.offset = uint32_t(e->strings.size());
        e->strings.push_back(ps.def.s ? ps.def.s : "");
        n = 1;
        break;
      case Store::kFloat: {
        v.offset = uint32_t(e->floats.size());
        int w = width_of(ps.kind);
        if (n == 1)
          for (int k = 0; k < w; ++k) e->floats.push_back(ps.def.v[w == 1 ? 0 : k]);
        else
          for (int k = 0; k < n * w && k < 4; ++k) e->floats.push_back(ps.def.v[k]);
        break;
      }
    }
    v.count = uint32_t(n);
  }
  return true;
}

bool ParamResolver::spectrum_to_rgb(const ParsedParam& p, const ParamList& params,
                                    std::vector<float>* rgb) {
  const float* f = params.floats_of(p);
  switch (p.type) {
    case ParamType::kRgb:
      rgb->insert(rgb->end(), f, f + p.count);
      return true;
    case ParamType::kXyz:
      for (uint32_t i = 0; i < p.count; i += 3) {
        Rgb c = rgb_from_xyz(f + i);
        rgb->insert(rgb->end(), {c.r, c.g, c.b});
      }
      return true;
    case ParamType::kBlackbody:
      for (uint32_t i = 0; i < p.count; i += 2) {
        if (f[i] <= 0) {
          char kelvin[32];
          std::snprintf(kelvin, sizeof kelvin, "%g", double(f[i]));
          diag_->error(p.value_loc,
                       "blackbody temperature must be positive, got " + std::string(kelvin) + " K");
          return false;
        }
        Rgb c = rgb_from_blackbody(f[i], f[i + 1]);
        rgb->insert(rgb->end(), {c.r, c.g, c.b});
      }
      return true;
    default:
      return false;
  }
}

bool ParamResolver::assign(Entity* e, int slot, const ParsedParam& p, const ParamList& params,
                           const TextureScope& scope) {
  const ParamSpec& ps = e->spec().params[slot];
  p.looked_up = true;
  Kind k = ps.kind;
  ParamType t = p.type;
  if (!type_fits(ps, t)) {
    warn_wrong_type(*e, ps, p);
    return false;
  }
  Value v;
  v.given = true;
  // Textures.
  if (t == ParamType::kTexture) {
    if (p.count != 1) {
      diag_->error(p.value_loc, "parameter " + param_desc(p) + " names one texture, got " +
                                    std::to_string(p.count));
      return false;
    }
    std::string name(params.strings[p.offset]);
    bool is_float = k == Kind::kFloatTex;
    const NameMap* map = is_float ? scope.float_textures : scope.spectrum_textures;
    auto it = map ? map->find(name) : NameMap::const_iterator();
    if (!map || it == map->end()) {
      const NameMap* other = is_float ? scope.spectrum_textures : scope.float_textures;
      std::string msg = "undefined " + std::string(is_float ? "float" : "spectrum") +
                        " texture \"" + name + "\" for parameter " + param_desc(p);
      if (other && other->count(name))
        msg += " (there is a " + std::string(is_float ? "spectrum" : "float") +
               " texture of that name)";
      diag_->error(params.string_locs[p.offset], msg);
      return false;
    }
    if (it->second == kNone) return false;  // its definition failed, and said why
    v.texture = it->second;
    // The constant slot keeps the default so a reader always finds a value.
    v.offset = uint32_t(e->floats.size());
    v.count = 1;
    for (int i = 0; i < width_of(k); ++i) e->floats.push_back(ps.def.v[width_of(k) == 1 ? 0 : i]);
    e->values[slot] = v;
    return true;
  }
  // Element count.
  uint32_t elems;
  std::vector<float> rgb;
  if (k == Kind::kRgb || k == Kind::kSpectrumTex) {
    // A string-valued spectrum names an .spd file.
    if (t == ParamType::kSpectrum && p.string_values) {
      if (p.count != 1) {
        diag_->error(p.value_loc, "parameter " + param_desc(p) + " names one .spd file, got " +
                                      std::to_string(p.count));
        return false;
      }
      std::string name(params.strings[p.offset]);
      std::string path = resolve_path(base_dir_, name);
      auto cached = spd_cache_.find(path);
      if (cached == spd_cache_.end()) {
        if (!file_exists(path)) {
          if (looks_like_v4_named_spectrum(name))
            diag_->error(p.value_loc, "named spectrum \"" + name +
                                          "\" is pbrt-v4 syntax; pbrt-v3 reads spectra from "
                                          ".spd files");
          else
            diag_->error(p.value_loc, "cannot open spectrum file \"" + path + "\"");
          return false;
        }
        std::ifstream in(path, std::ios::binary);
        std::stringstream ss;
        ss << in.rdbuf();
        std::vector<float> lambda, value;
        SpdError err;
        if (!parse_spd(ss.str(), &lambda, &value, &err)) {
          diag_->error(p.value_loc, "spectrum file \"" + path + "\":" + std::to_string(err.line) +
                                        ":" + std::to_string(err.column) + ": " + err.message);
          return false;
        }
        Rgb c = rgb_from_sampled(lambda.data(), value.data(), lambda.size());
        note_input(path);
        cached = spd_cache_.emplace(path, std::array<float, 3>{c.r, c.g, c.b}).first;
      }
      rgb.assign(cached->second.begin(), cached->second.end());
    } else if (t == ParamType::kSpectrum) {
      const float* f = params.floats_of(p);
      std::vector<float> lambda, value;
      for (uint32_t i = 0; i < p.count; i += 2) {
        lambda.push_back(f[i]);
        value.push_back(f[i + 1]);
      }
      Rgb c = rgb_from_sampled(lambda.data(), value.data(), lambda.size());
      rgb = {c.r, c.g, c.b};
    } else if (!spectrum_to_rgb(p, params, &rgb)) {
      return false;
    }
    elems = uint32_t(rgb.size() / 3);
  } else if (store_of(k) == Store::kFloat) {
    int w = width_of(k);
    if (p.count % w != 0) {
      diag_->error(p.value_loc, "parameter " + param_desc(p) + " needs " + std::to_string(w) +
                                    " numbers per element, got " + std::to_string(p.count));
      return false;
    }
    elems = p.count / uint32_t(w);
  } else {
    elems = p.count;
  }
  if (ps.arity > 0 && elems != ps.arity) {
    diag_->error(
        p.value_loc,
        "parameter " + param_desc(p) + " of " + describe_type(*e) + " takes " +
            (ps.arity == 1 ? std::string("one value") : std::to_string(ps.arity) + " values") +
            ", got " + std::to_string(elems));
    return false;
  }
  switch (store_of(k)) {
    case Store::kInt:
      v.offset = uint32_t(e->ints.size());
      e->ints.insert(e->ints.end(), params.ints_of(p), params.ints_of(p) + p.count);
      break;
    case Store::kString:
      v.offset = uint32_t(e->strings.size());
      for (uint32_t i = 0; i < p.count; ++i) {
        std::string s(params.strings[p.offset + i]);
        if (ps.flags & pbrta::kParamFilename) {
          std::string path = resolve_path(base_dir_, s);
          if (!file_exists(path)) {
            diag_->error(params.string_locs[p.offset + i],
                         "cannot open file \"" + path + "\" named by parameter " + param_desc(p));
            return false;
          }
          note_input(path);
          s = path;
        }
        e->strings.push_back(std::move(s));
      }
      break;
    case Store::kFloat:
      v.offset = uint32_t(e->floats.size());
      if (!rgb.empty())
        e->floats.insert(e->floats.end(), rgb.begin(), rgb.end());
      else
        e->floats.insert(e->floats.end(), params.floats_of(p), params.floats_of(p) + p.count);
      break;
  }
  v.count = elems;
  e->values[slot] = v;
  return true;
}

void ParamResolver::assign_all(Entity* e, const ParamList& params, const TextureScope& scope,
                               bool skip_bulk) {
  const TypeSpec& ts = e->spec();
  for (const ParsedParam& p : params.params) {
    int slot = pbrta::find_param(ts, p.name);
    if (slot < 0 || (ts.params[slot].flags & pbrta::kParamDerived)) continue;
    // pbrt-v3 reads a parameter's own name first and its alias only in its absence: an alias
    // given beside its parameter is ignored, whatever their order.
    if (p.name != ts.params[slot].name && params.find(ts.params[slot].name)) {
      p.looked_up = true;
      continue;
    }
    if (skip_bulk && (ts.params[slot].flags & pbrta::kParamBulk)) {
      p.looked_up = true;
      if (!type_fits(ts.params[slot], p.type)) {
        warn_wrong_type(*e, ts.params[slot], p);
        continue;
      }
      e->values[slot].given = true;
      continue;
    }
    assign(e, slot, p, params, scope);
  }
}

bool ParamResolver::check_required(const Entity& e, Loc loc, const ParamList* params) {
  const TypeSpec& ts = e.spec();
  bool ok = true;
  for (uint16_t i = 0; i < ts.num_params; ++i) {
    if ((ts.params[i].flags & pbrta::kParamRequired) && !e.values[i].given) {
      ok = false;
      // Given with the right type but rejected: that was reported as an
      // error. Given with the wrong type was only a warning.
      const ParsedParam* p = params ? params->find(ts.params[i].name) : nullptr;
      if (!p && params && !ts.params[i].alias.empty()) p = params->find(ts.params[i].alias);
      if (p && type_fits(ts.params[i], p->type)) continue;
      diag_->error(loc, describe_type(e) + " needs parameter \"" + declared_as(ts.params[i].kind) +
                            " " + std::string(ts.params[i].name) + "\"");
    }
  }
  return ok;
}

void ParamResolver::report_unused(const ParamList& params, const Entity* e) {
  for (const ParsedParam& p : params.params) {
    if (p.looked_up) continue;
    std::string msg = "parameter " + param_desc(p) + " is not used";
    if (e) {
      msg += " by " + describe_type(*e);
      const TypeSpec& ts = e->spec();
      std::string_view best;
      size_t best_d = 3;
      for (uint16_t i = 0; i < ts.num_params; ++i) {
        size_t d = edit_distance(p.name, ts.params[i].name);
        if (d < best_d && d < p.name.size()) best_d = d, best = ts.params[i].name;
      }
      if (!best.empty()) msg += " (did you mean \"" + std::string(best) + "\"?)";
    }
    diag_->warning(p.loc, msg);
  }
}

}  // namespace pbrtc
