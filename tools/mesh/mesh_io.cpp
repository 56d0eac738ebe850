// tools/mesh/mesh_io.cpp — read_mesh / write_mesh for every format the mesh tools speak.
//
// PLY goes through the project's one hardened reader (compiler/ply_reader.h) and its writer; .drc
// through the one Draco wrapper (format/draco_codec.h); .pbrt through pbrtc's own front end.
// OBJ, OFF and STL have small readers of their own here rather than OpenMesh's: OpenMesh 9's
// readers return success after silently dropping a face whose index is out of range
// ("ImporterT: Face contains invalid vertex index"), and its halfedge importer duplicates the
// vertices of every non-manifold face ("complex edge"), so a file read through it would lose
// faces without an error and `info` could never see the topology problems it exists to count.
// The three formats are simple enough to read carefully: every reader here takes its counts
// from what the bytes actually hold (a header count is checked against the file's size before
// anything is reserved for it), rejects NaN/Inf values and out-of-range indices with the line
// or element that holds them, and returns false on an empty file. The writers are ours too, for
// the same reason (an OpenMesh mesh cannot carry a non-manifold input through to the output)
// and so floats are printed with %.9g, which reads back to the same float.
//
// Every reader ends in check_mesh, which validates what any reader produced (array sizes,
// finite values, indices in range), so a later tool never sees an inconsistent Mesh.
#include "tools/mesh/mesh.h"

#include <fast_float/fast_float.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>
#include <unordered_map>

#include "compiler/diagnostics.h"
#include "compiler/scene_builder.h"
#include "compiler/scene_desc.h"
#include "compiler/source_files.h"
#include "format/draco_codec.h"
#include "compiler/ply_reader.h"
#include "compiler/ply_writer.h"

namespace meshtools {
namespace {

// ---- small helpers ----

bool fail(std::string* error, const std::string& path, const std::string& reason) {
  if (error) *error = path + ": " + reason;
  return false;
}

std::string directory_of(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

std::string file_name_of(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// Reads the whole file. The size comes from the stream, not from the content, so a lying
// header cannot make this allocate more than the file is.
bool read_bytes(const std::string& path, std::string* bytes, std::string* error) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return fail(error, path, std::string("cannot open: ") + std::strerror(errno));
  const std::streamoff size = in.tellg();
  if (size < 0) return fail(error, path, "cannot determine the file's size");
  if (size == 0) return fail(error, path, "empty file");
  bytes->resize(size_t(size));
  in.seekg(0);
  if (!in.read(bytes->data(), size)) return fail(error, path, "read error");
  return true;
}

// Writes through a temporary name in the same directory and renames, so a reader never sees
// a half-written file and a failure leaves nothing behind. The name is unique per process and
// call, so concurrent writers in one process do not collide.
bool write_atomically(const std::string& path, const std::string& bytes, std::string* error) {
  static std::atomic<uint64_t> counter{0};
  const std::string tmp =
      path + ".tmp." + std::to_string(getpid()) + "." + std::to_string(counter.fetch_add(1));
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) return fail(error, path, std::string("cannot create: ") + std::strerror(errno));
    out.write(bytes.data(), std::streamsize(bytes.size()));
    out.flush();
    if (!out) {
      std::remove(tmp.c_str());
      return fail(error, path, "write error");
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(tmp.c_str());
    return fail(error, path, "cannot rename the temporary file: " + reason);
  }
  return true;
}

// %.9g round-trips every float exactly (9 significant digits suffice for binary32).
void append_float(std::string* out, float v) {
  char buf[32];
  const int n = std::snprintf(buf, sizeof buf, "%.9g", double(v));
  out->append(buf, size_t(n));
}

void append_uint(std::string* out, uint64_t v) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out->append(buf, r.ptr);
}

void append_int(std::string* out, int64_t v) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out->append(buf, r.ptr);
}

// Progress on stderr for long reads: only when stderr is a terminal and the caller is not
// quiet, throttled so printing never costs measurable time.
class Progress {
 public:
  Progress(const std::string& path, size_t total, bool quiet)
      : path_(path),
        total_(total),
        enabled_(!quiet && total >= (size_t{16} << 20) && isatty(STDERR_FILENO)) {}
  ~Progress() {
    if (shown_) std::fprintf(stderr, "\r\033[K");
  }
  void update(size_t done) {
    if (!enabled_ || (++calls_ & 0xfff) != 0) return;
    const auto now = std::chrono::steady_clock::now();
    if (shown_ && now - last_ < std::chrono::milliseconds(250)) return;
    last_ = now;
    shown_ = true;
    std::fprintf(stderr, "\rpbrt-mesh: reading %s: %d%%", path_.c_str(),
                 int(100.0 * double(done) / double(total_)));
  }
  void note(const char* what) {
    if (!enabled_) return;
    std::fprintf(stderr, "\rpbrt-mesh: %s %s (%zu MB)...", what, path_.c_str(), total_ >> 20);
    shown_ = true;
  }

 private:
  std::string path_;
  size_t total_;
  bool enabled_;
  bool shown_ = false;
  uint64_t calls_ = 0;
  std::chrono::steady_clock::time_point last_{};
};

