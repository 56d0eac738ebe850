// tools/mesh/obj_scene.cpp — OBJ + MTL parsing and the pbrt-v3 directives obj2pbrt writes.
//
// The parser works on logical lines (physical lines joined where one ends in `\`), split into
// whitespace-separated tokens, with `#` starting a comment where it starts a token. OBJ data is
// global (indices count every v/vt/vn read so far, whatever the group), so the three arrays are
// kept for the whole file and each shape remaps the triples it uses to vertices of its own.
// The mapping to pbrt-v3 follows pbrt-v3's src/tools/obj2pbrt.cpp; where this file differs from
// it, a comment says why.
#include "tools/mesh/obj_scene.h"

#include <fast_float/fast_float.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string_view>
#include <type_traits>
#include <unordered_map>
#include <utility>

#include "compiler/ply_writer.h"

namespace meshtools {
namespace {

namespace fs = std::filesystem;

// ---- Text ------------------------------------------------------------------------------------

bool read_text(const std::string& path, std::string* text, std::string* error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    *error = path + ": cannot open: " + std::strerror(errno);
    return false;
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) {
    *error = path + ": read error";
    return false;
  }
  *text = ss.str();
  return true;
}

std::string join_path(const std::string& dir, const std::string& name) {
  if (name.empty() || name[0] == '/' || dir.empty()) return name;
  return (fs::path(dir) / name).lexically_normal().string();
}

std::string dir_of(const std::string& path) {
  return fs::path(path).parent_path().string();
}

// Calls fn(line_number, tokens) for each logical line that has tokens. A physical line ending in
// `\` continues on the next one (the line number reported is the first one's). Returns false
// with *error set when fn does, or on a control byte (a binary file is not OBJ text).
template <typename Fn>
bool for_each_line(const std::string& display, const std::string& text, std::string* error, Fn fn) {
  std::string logical;
  std::vector<std::string_view> tokens;
  size_t pos = 0;
  int line = 1;
  while (pos < text.size()) {
    const int first_line = line;
    logical.clear();
    for (;;) {
      size_t end = text.find('\n', pos);
      if (end == std::string::npos) end = text.size();
      size_t stop = end;
      if (stop > pos && text[stop - 1] == '\r') --stop;
      std::string_view phys(text.data() + pos, stop - pos);
      for (char c : phys) {
        unsigned char u = static_cast<unsigned char>(c);
        if (u < 0x20 && c != '\t' && c != '\v' && c != '\f') {
          char buf[64];
          std::snprintf(buf, sizeof buf, "control byte 0x%02x: is this a text file?", u);
          *error = display + ":" + std::to_string(line) + ": " + buf;
          return false;
        }
      }
      pos = end < text.size() ? end + 1 : end;
      if (!phys.empty() && phys.back() == '\\' && pos < text.size()) {
        logical.append(phys.substr(0, phys.size() - 1));
        logical.push_back(' ');
        ++line;
        continue;
      }
      if (!phys.empty() && phys.back() == '\\') phys.remove_suffix(1);  // `\` at end of file
      logical.append(phys);
      ++line;
      break;
    }
    tokens.clear();
    size_t i = 0;
    while (i < logical.size()) {
      while (i < logical.size() && std::isspace(static_cast<unsigned char>(logical[i]))) ++i;
      if (i >= logical.size() || logical[i] == '#') break;  // `#` starting a token: a comment
      size_t s = i;
      while (i < logical.size() && !std::isspace(static_cast<unsigned char>(logical[i]))) ++i;
      tokens.emplace_back(logical.data() + s, i - s);
    }
    if (tokens.empty()) continue;
    std::string message;
    if (!fn(first_line, tokens, &message)) {
      *error = display + ":" + std::to_string(first_line) + ": " + message;
      return false;
    }
  }
  return true;
}

std::string joined(const std::vector<std::string_view>& tokens, size_t from) {
  std::string s;
  for (size_t i = from; i < tokens.size(); ++i) {
    if (i > from) s.push_back(' ');
    s.append(tokens[i]);
  }
  return s;
}

std::string in_quotes(std::string_view s) {
  return "\"" + std::string(s) + "\"";
}

// A finite float; OBJ writers emit "+1" now and then, which fast_float does not take.
bool parse_float(std::string_view tok, float* out, std::string* message) {
  std::string_view t = tok;
  if (t.size() > 1 && t[0] == '+' && t[1] != '-' && t[1] != '+') t.remove_prefix(1);
  double d = 0;
  auto r = fast_float::from_chars(t.data(), t.data() + t.size(), d);
  if (r.ec != std::errc() || r.ptr != t.data() + t.size()) {
    if (r.ptr == t.data() + t.size() && std::isinf(d)) {
      *message = "number " + in_quotes(tok) + " is out of range";
      return false;
    }
    *message = "expected a number, found " + in_quotes(tok);
    return false;
  }
  if (std::isnan(d)) {
    *message = "number " + in_quotes(tok) + " is NaN";
    return false;
  }
  if (!std::isfinite(d) || std::fabs(d) > FLT_MAX) {
    *message = "number " + in_quotes(tok) + " is out of range";
    return false;
  }
  *out = static_cast<float>(d);
  return true;
}

bool parse_floats(const std::vector<std::string_view>& tokens, size_t from, size_t min_count,
                  size_t max_count, const char* what, std::vector<float>* out,
                  std::string* message) {
  size_t n = tokens.size() - from;
  if (n < min_count || n > max_count) {
    *message = std::string(what) + " needs " + std::to_string(min_count) +
               (min_count == max_count ? "" : " to " + std::to_string(max_count)) +
               " numbers, found " + std::to_string(n);
    return false;
  }
  out->clear();
  for (size_t i = from; i < tokens.size(); ++i) {
    float f = 0;
    if (!parse_float(tokens[i], &f, message)) {
      *message = std::string(what) + ": " + *message;
      return false;
    }
    out->push_back(f);
  }
  return true;
}

// ---- MTL -------------------------------------------------------------------------------------

class WarningSink {
 public:
  explicit WarningSink(std::vector<std::string>* out) : out_(out) {}
  // Reports "display:line: text" the first time `key` is seen in this file.
  void once(const std::string& display, int line, const std::string& key, const std::string& text) {
    if (seen_.insert(display + '\n' + key).second)
      out_->push_back(display + ":" + std::to_string(line) + ": " + text);
  }
  void always(const std::string& display, int line, const std::string& text) {
    out_->push_back(display + ":" + std::to_string(line) + ": " + text);
  }