// The check every reader's result goes through (and every mesh before it is written).
bool check_mesh(const Mesh& m, std::string* reason) {
  if (m.positions.size() % 3 != 0) return *reason = "positions are not 3 per vertex", false;
  if (m.indices.size() % 3 != 0) return *reason = "indices are not 3 per triangle", false;
  const size_t nv = m.num_vertices();
  if (!m.normals.empty() && m.normals.size() != 3 * nv)
    return *reason = "normals are not 3 per vertex", false;
  if (!m.uvs.empty() && m.uvs.size() != 2 * nv) return *reason = "uv are not 2 per vertex", false;
  if (!m.face_indices.empty() && m.face_indices.size() != m.num_triangles())
    return *reason = "face indices are not 1 per triangle", false;
  if (nv > uint64_t{0xffffffff}) return *reason = "more than 2^32 - 1 vertices", false;
  for (size_t i = 0; i < m.positions.size(); ++i)
    if (!std::isfinite(m.positions[i]))
      return *reason = "vertex " + std::to_string(i / 3) + ": coordinate is not finite", false;
  for (size_t i = 0; i < m.normals.size(); ++i)
    if (!std::isfinite(m.normals[i]))
      return *reason = "vertex " + std::to_string(i / 3) + ": normal is not finite", false;
  for (size_t i = 0; i < m.uvs.size(); ++i)
    if (!std::isfinite(m.uvs[i]))
      return *reason = "vertex " + std::to_string(i / 2) + ": uv is not finite", false;
  for (size_t i = 0; i < m.indices.size(); ++i)
    if (m.indices[i] >= nv)
      return *reason = "triangle " + std::to_string(i / 3) + ": vertex index " +
                       std::to_string(m.indices[i]) + " out of range (" + std::to_string(nv) +
                       " vertices)",
             false;
  return true;
}

// ---- a line/token scanner for the text formats ----

// Splits text into lines and whitespace-separated tokens; '#' starts a comment. Tokens are
// views into the file's bytes, so nothing is copied.
class LineScanner {
 public:
  explicit LineScanner(std::string_view text) : text_(text) {}
  // Next line's tokens (comments stripped); false at the end. Empty lines come back empty.
  bool next(std::vector<std::string_view>* tokens) {
    tokens->clear();
    if (pos_ >= text_.size()) return false;
    ++line_;
    size_t end = text_.find('\n', pos_);
    if (end == std::string_view::npos) end = text_.size();
    std::string_view line = text_.substr(pos_, end - pos_);
    pos_ = end + 1;
    if (const size_t hash = line.find('#'); hash != std::string_view::npos)
      line = line.substr(0, hash);
    size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && is_space(line[i])) ++i;
      size_t j = i;
      while (j < line.size() && !is_space(line[j])) ++j;
      if (j > i) tokens->push_back(line.substr(i, j - i));
      i = j;
    }
    return true;
  }
  size_t line() const { return line_; }
  size_t offset() const { return std::min(pos_, text_.size()); }

 private:
  static bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
  }
  std::string_view text_;
  size_t pos_ = 0;
  size_t line_ = 0;
};

// A finite float; "nan", "inf" and values that overflow float are rejected.
bool parse_float(std::string_view s, float* out) {
  double d = 0;
  const auto r = fast_float::from_chars(s.data(), s.data() + s.size(), d);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size()) return false;
  if (!std::isfinite(d) || std::fabs(d) > double(std::numeric_limits<float>::max())) return false;
  *out = float(d);
  return true;
}

bool parse_int(std::string_view s, int64_t* out) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  const auto r = std::from_chars(s.data(), s.data() + s.size(), *out);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

// ---- OBJ ----

// One polygon corner: 0-based position, uv and normal indices (-1: absent).
struct ObjCorner {
  int64_t v, vt, vn;
  bool operator==(const ObjCorner& o) const { return v == o.v && vt == o.vt && vn == o.vn; }
};
struct ObjCornerHash {
  size_t operator()(const ObjCorner& c) const {
    return std::hash<int64_t>()(c.v * 1000003 ^ c.vt * 7919 ^ c.vn);
  }
};

bool read_obj(const std::string& path, std::string_view text, Mesh* mesh, std::string* error,
              bool quiet) {
  Progress progress(path, text.size(), quiet);
  std::vector<float> v, vt, vn;
  std::vector<ObjCorner> corners;  // 3 per triangle, after fan triangulation
  std::vector<std::string_view> tok;
  std::vector<ObjCorner> poly;
  LineScanner scan(text);
  auto at = [&](const std::string& what) {
    return "line " + std::to_string(scan.line()) + ": " + what;
  };
  // OBJ indices are 1-based, or negative: relative to the end of the list so far.
  auto resolve = [](int64_t i, size_t count, int64_t* out) {
    if (i > 0 && uint64_t(i) <= count) return *out = i - 1, true;
    if (i < 0 && uint64_t(-i) <= count) return *out = int64_t(count) + i, true;
    return false;
  };
  while (scan.next(&tok)) {
    progress.update(scan.offset());
    if (tok.empty()) continue;
    const std::string_view kw = tok[0];
    if (kw == "v" || kw == "vn" || kw == "vt") {
      const size_t need = kw == "vt" ? 2 : 3;
      if (tok.size() < need + 1)
        return fail(error, path,
                    at(std::string(kw) + " needs " + std::to_string(need) + " numbers"));
      std::vector<float>& dst = kw == "v" ? v : kw == "vn" ? vn : vt;
      for (size_t k = 1; k <= need; ++k) {
        float f;
        if (!parse_float(tok[k], &f))
          return fail(error, path, at("\"" + std::string(tok[k]) + "\" is not a finite number"));
        dst.push_back(f);
      }
    } else if (kw == "f") {
      if (tok.size() < 4) return fail(error, path, at("a face needs at least 3 vertices"));
      poly.clear();
      for (size_t k = 1; k < tok.size(); ++k) {
        // v, v/vt, v//vn or v/vt/vn
        std::string_view parts[3];
        size_t np = 0;
        std::string_view rest = tok[k];
        while (np < 3) {
          const size_t slash = rest.find('/');
          parts[np++] = rest.substr(0, slash);
          if (slash == std::string_view::npos) break;
          rest.remove_prefix(slash + 1);
        }
        ObjCorner c{-1, -1, -1};
        int64_t raw;
        if (!parse_int(parts[0], &raw) || !resolve(raw, v.size() / 3, &c.v))
          return fail(error, path,
                      at("vertex index \"" + std::string(parts[0]) + "\" out of range (" +
                         std::to_string(v.size() / 3) + " vertices so far)"));
        if (np > 1 && !parts[1].empty() &&
            (!parse_int(parts[1], &raw) || !resolve(raw, vt.size() / 2, &c.vt)))
          return fail(error, path,
                      at("texture index \"" + std::string(parts[1]) + "\" out of range"));
        if (np > 2 && !parts[2].empty() &&
            (!parse_int(parts[2], &raw) || !resolve(raw, vn.size() / 3, &c.vn)))
          return fail(error, path,
                      at("normal index \"" + std::string(parts[2]) + "\" out of range"));
        poly.push_back(c);
      }
      for (size_t k = 1; k + 1 < poly.size(); ++k) {
        corners.push_back(poly[0]);
        corners.push_back(poly[k]);
        corners.push_back(poly[k + 1]);
      }
    }
    // Everything else (o, g, s, usemtl, mtllib, l, p, curves) carries nothing a Mesh holds.
  }
  if (v.empty()) return fail(error, path, "no vertices");

  // uv and normals are kept only when every corner has one; a file that gives them to some
  // faces only has nothing to give the others.
  bool all_vt = !corners.empty(), all_vn = !corners.empty();
  bool same_index = true;  // every corner's vt/vn index equals its v index
  for (const ObjCorner& c : corners) {
    all_vt = all_vt && c.vt >= 0;
    all_vn = all_vn && c.vn >= 0;
  }
  for (const ObjCorner& c : corners)
    same_index = same_index && (!all_vt || c.vt == c.v) && (!all_vn || c.vn == c.v);

  Mesh m;
  if (same_index) {
    // The common case (and what write_mesh writes): one vertex per "v", order kept.
    m.positions = std::move(v);
    const size_t nv = m.positions.size() / 3;
    if (all_vt) {
      if (vt.size() / 2 < nv) vt.resize(nv * 2, 0.f);  // vt beyond the used ones are unused
      m.uvs.assign(vt.begin(), vt.begin() + std::ptrdiff_t(nv * 2));
    }
    if (all_vn) {
      if (vn.size() / 3 < nv) vn.resize(nv * 3, 0.f);
      m.normals.assign(vn.begin(), vn.begin() + std::ptrdiff_t(nv * 3));
    }
    m.indices.reserve(corners.size());
    for (const ObjCorner& c : corners) m.indices.push_back(uint32_t(c.v));
  } else {
    // Corners with distinct (v, vt, vn) become distinct vertices, in order of first use.
    std::unordered_map<ObjCorner, uint32_t, ObjCornerHash> ids;
    m.indices.reserve(corners.size());
    for (ObjCorner c : corners) {
      if (!all_vt) c.vt = -1;
      if (!all_vn) c.vn = -1;
      auto [it, added] = ids.emplace(c, uint32_t(ids.size()));
      if (added) {
        m.positions.insert(m.positions.end(), &v[size_t(c.v) * 3], &v[size_t(c.v) * 3] + 3);
        if (all_vt) m.uvs.insert(m.uvs.end(), &vt[size_t(c.vt) * 2], &vt[size_t(c.vt) * 2] + 2);
        if (all_vn)
          m.normals.insert(m.normals.end(), &vn[size_t(c.vn) * 3], &vn[size_t(c.vn) * 3] + 3);
      }
      m.indices.push_back(it->second);
    }
  }
  *mesh = std::move(m);
  return true;
}