 private:
  std::vector<std::string>* out_;
  std::set<std::string> seen_;
};

// A map statement's file name: what follows its options. The options are skipped with their
// arguments (pbrt-v3's imagemap has no counterpart for them; tinyobjloader would take them
// as part of the file name).
bool map_file_name(const std::vector<std::string_view>& tokens, std::string* name,
                   bool* had_options, std::string* message) {
  // Options with their maximum argument count; -o, -s and -t take 1 to 3 numbers.
  static const std::map<std::string_view, int> kOptions = {
      {"-blendu", 1},  {"-blendv", 1}, {"-boost", 1},  {"-mm", 2},    {"-o", 3},
      {"-s", 3},       {"-t", 3},      {"-texres", 1}, {"-clamp", 1}, {"-bm", 1},
      {"-imfchan", 1}, {"-type", 1},   {"-cc", 1}};
  size_t i = 1;
  *had_options = false;
  while (i < tokens.size() && tokens[i].size() > 1 && tokens[i][0] == '-') {
    auto it = kOptions.find(tokens[i]);
    if (it == kOptions.end()) break;  // a file name starting with '-'
    *had_options = true;
    ++i;
    const bool variable = it->second == 3;
    for (int k = 0; k < it->second && i + 1 < tokens.size(); ++k) {
      if (variable && k > 0) {
        float f;
        std::string ignored;
        if (!parse_float(tokens[i], &f, &ignored)) break;
      }
      ++i;
    }
  }
  if (i >= tokens.size()) {
    *message = std::string(tokens[0]) + " names no file";
    return false;
  }
  *name = joined(tokens, i);  // file names may hold spaces
  return true;
}

// Finds a texture named in an MTL file, first found wins:
//   1. the name as written, relative to the MTL's directory;
//   2. with `\` read as a separator (MTL files written on Windows use it: `.\wall.jpg`);
//   3. its file name alone in the MTL's directory, then in the OBJ's (a path from the author's
//      machine, `C:\Models\tex\wall.jpg`, while the file came along beside the model);
//   4. the same file name in those directories, letter case aside (files copied from a
//      case-insensitive file system), as a last resort.
bool find_texture(const std::string& mtl_dir, const std::string& obj_dir, const std::string& name,
                  std::string* found) {
  std::error_code ec;
  auto exists = [&](const std::string& p) {
    if (!fs::is_regular_file(p, ec)) return false;
    *found = p;
    return true;
  };
  std::string slashed = name;
  std::replace(slashed.begin(), slashed.end(), '\\', '/');
  if (exists(join_path(mtl_dir, name)) || exists(join_path(mtl_dir, slashed))) return true;
  const std::string file = fs::path(slashed).filename().string();
  if (file.empty()) return false;
  const std::string dirs[2] = {mtl_dir, obj_dir};
  for (const std::string& dir : dirs)
    if (exists(join_path(dir, file))) return true;
  auto lower = [](std::string t) {
    for (char& c : t) c = char(std::tolower(static_cast<unsigned char>(c)));
    return t;
  };
  const std::string wanted = lower(file);
  for (const std::string& dir : dirs) {
    // Sorted, so that two files differing only in case resolve the same way on every machine.
    std::vector<std::string> matches;
    for (fs::directory_iterator it(dir.empty() ? "." : dir, ec), end; !ec && it != end;
         it.increment(ec))
      if (lower(it->path().filename().string()) == wanted && it->is_regular_file(ec))
        matches.push_back(join_path(dir, it->path().filename().string()));
    if (!matches.empty()) {
      *found = *std::min_element(matches.begin(), matches.end());
      return true;
    }
  }
  return false;
}

bool parse_mtl(const std::string& path, const std::string& obj_dir, bool strict,
               std::vector<ObjMaterial>* materials, std::map<std::string, int>* by_name,
               WarningSink* warn, std::string* error) {
  std::string text;
  if (!read_text(path, &text, error)) return false;
  const std::string dir = dir_of(path);
  ObjMaterial* current = nullptr;
  ObjMaterial discarded;  // statements of a material defined twice (the first one wins)
  std::vector<float> nums;
  return for_each_line(
      path, text, error,
      [&](int line, const std::vector<std::string_view>& t, std::string* message) {
        const std::string_view key = t[0];
        if (key == "newmtl") {
          if (t.size() < 2) {
            *message = "newmtl names no material";
            return false;
          }
          std::string name = joined(t, 1);
          if (by_name->count(name)) {
            // tinyobjloader keeps the first definition of a name; so do we, but say so.
            warn->always(path, line, "material " + in_quotes(name) + " defined again; ignored");
            discarded = ObjMaterial();
            current = &discarded;
            return true;
          }
          (*by_name)[name] = static_cast<int>(materials->size());
          materials->emplace_back();
          materials->back().name = name;
          current = &materials->back();
          return true;
        }
        if (!current) {
          warn->once(path, line, "before-newmtl", std::string(key) + " before any newmtl; ignored");
          return true;
        }
        ObjMaterial& m = *current;
        auto colour = [&](std::array<float, 3>* c) {
          if (t.size() >= 2 && (t[1] == "spectral" || t[1] == "xyz")) {
            warn->once(path, line, std::string(key) + std::string(t[1]),
                       std::string(key) + " " + std::string(t[1]) +
                           " colours are not supported; "
                           "ignored");
            return true;
          }
          // "Kd r" is grey r, "Kd r g b" a colour.
          if (!parse_floats(t, 1, 1, 3, std::string(key).c_str(), &nums, message)) return false;
          if (nums.size() == 2) {
            *message = std::string(key) + " needs 1 or 3 numbers, found 2";
            return false;
          }
          *c = nums.size() == 1 ? std::array<float, 3>{nums[0], nums[0], nums[0]}
                                : std::array<float, 3>{nums[0], nums[1], nums[2]};
          return true;
        };
        auto scalar = [&](float* f, size_t from) {
          if (!parse_floats(t, from, 1, 1, std::string(key).c_str(), &nums, message)) return false;
          *f = nums[0];
          return true;
        };
        auto texture = [&](std::string* dst) {
          std::string name;
          bool had_options = false;
          if (!map_file_name(t, &name, &had_options, message)) return false;
          if (had_options)
            warn->once(path, line, "map-options",
                       std::string(key) + " options are ignored (pbrt-v3's imagemap has none)");
          if (!find_texture(dir, obj_dir, name, dst)) {
            std::string where = in_quotes(dir.empty() ? "." : dir);
            if (obj_dir != dir) where += " and " + in_quotes(obj_dir.empty() ? "." : obj_dir);
            const std::string what = std::string(key) + " file " + in_quotes(name) +
                                     " not found (looked in " + where + ")";
            if (strict) {
              *message = what;
              return false;
            }
            // A converter converts what it can: the material keeps its constant colour.
            warn->always(path, line, what + "; the material keeps its constant value");
          }
          return true;
        };
        if (key == "Kd") return colour(&m.kd);
        if (key == "Ks") return colour(&m.ks);
        if (key == "Kt") return colour(&m.kt);
        if (key == "Ke") return colour(&m.ke);
        if (key == "Ns") return scalar(&m.ns, 1);
        if (key == "Ni") return scalar(&m.ni, 1);
        if (key == "d") return scalar(&m.d, t.size() > 1 && t[1] == "-halo" ? 2 : 1);
        if (key == "Tr") {
          // tinyobjloader inverts Tr (transparency) into d (dissolve); the later statement wins.
          float tr = 0;
          if (!scalar(&tr, 1)) return false;
          m.d = 1.f - tr;
          return true;
        }
        if (key == "map_Kd") return texture(&m.map_kd);
        if (key == "map_Ks") return texture(&m.map_ks);
        if (key == "map_bump" || key == "bump" || key == "map_Bump") return texture(&m.map_bump);
        if (key == "Ka" || key == "illum") return true;  // pbrt-v3 has no ambient term
        warn->once(path, line, std::string(key),
                   std::string(key) + " is not converted (pbrt-v3's obj2pbrt ignores it too)");
        return true;
      });
}

// ---- OBJ -------------------------------------------------------------------------------------

struct Triple {
  int32_t v, vt, vn;  // -1: absent
  bool operator==(const Triple& o) const { return v == o.v && vt == o.vt && vn == o.vn; }
};
struct TripleHash {
  size_t operator()(const Triple& t) const {
    uint64_t h = uint64_t(uint32_t(t.v)) * 0x9E3779B97F4A7C15ull;
    h ^= (uint64_t(uint32_t(t.vt)) + 0x632BE59BD9B4E019ull) * 0xC2B2AE3D27D4EB4Full;
    h ^= (uint64_t(uint32_t(t.vn)) + 0x165667B19E3779F9ull) * 0x27D4EB2F165667C5ull;
    return size_t(h ^ (h >> 29));
  }
};

struct ShapeBuild {
  ObjShape shape;
  std::unordered_map<Triple, uint32_t, TripleHash> remap;
  std::vector<Triple> sources;  // per vertex
};

// An OBJ index (1-based, or negative: relative to the end) to a 0-based one.
bool resolve_index(std::string_view tok, size_t count, const char* what, int32_t* out,
                   std::string* message) {
  std::string_view t = tok;
  if (t.size() > 1 && t[0] == '+') t.remove_prefix(1);
  long long i = 0;
  auto r = std::from_chars(t.data(), t.data() + t.size(), i);
  if (r.ec == std::errc::result_out_of_range) {
    *message = std::string(what) + " index " + std::string(tok) + " out of range (" +
               std::to_string(count) + " defined so far)";
    return false;
  }
  if (r.ec != std::errc() || r.ptr != t.data() + t.size()) {
    *message = "expected a " + std::string(what) + " index, found " + in_quotes(tok);
    return false;
  }
  if (i == 0) {
    *message = std::string(what) + " index 0 (OBJ indices start at 1)";
    return false;
  }
  const long long n = static_cast<long long>(count);
  if (i > n || -i > n) {
    *message = std::string(what) + " index " + std::to_string(i) + " out of range (" +
               std::to_string(count) + " defined so far)";
    return false;
  }
  *out = static_cast<int32_t>(i > 0 ? i - 1 : n + i);
  return true;
}

bool parse_face_vertex(std::string_view tok, size_t nv, size_t nvt, size_t nvn, Triple* out,
                       std::string* message) {
  std::string_view parts[3];
  size_t count = 0, start = 0;
  for (size_t i = 0; i <= tok.size(); ++i) {
    if (i == tok.size() || tok[i] == '/') {
      if (count == 3) {
        *message = "face vertex " + in_quotes(tok) + " has more than three parts";
        return false;
      }
      parts[count++] = tok.substr(start, i - start);
      start = i + 1;
    }
  }
  *out = Triple{-1, -1, -1};
  if (!resolve_index(parts[0], nv, "vertex", &out->v, message)) return false;
  if (count > 1 && !parts[1].empty() &&
      !resolve_index(parts[1], nvt, "texture coordinate", &out->vt, message))
    return false;
  if (count > 2 && !parts[2].empty() && !resolve_index(parts[2], nvn, "normal", &out->vn, message))
    return false;
  if (count > 2 && parts[2].empty()) {
    *message = "face vertex " + in_quotes(tok) + " ends in '/'";
    return false;
  }
  return true;
}

}  // namespace