std::string obj_text(const Mesh& m) {
  std::string out = "# written by pbrt-mesh: " + std::to_string(m.num_vertices()) + " vertices, " +
                    std::to_string(m.num_triangles()) + " triangles\n";
  out.reserve(m.positions.size() * 14 + m.indices.size() * 10);
  auto line = [&](const char* kw, const float* p, int n) {
    out += kw;
    for (int k = 0; k < n; ++k) {
      out += ' ';
      append_float(&out, p[k]);
    }
    out += '\n';
  };
  for (size_t i = 0; i < m.num_vertices(); ++i) line("v", &m.positions[3 * i], 3);
  for (size_t i = 0; i < (m.uvs.size() / 2); ++i) line("vt", &m.uvs[2 * i], 2);
  for (size_t i = 0; i < (m.normals.size() / 3); ++i) line("vn", &m.normals[3 * i], 3);
  const bool t = !m.uvs.empty(), n = !m.normals.empty();
  for (size_t f = 0; f < m.num_triangles(); ++f) {
    out += 'f';
    for (int k = 0; k < 3; ++k) {
      const uint64_t i = uint64_t(m.indices[3 * f + size_t(k)]) + 1;
      out += ' ';
      append_uint(&out, i);
      if (t || n) {
        out += '/';
        if (t) append_uint(&out, i);
        if (n) {
          out += '/';
          append_uint(&out, i);
        }
      }
    }
    out += '\n';
  }
  return out;
}

// ---- OFF ----

// Geomview OFF: "[ST][C][N][4][n]OFF", then "nv nf ne", nv vertex lines "x y z [nx ny nz]
// [colour] [s t]", nf face lines "k i1 ... ik [colour]". Colours are skipped (a Mesh holds none);
// 4D and binary OFF are refused.
bool read_off(const std::string& path, std::string_view text, Mesh* mesh, std::string* error,
              bool quiet) {
  Progress progress(path, text.size(), quiet);
  LineScanner scan(text);
  std::vector<std::string_view> tok;
  auto at = [&](const std::string& what) {
    return "line " + std::to_string(scan.line()) + ": " + what;
  };
  // The next non-empty line.
  auto next_line = [&]() {
    while (scan.next(&tok))
      if (!tok.empty()) return true;
    return false;
  };
  if (!next_line()) return fail(error, path, "no OFF header");
  std::string_view kw = tok[0];
  if (kw.size() < 3 || kw.substr(kw.size() - 3) != "OFF")
    return fail(error, path, "not an OFF file (no OFF keyword)");
  std::string_view prefix = kw.substr(0, kw.size() - 3);
  bool has_st = false, has_c = false, has_n = false;
  if (prefix.substr(0, 2) == "ST") has_st = true, prefix.remove_prefix(2);
  if (!prefix.empty() && prefix[0] == 'C') has_c = true, prefix.remove_prefix(1);
  if (!prefix.empty() && prefix[0] == 'N') has_n = true, prefix.remove_prefix(1);
  if (!prefix.empty())
    return fail(error, path, "OFF variant \"" + std::string(kw) + "\" is not supported");
  std::vector<std::string_view> counts(tok.begin() + 1, tok.end());
  if (!counts.empty() && counts[0] == "BINARY")
    return fail(error, path, "binary OFF is not supported");
  if (counts.empty()) {
    if (!next_line()) return fail(error, path, "missing vertex and face counts");
    counts = tok;
  }
  int64_t nv = 0, nf = 0;
  if (counts.size() < 2 || !parse_int(counts[0], &nv) || !parse_int(counts[1], &nf) || nv < 0 ||
      nf < 0)
    return fail(error, path, at("bad vertex and face counts"));
  // A vertex line holds at least "0 0 0\n" (6 bytes), a face line at least "3 0 0 0\n" (8):
  // counts the remaining bytes cannot hold are lies, refused before anything is reserved.
  const uint64_t remaining = text.size() - scan.offset();
  if (uint64_t(nv) > remaining / 6 || uint64_t(nf) > remaining / 8 ||
      uint64_t(nv) * 6 + uint64_t(nf) * 8 > remaining)
    return fail(error, path,
                "header promises " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                    " faces, but only " + std::to_string(remaining) + " bytes follow");
  Mesh m;
  m.positions.reserve(size_t(nv) * 3);
  if (has_n) m.normals.reserve(size_t(nv) * 3);
  if (has_st) m.uvs.reserve(size_t(nv) * 2);
  for (int64_t i = 0; i < nv; ++i) {
    progress.update(scan.offset());
    if (!next_line())
      return fail(
          error, path,
          "file ends after " + std::to_string(i) + " of " + std::to_string(nv) + " vertices");
    const size_t fixed = 3 + (has_n ? 3 : 0) + (has_st ? 2 : 0);
    // A colour is one colour-map index or 3 or 4 components.
    const size_t extra = tok.size() - std::min(tok.size(), fixed);
    if (tok.size() < fixed || (has_c ? !(extra == 1 || extra == 3 || extra == 4) : extra != 0))
      return fail(
          error, path,
          at("vertex " + std::to_string(i) + " has " + std::to_string(tok.size()) + " numbers"));
    float f[3];
    auto take = [&](size_t first, size_t n, std::vector<float>* dst) {
      for (size_t k = 0; k < n; ++k) {
        if (!parse_float(tok[first + k], &f[0])) return false;
        dst->push_back(f[0]);
      }
      return true;
    };
    const size_t after_n = 3 + (has_n ? 3 : 0);
    const size_t st_at = after_n + (has_c ? extra : 0);
    if (!take(0, 3, &m.positions) || (has_n && !take(3, 3, &m.normals)) ||
        (has_st && !take(st_at, 2, &m.uvs)))
      return fail(error, path,
                  at("vertex " + std::to_string(i) + ": a value is not a finite number"));
  }
  m.indices.reserve(size_t(nf) * 3);
  for (int64_t i = 0; i < nf; ++i) {
    progress.update(scan.offset());
    if (!next_line())
      return fail(error, path,
                  "file ends after " + std::to_string(i) + " of " + std::to_string(nf) + " faces");
    int64_t k = 0;
    if (!parse_int(tok[0], &k) || k < 3 || uint64_t(k) > tok.size() - 1)
      return fail(error, path, at("face " + std::to_string(i) + ": bad vertex count"));
    uint32_t first = 0, prev = 0;
    for (int64_t j = 0; j < k; ++j) {
      int64_t idx;
      if (!parse_int(tok[size_t(j) + 1], &idx) || idx < 0 || idx >= nv)
        return fail(
            error, path,
            at("face " + std::to_string(i) + ": vertex index \"" + std::string(tok[size_t(j) + 1]) +
               "\" out of range (" + std::to_string(nv) + " vertices)"));
      if (j == 0) first = uint32_t(idx);
      if (j >= 2) m.indices.insert(m.indices.end(), {first, prev, uint32_t(idx)});
      prev = uint32_t(idx);
    }
  }
  *mesh = std::move(m);
  return true;
}

// One text row per vertex (position, then normal and uv where present) and per triangle
// ("3 a b c", then the face index where wanted): the body OFF and ASCII PLY share.
void append_vertex_rows(std::string* out, const Mesh& m) {
  const bool n = !m.normals.empty(), t = !m.uvs.empty();
  for (size_t i = 0; i < m.num_vertices(); ++i) {
    for (int k = 0; k < 3; ++k) {
      if (k) *out += ' ';
      append_float(out, m.positions[3 * i + size_t(k)]);
    }
    for (int k = 0; n && k < 3; ++k) {
      *out += ' ';
      append_float(out, m.normals[3 * i + size_t(k)]);
    }
    for (int k = 0; t && k < 2; ++k) {
      *out += ' ';
      append_float(out, m.uvs[2 * i + size_t(k)]);
    }
    *out += '\n';
  }
}

void append_face_rows(std::string* out, const Mesh& m, bool face_indices) {
  for (size_t f = 0; f < m.num_triangles(); ++f) {
    *out += '3';
    for (int k = 0; k < 3; ++k) {
      *out += ' ';
      append_uint(out, m.indices[3 * f + size_t(k)]);
    }
    if (face_indices) {
      *out += ' ';
      append_int(out, m.face_indices[f]);
    }
    *out += '\n';
  }
}

std::string off_text(const Mesh& m) {
  const bool n = !m.normals.empty(), t = !m.uvs.empty();
  std::string out = std::string(t ? "ST" : "") + (n ? "N" : "") + "OFF\n";
  out += "# written by pbrt-mesh\n";
  append_uint(&out, m.num_vertices());
  out += ' ';
  append_uint(&out, m.num_triangles());
  out += " 0\n";
  append_vertex_rows(&out, m);
  append_face_rows(&out, m, false);
  return out;
}

// ---- STL ----

// STL repeats every vertex in every facet; vertices with bitwise-equal positions are welded so
// the mesh is indexed (what OpenMesh's STL reader does too). Facet normals are dropped: a Mesh
// holds per-vertex normals only.
class Welder {
 public:
  explicit Welder(Mesh* m) : m_(m) {}
  uint32_t add(const float p[3]) {
    Key k;
    std::memcpy(k.bits, p, sizeof k.bits);
    // -0 and +0 are the same point.
    for (uint32_t& b : k.bits)
      if (b == 0x80000000u) b = 0;
    auto [it, added] = ids_.emplace(k, uint32_t(ids_.size()));
    if (added) m_->positions.insert(m_->positions.end(), p, p + 3);
    return it->second;
  }

 private:
  struct Key {
    uint32_t bits[3];
    bool operator==(const Key& o) const { return std::memcmp(bits, o.bits, sizeof bits) == 0; }
  };
  struct KeyHash {
    size_t operator()(const Key& k) const {
      return (uint64_t(k.bits[0]) * 0x9E3779B97F4A7C15ull) ^ (uint64_t(k.bits[1]) * 0xC2B2AE3Dull) ^
             (uint64_t(k.bits[2]) << 17);
    }
  };
  Mesh* m_;
  std::unordered_map<Key, uint32_t, KeyHash> ids_;
};