float roughness_from_ns(float ns) {
  return ns == 0 ? 0.f : 1.f / ns;
}

bool parse_obj_scene(const std::string& display_path, const std::string& text,
                     const std::string& base_dir, ObjScene* scene, std::string* error,
                     bool strict) {
  *scene = ObjScene();
  WarningSink warn(&scene->warnings);
  std::vector<float> v, vt, vn;
  std::map<std::string, int> material_by_name;
  std::vector<ShapeBuild> builds;
  std::map<std::pair<std::string, int>, size_t> build_of;  // (name, material) -> builds index
  std::string name;
  int material = -1;
  std::vector<float> nums;
  std::vector<Triple> face;
  std::string mtl_error;

  const bool ok = for_each_line(
      display_path, text, error,
      [&](int line, const std::vector<std::string_view>& t, std::string* message) {
        const std::string_view key = t[0];
        if (key == "v") {
          // x y z, then an optional w or an r g b vertex colour: all must be numbers, 3 are kept.
          if (!parse_floats(t, 1, 3, 7, "vertex", &nums, message)) return false;
          if (v.size() / 3 >= size_t(INT32_MAX)) {
            *message = "too many vertices";
            return false;
          }
          v.insert(v.end(), nums.begin(), nums.begin() + 3);
          return true;
        }
        if (key == "vt") {
          if (!parse_floats(t, 1, 1, 3, "texture coordinate", &nums, message)) return false;
          if (vt.size() / 2 >= size_t(INT32_MAX)) {
            *message = "too many texture coordinates";
            return false;
          }
          vt.push_back(nums[0]);
          vt.push_back(nums.size() > 1 ? nums[1] : 0.f);
          return true;
        }
        if (key == "vn") {
          if (!parse_floats(t, 1, 3, 3, "normal", &nums, message)) return false;
          if (vn.size() / 3 >= size_t(INT32_MAX)) {
            *message = "too many normals";
            return false;
          }
          vn.insert(vn.end(), nums.begin(), nums.end());
          return true;
        }
        if (key == "f" || key == "fo") {
          if (t.size() < 4) {
            *message = "a face needs at least 3 vertices, found " + std::to_string(t.size() - 1);
            return false;
          }
          face.clear();
          for (size_t i = 1; i < t.size(); ++i) {
            Triple tr;
            if (!parse_face_vertex(t[i], v.size() / 3, vt.size() / 2, vn.size() / 3, &tr, message))
              return false;
            face.push_back(tr);
          }
          auto key_pair = std::make_pair(name, material);
          auto it = build_of.find(key_pair);
          if (it == build_of.end()) {
            it = build_of.emplace(key_pair, builds.size()).first;
            builds.emplace_back();
            builds.back().shape.name = name;
            builds.back().shape.material = material;
          }
          ShapeBuild& b = builds[it->second];
          uint32_t ids[3];
          auto vertex_of = [&](const Triple& tr, uint32_t* id) {
            auto found = b.remap.find(tr);
            if (found != b.remap.end()) {
              *id = found->second;
              return true;
            }
            if (b.sources.size() >= size_t(UINT32_MAX)) {
              *message = "shape " + in_quotes(name) + " has too many vertices";
              return false;
            }
            *id = static_cast<uint32_t>(b.sources.size());
            b.remap.emplace(tr, *id);
            b.sources.push_back(tr);
            const float* p = &v[size_t(tr.v) * 3];
            b.shape.mesh.positions.insert(b.shape.mesh.positions.end(), p, p + 3);
            return true;
          };
          // A fan around the first vertex, as tinyobjloader triangulates for pbrt-v3's obj2pbrt.
          if (!vertex_of(face[0], &ids[0]) || !vertex_of(face[1], &ids[2])) return false;
          for (size_t k = 2; k < face.size(); ++k) {
            ids[1] = ids[2];
            if (!vertex_of(face[k], &ids[2])) return false;
            b.shape.mesh.indices.insert(b.shape.mesh.indices.end(), ids, ids + 3);
          }
          return true;
        }
        if (key == "o" || key == "g") {
          name = joined(t, 1);
          return true;
        }
        if (key == "usemtl") {
          std::string m = joined(t, 1);
          auto it = material_by_name.find(m);
          if (it == material_by_name.end()) {
            // pbrt-v3's obj2pbrt (tinyobjloader) silently uses no material then.
            warn.always(display_path, line,
                        "usemtl " + in_quotes(m) +
                            ": no such material in the mtllib files read so "
                            "far; its faces get the including scene's material");
            material = -1;
          } else {
            material = it->second;
          }
          return true;
        }
        if (key == "mtllib") {
          if (t.size() < 2) {
            *message = "mtllib names no file";
            return false;
          }
          // Several names on one line are several libraries (the OBJ specification's reading).
          for (size_t i = 1; i < t.size(); ++i) {
            std::string lib(t[i]);
            std::string path = join_path(base_dir, lib);
            std::error_code ec;
            if (!fs::is_regular_file(path, ec)) {
              std::string slashed = lib;
              std::replace(slashed.begin(), slashed.end(), '\\', '/');
              std::string alt = join_path(base_dir, slashed);
              if (slashed == lib || !fs::is_regular_file(alt, ec)) {
                // pbrt-v3 warns and goes on with default materials; a scene converted without its
                // materials is rarely what was meant, so this is an error.
                *message = "material library " + in_quotes(lib) + " not found (looked in " +
                           in_quotes(base_dir.empty() ? "." : base_dir) + ")";
                return false;
              }
              path = alt;
            }
            if (!parse_mtl(path, base_dir, strict, &scene->materials, &material_by_name, &warn,
                           &mtl_error)) {
              *message = "in material library " + in_quotes(lib) + ": " + mtl_error;
              return false;
            }
          }
          return true;
        }
        if (key == "s") return true;  // smoothing groups: OBJ normals already say it
        if (key == "l" || key == "p") {
          warn.once(
              display_path, line, std::string(key),
              std::string(key == "l" ? "lines" : "points") + " have no pbrt-v3 shape; skipped");
          return true;
        }
        warn.once(display_path, line, std::string(key),
                  "statement " + in_quotes(key) + " is not supported; skipped");
        return true;
      });
  if (!ok) {
    *scene = ObjScene();
    return false;
  }

  // Normals and uv belong to a shape only if every one of its vertices has them: pbrt-v3's
  // trianglemesh takes one array per vertex or none.
  for (ShapeBuild& b : builds) {
    Mesh& m = b.shape.mesh;
    size_t with_n = 0, with_uv = 0;
    for (const Triple& tr : b.sources) {
      with_n += tr.vn >= 0;
      with_uv += tr.vt >= 0;
    }
    const size_t n = b.sources.size();
    if (with_n == n) {
      m.normals.reserve(n * 3);
      for (const Triple& tr : b.sources)
        m.normals.insert(m.normals.end(), &vn[size_t(tr.vn) * 3], &vn[size_t(tr.vn) * 3] + 3);
    } else if (with_n > 0) {
      scene->warnings.push_back(display_path + ": shape " + in_quotes(b.shape.name) + ": " +
                                std::to_string(n - with_n) + " of " + std::to_string(n) +
                                " vertices have no normal; normals dropped");
    }
    if (with_uv == n) {
      m.uvs.reserve(n * 2);
      for (const Triple& tr : b.sources)
        m.uvs.insert(m.uvs.end(), &vt[size_t(tr.vt) * 2], &vt[size_t(tr.vt) * 2] + 2);
    } else if (with_uv > 0) {
      scene->warnings.push_back(display_path + ": shape " + in_quotes(b.shape.name) + ": " +
                                std::to_string(n - with_uv) + " of " + std::to_string(n) +
                                " vertices have no texture coordinates; uv dropped");
    }
    scene->shapes.push_back(std::move(b.shape));
  }
  return true;
}