bool read_stl(const std::string& path, std::string_view bytes, Mesh* mesh, std::string* error,
              bool quiet) {
  Progress progress(path, bytes.size(), quiet);
  Mesh m;
  Welder weld(&m);
  uint32_t count = 0;
  if (bytes.size() >= 84) std::memcpy(&count, bytes.data() + 80, 4);  // little-endian hosts
  const bool binary = bytes.size() >= 84 && uint64_t(bytes.size()) == 84 + 50 * uint64_t(count);
  size_t first = 0;
  while (first < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[first]))) ++first;
  const bool ascii = !binary && bytes.substr(first, 5) == "solid";
  if (binary) {
    m.indices.reserve(size_t(count) * 3);
    for (uint32_t t = 0; t < count; ++t) {
      if ((t & 0xffff) == 0) progress.update(84 + size_t(t) * 50);
      const char* rec = bytes.data() + 84 + size_t(t) * 50;
      for (int k = 0; k < 3; ++k) {
        float p[3];
        std::memcpy(p, rec + 12 + 12 * k, 12);
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
          return fail(error, path, "triangle " + std::to_string(t) + ": coordinate is not finite");
        m.indices.push_back(weld.add(p));
      }
    }
  } else if (ascii) {
    LineScanner scan(bytes);
    std::vector<std::string_view> tok;
    std::vector<uint32_t> loop;
    bool in_loop = false;
    while (scan.next(&tok)) {
      progress.update(scan.offset());
      if (tok.empty()) continue;
      auto at = [&](const std::string& what) {
        return "line " + std::to_string(scan.line()) + ": " + what;
      };
      if (tok[0] == "outer") {
        if (in_loop) return fail(error, path, at("nested outer loop"));
        in_loop = true;
        loop.clear();
      } else if (tok[0] == "vertex") {
        float p[3];
        if (!in_loop) return fail(error, path, at("vertex outside a facet's loop"));
        if (tok.size() != 4 || !parse_float(tok[1], &p[0]) || !parse_float(tok[2], &p[1]) ||
            !parse_float(tok[3], &p[2]))
          return fail(error, path, at("a vertex needs 3 finite numbers"));
        loop.push_back(weld.add(p));
      } else if (tok[0] == "endloop") {
        if (!in_loop || loop.size() < 3) return fail(error, path, at("a facet needs 3 vertices"));
        for (size_t k = 1; k + 1 < loop.size(); ++k)
          m.indices.insert(m.indices.end(), {loop[0], loop[k], loop[k + 1]});
        in_loop = false;
      }
      // solid, facet normal, endfacet, endsolid: nothing to keep.
    }
    if (in_loop) return fail(error, path, "file ends inside a facet");
  } else if (bytes.size() >= 84) {
    return fail(error, path,
                "binary STL header says " + std::to_string(count) + " triangles (" +
                    std::to_string(84 + 50 * uint64_t(count)) + " bytes) but the file has " +
                    std::to_string(bytes.size()) + " bytes");
  } else {
    return fail(error, path, "not an STL file (too short for binary, no \"solid\")");
  }
  if (m.indices.empty()) return fail(error, path, "no triangles");
  *mesh = std::move(m);
  return true;
}

std::string stl_bytes(const Mesh& m) {
  std::string out(84 + 50 * m.num_triangles(), '\0');
  const char header[] = "binary STL written by pbrt-mesh";
  std::memcpy(&out[0], header, sizeof header - 1);
  const uint32_t n = uint32_t(m.num_triangles());
  std::memcpy(&out[80], &n, 4);
  for (size_t t = 0; t < m.num_triangles(); ++t) {
    const float* p[3];
    for (int k = 0; k < 3; ++k) p[k] = &m.positions[3 * size_t(m.indices[3 * t + size_t(k)])];
    // STL stores a facet normal; compute it from the triangle (zero for a degenerate one).
    const double e1[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
    const double e2[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
    double nrm[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                     e1[0] * e2[1] - e1[1] * e2[0]};
    const double len = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
    float fn[3] = {0, 0, 0};
    if (len > 0)
      for (int k = 0; k < 3; ++k) fn[k] = float(nrm[k] / len);
    char* rec = &out[84 + 50 * t];
    std::memcpy(rec, fn, 12);
    for (int k = 0; k < 3; ++k) std::memcpy(rec + 12 + 12 * k, p[k], 12);
  }
  return out;
}

// ---- PLY (ASCII writer; binary goes through compiler/ply_writer) ----

std::string ply_ascii_text(const Mesh& m) {
  const bool n = !m.normals.empty(), t = !m.uvs.empty(), fi = !m.face_indices.empty();
  std::string out = "ply\nformat ascii 1.0\ncomment written by pbrt-mesh\nelement vertex ";
  append_uint(&out, m.num_vertices());
  out += "\nproperty float x\nproperty float y\nproperty float z\n";
  if (n) out += "property float nx\nproperty float ny\nproperty float nz\n";
  if (t) out += "property float u\nproperty float v\n";
  out += "element face ";
  append_uint(&out, m.num_triangles());
  out += "\nproperty list uchar uint vertex_indices\n";
  if (fi) out += "property int face_indices\n";
  out += "end_header\n";
  append_vertex_rows(&out, m);
  append_face_rows(&out, m, fi);
  return out;
}

bool write_ply_file(const std::string& path, const Mesh& m, bool ascii, std::string* error) {
  if (ascii) return write_atomically(path, ply_ascii_text(m), error);
  std::string reason;
  if (!pbrtc::write_ply(path, pbrta::arrays_of(m), &reason)) return fail(error, path, reason);
  return true;
}

// ---- pbrt ----

// Merges every mesh shape of the scene, in object space: a shape file is usually an Include'd
// piece of a scene, and object space is what it holds (applying the transforms would bake the
// placement of one scene into the mesh). Shapes inside ObjectBegin/End count once, however many
// times they are instanced.
bool read_pbrt(const std::string& path, std::string_view text, Mesh* mesh, std::string* error) {
  pbrtc::SourceFiles files;
  std::ostringstream messages;
  pbrtc::Diagnostics diag(&files, &messages);
  pbrtc::SceneDesc scene;
  bool ok;
  if (text.find("WorldBegin") != std::string_view::npos) {
    ok = pbrtc::build_scene(path, &files, &diag, &scene);
  } else {
    // A file of shapes (what write_mesh writes): wrap it in a world block. Relative plymesh
    // names then resolve against the file's own directory, as they do when the file is
    // Included by a scene in that directory.
    std::string quoted;
    for (char c : path) {
      if (c == '"' || c == '\\') quoted += '\\';
      quoted += c;
    }
    // The wrapper gets a name of its own: the parser takes an in-memory text's name for a file
    // being read, and the Include of the real file would otherwise look like a cycle.
    ok = pbrtc::build_scene_from_string("<world block around " + path + ">",
                                        "WorldBegin\nInclude \"" + quoted + "\"\nWorldEnd\n",
                                        directory_of(path), &files, &diag, &scene);
  }
  if (!ok || diag.failed()) {
    for (const pbrtc::Diagnostic& d : diag.all())
      if (d.severity == pbrtc::Severity::kError) {
        // The located message ("file:line:col: error: ..."), without the include chain our
        // world-block wrapper adds in front of it.
        if (error)
          *error = d.loc.valid() ? files.format(d.loc) + ": " + d.message : path + ": " + d.message;
        return false;
      }
    return fail(error, path, "pbrtc could not build the scene");
  }
  Mesh m;
  size_t used = 0;
  bool all_n = true, all_uv = true, all_fi = true;
  for (const pbrtc::ShapeDesc& s : scene.shapes) {
    if (s.mesh == pbrtc::kNone) continue;
    const pbrtc::TriangleMesh& t = scene.meshes[size_t(s.mesh)];
    ++used;
    all_n = all_n && !t.N.empty();
    all_uv = all_uv && !t.uv.empty();
    all_fi = all_fi && !t.face_indices.empty();
  }
  if (used == 0) return fail(error, path, "no trianglemesh, plymesh or refined shape");
  for (const pbrtc::ShapeDesc& s : scene.shapes) {
    if (s.mesh == pbrtc::kNone) continue;
    const pbrtc::TriangleMesh& t = scene.meshes[size_t(s.mesh)];
    const uint64_t base = m.num_vertices();
    if (base + t.num_vertices() > 0xffffffffull)
      return fail(error, path, "the merged mesh has more than 2^32 - 1 vertices");
    m.positions.insert(m.positions.end(), t.P.begin(), t.P.end());
    if (all_n) m.normals.insert(m.normals.end(), t.N.begin(), t.N.end());
    if (all_uv) m.uvs.insert(m.uvs.end(), t.uv.begin(), t.uv.end());
    if (all_fi)
      m.face_indices.insert(m.face_indices.end(), t.face_indices.begin(), t.face_indices.end());
    for (uint32_t i : t.indices) m.indices.push_back(uint32_t(base + i));
  }
  *mesh = std::move(m);
  return true;
}

void append_array(std::string* out, const char* decl, const float* v, size_t n) {
  *out += "  \"";
  *out += decl;
  *out += "\" [";
  for (size_t i = 0; i < n; ++i) {
    *out += (i % 12 == 0) ? "\n    " : " ";
    append_float(out, v[i]);
  }
  *out += "\n  ]\n";
}

std::string pbrt_inline_text(const Mesh& m) {
  std::string out = "# written by pbrt-mesh: " + std::to_string(m.num_vertices()) + " vertices, " +
                    std::to_string(m.num_triangles()) + " triangles\n" +
                    "Shape \"trianglemesh\"\n  \"integer indices\" [";
  for (size_t i = 0; i < m.indices.size(); ++i) {
    out += (i % 15 == 0) ? "\n    " : " ";
    append_uint(&out, m.indices[i]);
  }
  out += "\n  ]\n";
  append_array(&out, "point P", m.positions.data(), m.positions.size());
  if (!m.normals.empty()) append_array(&out, "normal N", m.normals.data(), m.normals.size());
  if (!m.uvs.empty()) append_array(&out, "float uv", m.uvs.data(), m.uvs.size());
  if (!m.face_indices.empty()) {
    out += "  \"integer faceIndices\" [";
    for (size_t i = 0; i < m.face_indices.size(); ++i) {
      out += (i % 15 == 0) ? "\n    " : " ";
      append_int(&out, m.face_indices[i]);
    }
    out += "\n  ]\n";
  }
  return out;
}

std::string quoted_pbrt_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

bool write_pbrt(const std::string& path, const Mesh& m, const WriteOptions& options,
                std::string* error) {
  if (options.pbrt == PbrtStyle::kInline) return write_atomically(path, pbrt_inline_text(m), error);
  // plymesh: the PLY goes beside the .pbrt under the same stem, named relative to it (pbrt
  // resolves a relative name against the including scene's directory, which is where a shape
  // file written beside its scene lives).
  std::string name = file_name_of(path);
  if (const size_t dot = name.find_last_of('.'); dot != std::string::npos) name.resize(dot);
  name += ".ply";
  const std::string ply_path = directory_of(path) + "/" + name;
  if (!write_ply_file(ply_path, m, options.ply_ascii, error)) return false;
  const std::string text = "# written by pbrt-mesh: " + std::to_string(m.num_vertices()) +
                           " vertices, " + std::to_string(m.num_triangles()) + " triangles\n" +
                           "Shape \"plymesh\" \"string filename\" " + quoted_pbrt_string(name) +
                           "\n";
  if (!write_atomically(path, text, error)) {
    std::remove(ply_path.c_str());
    return false;
  }
  return true;
}

// ---- Draco ----

bool read_drc(const std::string& path, std::string_view bytes, Mesh* mesh, std::string* error) {
  pbrta::DecodedMesh d;
  std::string reason;
  if (!pbrta::draco_decode_isolated(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(),
                                    &d, &reason))
    return fail(error, path, reason);
  Mesh m;
  m.positions = std::move(d.positions);
  m.normals = std::move(d.normals);
  m.uvs = std::move(d.uv);
  m.indices = std::move(d.indices);
  m.face_indices = std::move(d.face_indices);
  *mesh = std::move(m);
  return true;
}

bool write_drc(const std::string& path, const Mesh& m, const WriteOptions& options,
               std::string* error) {
  if (options.draco_bits < pbrta::kDracoMinPositionBits ||
      options.draco_bits > pbrta::kDracoMaxPositionBits)
    return fail(error, path,
                "Draco position bits must be " + std::to_string(pbrta::kDracoMinPositionBits) +
                    " to " + std::to_string(pbrta::kDracoMaxPositionBits));
  const pbrta::MeshArrays a = pbrta::arrays_of(m);
  pbrta::DracoOptions opt;
  opt.position_bits = options.draco_bits;
  opt.sequential = options.draco_sequential;
  std::vector<uint8_t> out;
  std::string reason;
  if (!pbrta::draco_encode(a, opt, &out, &reason)) return fail(error, path, reason);
  return write_atomically(path, std::string(out.begin(), out.end()), error);
}

}  // namespace

std::string extension_of(const std::string& path) {
  const std::string name = file_name_of(path);
  const size_t dot = name.find_last_of('.');
  if (dot == std::string::npos || dot == 0) return "";
  std::string ext = name.substr(dot + 1);
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

bool read_mesh(const std::string& path, Mesh* mesh, std::string* error, bool quiet,
               std::vector<std::string>* warnings) {
  *mesh = Mesh();
  const std::string ext = extension_of(path);
  Mesh m;
  if (ext == "ply") {
    // The PLY reader checks the file is non-empty itself, but say so in our words.
    std::string bytes;
    if (!read_bytes(path, &bytes, error)) return false;
    Progress progress(path, bytes.size(), quiet);
    progress.note("reading");
    pbrtc::PlyMesh p;
    pbrtc::PlyError pe;
    std::vector<std::string> said;
    if (!pbrtc::parse_ply(bytes, &p, &pe, &said)) return fail(error, path, pe.message);
    if (warnings != nullptr)
      for (const std::string& w : said) warnings->push_back(path + ": " + w);
    m.positions = std::move(p.positions);
    m.normals = std::move(p.normals);
    m.uvs = std::move(p.uvs);
    m.indices = std::move(p.indices);
    m.face_indices = std::move(p.face_indices);
  } else if (ext == "drc" || ext == "obj" || ext == "off" || ext == "stl" || ext == "pbrt") {
    std::string bytes;
    if (!read_bytes(path, &bytes, error)) return false;
    bool ok = false;
    if (ext == "drc") {
      Progress progress(path, bytes.size(), quiet);
      progress.note("decoding");
      ok = read_drc(path, bytes, &m, error);
    } else if (ext == "obj") {
      ok = read_obj(path, bytes, &m, error, quiet);
    } else if (ext == "off") {
      ok = read_off(path, bytes, &m, error, quiet);
    } else if (ext == "stl") {
      ok = read_stl(path, bytes, &m, error, quiet);
    } else {
      ok = read_pbrt(path, bytes, &m, error);
    }
    if (!ok) return false;
  } else {
    return fail(error, path,
                ext.empty() ? "no file extension to tell the format by"
                            : "unknown mesh format \"." + ext + "\"");
  }
  std::string reason;
  if (!check_mesh(m, &reason)) return fail(error, path, reason);
  *mesh = std::move(m);
  return true;
}

bool write_mesh(const std::string& path, const Mesh& mesh, const WriteOptions& options,
                std::string* error) {
  const std::string ext = extension_of(path);
  std::string reason;
  if (!check_mesh(mesh, &reason)) return fail(error, path, "invalid mesh: " + reason);
  if (mesh.num_triangles() == 0 && ext != "ply" && ext != "obj" && ext != "off")
    return fail(error, path, "the mesh has no triangles");
  if (ext == "ply") return write_ply_file(path, mesh, options.ply_ascii, error);
  if (ext == "drc") return write_drc(path, mesh, options, error);
  if (ext == "obj") return write_atomically(path, obj_text(mesh), error);
  if (ext == "off") return write_atomically(path, off_text(mesh), error);
  if (ext == "stl") {
    if (mesh.num_triangles() > 0xffffffffull) return fail(error, path, "too many triangles");
    return write_atomically(path, stl_bytes(mesh), error);
  }
  if (ext == "pbrt") return write_pbrt(path, mesh, options, error);
  return fail(error, path,
              ext.empty() ? "no file extension to tell the format by"
                          : "unknown mesh format \"." + ext + "\"");
}

}  // namespace meshtools