bool read_obj_scene(const std::string& path, ObjScene* scene, std::string* error, bool strict) {
  std::string text;
  if (!read_text(path, &text, error)) {
    *scene = ObjScene();
    return false;
  }
  return parse_obj_scene(path, text, dir_of(path), scene, error, strict);
}

// ---- pbrt-v3 output --------------------------------------------------------------------------

namespace {

// A pbrt string literal: the lexer takes \" and \\ as escapes.
std::string pbrt_string(std::string_view s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out.push_back('\\');
    out.push_back(static_cast<unsigned char>(c) < 0x20 ? '_' : c);
  }
  out.push_back('"');
  return out;
}

// Shortest text that reads back as the same float.
void append_float(std::string* out, float f) {
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof buf, f);
  out->append(buf, r.ptr);
}

std::string floats_text(const float* f, size_t n) {
  std::string s = "[";
  for (size_t i = 0; i < n; ++i) {
    s.push_back(' ');
    append_float(&s, f[i]);
  }
  s += " ]";
  return s;
}

// A bulk array, 12 numbers to a line so the file stays readable in an editor.
template <typename T>
void append_array(std::string* out, const char* decl, const T* data, size_t n) {
  *out += "    ";
  *out += decl;
  *out += " [";
  for (size_t i = 0; i < n; ++i) {
    *out += (i % 12 == 0) ? "\n      " : " ";
    if constexpr (std::is_floating_point_v<T>) {
      append_float(out, data[i]);
    } else {
      *out += std::to_string(data[i]);
    }
  }
  *out += "\n    ]\n";
}

bool black(const std::array<float, 3>& c) {
  return c[0] == 0 && c[1] == 0 && c[2] == 0;
}
bool emissive(const ObjMaterial& m) {
  return m.ke[0] > 0 || m.ke[1] > 0 || m.ke[2] > 0;
}

bool write_atomically(const std::string& path, const std::string& text, std::string* error) {
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) {
    *error = path + ": cannot create: " + std::strerror(errno);
    return false;
  }
  bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  ok = (std::fflush(f) == 0) && ok;
  const int saved = errno;
  ok = (std::fclose(f) == 0) && ok;
  if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0) {
    *error = path + ": cannot write: " + std::strerror(ok ? errno : saved);
    std::remove(tmp.c_str());
    return false;
  }
  return true;
}

}  // namespace

bool write_obj_scene_pbrt(const ObjScene& scene, const std::string& out_path,
                          const ObjPbrtOptions& options, ObjPbrtStats* stats, std::string* error) {
  ObjPbrtStats st;
  std::error_code ec;
  const fs::path out_dir = fs::absolute(fs::path(out_path), ec).parent_path();
  // File names in the output: relative to its directory (pbrt-v3 resolves relative names
  // against the top-level scene file's directory, so the including scene should sit beside it).
  auto name_for = [&](const std::string& file) {
    fs::path abs = fs::absolute(file, ec).lexically_normal();
    if (options.absolute_paths) return abs.string();
    fs::path rel = abs.lexically_relative(out_dir);
    return rel.empty() ? abs.string() : rel.generic_string();
  };

  float lo[3] = {FLT_MAX, FLT_MAX, FLT_MAX}, hi[3] = {-FLT_MAX, -FLT_MAX, -FLT_MAX};
  for (const ObjShape& s : scene.shapes)
    for (size_t i = 0; i < s.mesh.positions.size(); ++i) {
      lo[i % 3] = std::min(lo[i % 3], s.mesh.positions[i]);
      hi[i % 3] = std::max(hi[i % 3], s.mesh.positions[i]);
    }
  const bool have_bounds = lo[0] <= hi[0];

  std::string body;
  // Materials first, every one the MTL files define, as pbrt-v3's obj2pbrt does.
  for (const ObjMaterial& m : scene.materials) {
    auto colour_texture = [&](const std::string& file, const std::array<float, 3>& c,
                              const char* suffix) {
      if (file.empty()) return;
      const std::string tex = m.name + "-" + suffix;
      if (!black(c)) {
        // pbrt-v3 multiplies the map by a non-black colour; a black one means "the map alone".
        body += "Texture " + pbrt_string(tex + "-img") + " \"spectrum\" \"imagemap\" " +
                "\"string filename\" " + pbrt_string(name_for(file)) + "\n";
        body += "Texture " + pbrt_string(tex) + " \"spectrum\" \"scale\" \"texture tex1\" " +
                pbrt_string(tex + "-img") + " \"rgb tex2\" " + floats_text(c.data(), 3) + "\n";
        st.textures += 2;
      } else {
        body += "Texture " + pbrt_string(tex) + " \"spectrum\" \"imagemap\" " +
                "\"string filename\" " + pbrt_string(name_for(file)) + "\n";
        st.textures += 1;
      }
    };
    colour_texture(m.map_kd, m.kd, "kd");
    colour_texture(m.map_ks, m.ks, "ks");
    if (!m.map_bump.empty()) {
      body += "Texture " + pbrt_string(m.name + "-bump") + " \"float\" \"imagemap\" " +
              "\"string filename\" " + pbrt_string(name_for(m.map_bump)) + "\n";
      st.textures += 1;
    }
    const float roughness = roughness_from_ns(m.ns);
    const float opacity[3] = {m.d, m.d, m.d};
    body += "MakeNamedMaterial " + pbrt_string(m.name) + "\n    \"string type\" \"uber\"\n";
    if (!m.map_kd.empty())
      body += "    \"texture Kd\" " + pbrt_string(m.name + "-kd") + "\n";
    else
      body += "    \"rgb Kd\" " + floats_text(m.kd.data(), 3) + "\n";
    if (!m.map_ks.empty())
      body += "    \"texture Ks\" " + pbrt_string(m.name + "-ks") + "\n";
    else
      body += "    \"rgb Ks\" " + floats_text(m.ks.data(), 3) + "\n";
    body += "    \"float roughness\" " + floats_text(&roughness, 1) + "\n";
    body += "    \"rgb Kt\" " + floats_text(m.kt.data(), 3) + "\n";
    body += "    \"float index\" " + floats_text(&m.ni, 1) + "\n";
    body += "    \"rgb opacity\" " + floats_text(opacity, 3) + "\n";
    if (!m.map_bump.empty())
      body += "    \"texture bumpmap\" " + pbrt_string(m.name + "-bump") + "\n";
    body += "\n";
    ++st.materials;
  }

  const std::string stem = fs::path(out_path).stem().string();
  std::vector<std::string> written;  // PLY files, removed again if a later step fails
  auto fail = [&](const std::string& message) {
    for (const std::string& f : written) std::remove(f.c_str());
    *error = message;
    return false;
  };
  size_t part = 0;
  for (const ObjShape& s : scene.shapes) {
    const Mesh& mesh = s.mesh;
    if (mesh.num_triangles() == 0) continue;
    body += "# Name " + pbrt_string(s.name) + "\n";
    // One attribute block per shape, so an area light stays on the emissive material's faces
    // (pbrt-v3's obj2pbrt opens one block per OBJ group, and its AreaLightSource leaks into the
    // group's later materials).
    body += "AttributeBegin\n";
    if (s.material < 0) {
      body += "  # Material unspecified in OBJ file: the including scene's material\n";
    } else {
      const ObjMaterial& m = scene.materials[size_t(s.material)];
      if (emissive(m)) {
        body += "  AreaLightSource \"diffuse\" \"rgb L\" " + floats_text(m.ke.data(), 3) + "\n";
        ++st.area_lights;
      }
      body += "  NamedMaterial " + pbrt_string(m.name) + "\n";
    }
    if (options.style == PbrtStyle::kPlymesh) {
      const std::string ply = (out_dir / (stem + "-" + std::to_string(part) + ".ply")).string();
      std::string ply_error;
      if (!pbrtc::write_ply(ply, pbrta::arrays_of(mesh), &ply_error))
        return fail(ply + ": " + ply_error);
      written.push_back(ply);
      body += "  Shape \"plymesh\" \"string filename\" " + pbrt_string(name_for(ply)) + "\n";
    } else {
      body += "  Shape \"trianglemesh\"\n";
      append_array(&body, "\"integer indices\"", mesh.indices.data(), mesh.indices.size());
      append_array(&body, "\"point P\"", mesh.positions.data(), mesh.positions.size());
      if (!mesh.normals.empty())
        append_array(&body, "\"normal N\"", mesh.normals.data(), mesh.normals.size());
      if (!mesh.uvs.empty()) append_array(&body, "\"point2 uv\"", mesh.uvs.data(), mesh.uvs.size());
    }
    body += "AttributeEnd\n\n";
    ++part;
    ++st.shapes;
    st.triangles += mesh.num_triangles();
  }

  std::string out;
  out += "# Converted from " + pbrt_string(options.source_name) + " by pbrtc's obj2pbrt\n";
  if (have_bounds) {
    char buf[200];
    std::snprintf(buf, sizeof buf, "# Scene bounds: (%g, %g, %g) - (%g, %g, %g)\n", lo[0], lo[1],
                  lo[2], hi[0], hi[1], hi[2]);
    out += buf;
  }
  if (!options.complete_scene) {
    out += "# A scene fragment: Include it after WorldBegin of a scene that sets the camera.\n\n";
    out += body;
  } else {
    // A camera that sees the whole bounding sphere from above and in front (OBJ is y-up), 45
    // degrees of field of view; Scale -1 1 1 because pbrt's camera space is left-handed and
    // OBJ's right-handed, so the image is not mirrored.
    double c[3] = {0, 0, 0}, radius = 1;
    if (have_bounds) {
      double d2 = 0;
      for (int k = 0; k < 3; ++k) {
        c[k] = 0.5 * (double(lo[k]) + double(hi[k]));
        d2 += (double(hi[k]) - lo[k]) * (double(hi[k]) - lo[k]);
      }
      radius = std::max(0.5 * std::sqrt(d2), 1e-6);
    }
    const double fov = 45, dir[3] = {0.6, 0.5, 1.0};
    const double len = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    const double dist = 1.1 * radius / std::sin(0.5 * fov * 3.14159265358979323846 / 180);
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "\nScale -1 1 1\nLookAt %.9g %.9g %.9g  %.9g %.9g %.9g  0 1 0\n"
                  "Camera \"perspective\" \"float fov\" [ %g ]\n",
                  c[0] + dir[0] / len * dist, c[1] + dir[1] / len * dist,
                  c[2] + dir[2] / len * dist, c[0], c[1], c[2], fov);
    out += buf;
    out +=
        "Film \"image\" \"integer xresolution\" [ 640 ] \"integer yresolution\" [ 480 ]\n"
        "    \"string filename\" " +
        pbrt_string(stem + ".exr") + "\n";
    out += "Sampler \"halton\" \"integer pixelsamples\" [ 16 ]\n";
    out += "Integrator \"path\"\n\nWorldBegin\n\n";
    out += "LightSource \"infinite\" \"rgb L\" [ 1 1 1 ]\n\n";
    out += body;
    out += "WorldEnd\n";
  }
  std::string write_error;
  if (!write_atomically(out_path, out, &write_error)) return fail(write_error);
  if (stats) *stats = st;
  return true;
}

}  // namespace meshtools
