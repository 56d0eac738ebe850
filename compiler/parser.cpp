#include "compiler/parser.h"

#include <unistd.h>

#include <algorithm>
#include <climits>
#include <cstdlib>
#include <iostream>
#include <iterator>
#include <memory>
#include <sstream>

#include "compiler/lexer.h"

namespace pbrtc {

std::string directory_of(const std::string& path) {
  size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return "";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

std::string resolve_path(const std::string& base_dir, std::string_view path) {
  if (path.empty() || path[0] == '/' || base_dir.empty()) return std::string(path);
  std::string out = base_dir;
  if (out.back() != '/') out += '/';
  out += path;
  return out;
}

namespace {

enum class Dir {
  kAccelerator,
  kActiveTransform,
  kAreaLightSource,
  kAttributeBegin,
  kAttributeEnd,
  kCamera,
  kConcatTransform,
  kCoordinateSystem,
  kCoordSysTransform,
  kFilm,
  kIdentity,
  kInclude,
  kIntegrator,
  kLightSource,
  kLookAt,
  kMakeNamedMaterial,
  kMakeNamedMedium,
  kMaterial,
  kMediumInterface,
  kNamedMaterial,
  kObjectBegin,
  kObjectEnd,
  kObjectInstance,
  kPixelFilter,
  kReverseOrientation,
  kRotate,
  kSampler,
  kScale,
  kShape,
  kTexture,
  kTransform,
  kTransformBegin,
  kTransformEnd,
  kTransformTimes,
  kTranslate,
  kWorldBegin,
  kWorldEnd,
  // pbrt-v4 only: recognised so the message can say so.
  kV4Import,
  kV4Attribute,
  kV4ColorSpace,
  kV4Option,
};

struct DirName {
  std::string_view name;
  Dir dir;
};
// Sorted by name for binary search.
constexpr DirName kDirectives[] = {
    {"Accelerator", Dir::kAccelerator},
    {"ActiveTransform", Dir::kActiveTransform},
    {"AreaLightSource", Dir::kAreaLightSource},
    {"Attribute", Dir::kV4Attribute},
    {"AttributeBegin", Dir::kAttributeBegin},
    {"AttributeEnd", Dir::kAttributeEnd},
    {"Camera", Dir::kCamera},
    {"ColorSpace", Dir::kV4ColorSpace},
    {"ConcatTransform", Dir::kConcatTransform},
    {"CoordSysTransform", Dir::kCoordSysTransform},
    {"CoordinateSystem", Dir::kCoordinateSystem},
    {"Film", Dir::kFilm},
    {"Identity", Dir::kIdentity},
    {"Import", Dir::kV4Import},
    {"Include", Dir::kInclude},
    {"Integrator", Dir::kIntegrator},
    {"LightSource", Dir::kLightSource},
    {"LookAt", Dir::kLookAt},
    {"MakeNamedMaterial", Dir::kMakeNamedMaterial},
    {"MakeNamedMedium", Dir::kMakeNamedMedium},
    {"Material", Dir::kMaterial},
    {"MediumInterface", Dir::kMediumInterface},
    {"NamedMaterial", Dir::kNamedMaterial},
    {"ObjectBegin", Dir::kObjectBegin},
    {"ObjectEnd", Dir::kObjectEnd},
    {"ObjectInstance", Dir::kObjectInstance},
    {"Option", Dir::kV4Option},
    {"PixelFilter", Dir::kPixelFilter},
    {"ReverseOrientation", Dir::kReverseOrientation},
    {"Rotate", Dir::kRotate},
    {"Sampler", Dir::kSampler},
    {"Scale", Dir::kScale},
    {"Shape", Dir::kShape},
    {"Texture", Dir::kTexture},
    {"Transform", Dir::kTransform},
    {"TransformBegin", Dir::kTransformBegin},
    {"TransformEnd", Dir::kTransformEnd},
    {"TransformTimes", Dir::kTransformTimes},
    {"Translate", Dir::kTranslate},
    {"WorldBegin", Dir::kWorldBegin},
    {"WorldEnd", Dir::kWorldEnd},
};

bool find_directive(std::string_view name, Dir* d) {
  auto it = std::lower_bound(std::begin(kDirectives), std::end(kDirectives), name,
                             [](const DirName& a, std::string_view b) { return a.name < b; });
  if (it == std::end(kDirectives) || it->name != name) return false;
  *d = it->dir;
  return true;
}

std::string quote(std::string_view s) {
  return "'" + std::string(s) + "'";
}

std::string token_desc(const Token& t) {
  switch (t.kind) {
    case TokenKind::kEnd:
      return "end of file";
    case TokenKind::kString:
      return "\"" + std::string(t.text) + "\"";
    default:
      return quote(t.text);
  }
}

class Parser {
 public:
  Parser(SourceFiles* files, Diagnostics* diag, ParserTarget* target, std::string base_dir,
         const ParseOptions& options)
      : files_(files),
        diag_(diag),
        target_(target),
        base_dir_(std::move(base_dir)),
        options_(options) {}

  void run(uint32_t file, const std::string& canonical) {
    push(file, canonical);
    Loc end_loc;
    for (;;) {
      if (diag_->should_stop()) break;
      Token t = next();
      if (t.kind == TokenKind::kEnd) {
        end_loc = t.loc;
        break;
      }
      directive(t);
    }
    // After a lexical error the input was cut short: blocks it leaves open
    // are not the author's mistake (see ParserTarget::EndOfInput).
    target_->EndOfInput(lexers_.front()->broken() ? Loc{} : end_loc);
  }

 private:
  Lexer& lx() { return *lexers_.back(); }

  void push(uint32_t file, const std::string& canonical) {
    lexers_.push_back(std::make_unique<Lexer>(*files_, file, diag_));
    canonical_.push_back(canonical);
  }

  // The input is one token stream across Include boundaries, as in pbrt-v3:
  // an included file may end in the middle of a parameter list that the
  // including file finishes. Finished lexers are kept until the next directive
  // starts, because a view into one's unescape buffer may still be in use.
  const Token& tpeek() {
    for (;;) {
      const Token& t = lx().peek();
      if (t.kind != TokenKind::kEnd || lexers_.size() == 1) return t;
      finished_.push_back(std::move(lexers_.back()));
      lexers_.pop_back();
      canonical_.pop_back();
    }
  }
  Token tnext() {
    tpeek();
    return lx().next();
  }
  Token next() {
    finished_.clear();
    return tnext();
  }

  // After an error: skip to the next directive name in this file. A bare
  // true/false (pbrt-v4 syntax, already reported) is a value, not a directive.
  void recover() {
    for (;;) {
      const Token& t = tpeek();
      if (t.kind == TokenKind::kEnd) return;
      if (t.kind == TokenKind::kWord && t.text != "true" && t.text != "false") return;
      tnext();
    }
  }

  // A lexical error ends the top-level file early: whatever the parser would
  // then report about the directive it cut short ("got end of file") is only
  // a consequence of it, so it is not reported.
  void error(Loc loc, const std::string& message) {
    if (lx().broken()) return;
    diag_->error(loc, message);
  }

  bool expect_string(const Token& dir, const char* what, std::string* out) {
    const Token& next_token = tpeek();
    if (next_token.kind == TokenKind::kWord || next_token.kind == TokenKind::kEnd) {
      // Most likely the next directive: leave it to be read as one.
      error(next_token.loc,
            std::string(dir.text) + " needs a quoted " + what + ", got " + token_desc(next_token));
      return false;
    }
    Token t = tnext();
    if (t.kind != TokenKind::kString) {
      if (t.kind == TokenKind::kLBracket) {
        // pbrt-v3 accepts a one-element bracketed string here too.
        Token s = tnext();
        Token close = tnext();
        if (s.kind == TokenKind::kString && close.kind == TokenKind::kRBracket) {
          *out = std::string(s.text);
          return true;
        }
        t = s.kind != TokenKind::kString ? s : close;
      }
      error(t.loc, std::string(dir.text) + " needs a quoted " + what + ", got " + token_desc(t));
      recover();
      return false;
    }
    *out = std::string(t.text);
    return true;
  }

  template <size_t N>
  bool expect_numbers(const Token& dir, const char* shape, std::array<double, N>* out) {
    for (size_t i = 0; i < N; ++i) {
      const Token& t = tpeek();
      if (t.kind != TokenKind::kNumber) {
        error(t.loc, std::string(dir.text) + " needs " + std::to_string(N) + " numbers (" + shape +
                         "), got " + std::to_string(i) +
                         (t.kind == TokenKind::kEnd ? " before the end of file"
                                                    : " before " + token_desc(t)));
        recover();
        return false;
      }
      Token n = tnext();
      double v;
      if (!lx().to_double(n, &v)) {
        recover();
        return false;
      }
      (*out)[i] = v;
    }
    return true;
  }

  bool expect_matrix(const Token& dir, std::array<double, 16>* out) {
    const Token& next_token = tpeek();
    if (next_token.kind != TokenKind::kLBracket) {
      error(next_token.loc,
            std::string(dir.text) + " needs 16 numbers in [ ], got " + token_desc(next_token));
      recover();  // leaves a following directive in place
      return false;
    }
    Token open = tnext();
    scratch_.clear();
    if (!lx().read_doubles(&scratch_)) {
      recover();
      return false;
    }
    if (scratch_.size() != 16) {
      error(open.loc,
            std::string(dir.text) + " needs 16 numbers, got " + std::to_string(scratch_.size()));
      return false;
    }
    for (int i = 0; i < 16; ++i) (*out)[i] = scratch_[i];
    return true;
  }

  std::string_view keep(std::string_view s) {
    // Views into a lexer's unescape buffer die at its next token: copy them.
    bool owned = false;
    for (const auto& l : lexers_) owned = owned || l->owns(s);
    for (const auto& l : finished_) owned = owned || l->owns(s);
    if (!owned) return s;
    params_.owned_strings.emplace_back(s);
    return params_.owned_strings.back();
  }

  // Parses "type name" value pairs until the next directive. False after an
  // error (already reported and recovered from).
  bool parse_params(const Token& dir) {
    params_.clear();
    for (;;) {
      const Token& peeked = tpeek();
      if (peeked.kind == TokenKind::kWord || peeked.kind == TokenKind::kEnd) return true;
      if (peeked.kind != TokenKind::kString) {
        error(peeked.loc,
              "expected a parameter declaration such as \"float radius\" or "
              "the next directive, got " +
                  token_desc(peeked));
        tnext();
        recover();
        return false;
      }
      Token decl = tnext();
      ParsedParam p;
      p.loc = decl.loc;
      std::string_view d = keep(decl.text);
      // "type name": exactly two words.
      size_t a = d.find_first_not_of(" \t");
      size_t b = a == std::string_view::npos ? a : d.find_first_of(" \t", a);
      size_t c = b == std::string_view::npos ? b : d.find_first_not_of(" \t", b);
      size_t e = c == std::string_view::npos ? c : d.find_first_of(" \t", c);
      size_t f = e == std::string_view::npos ? e : d.find_first_not_of(" \t", e);
      if (a == std::string_view::npos || c == std::string_view::npos ||
          f != std::string_view::npos) {
        error(decl.loc,
              "malformed parameter declaration \"" + std::string(d) + "\": expected \"type name\"");
        skip_value();
        recover();
        return false;
      }
      p.type_name = d.substr(a, b - a);
      p.name = d.substr(c, e == std::string_view::npos ? std::string_view::npos : e - c);
      if (!parse_param_type(p.type_name, &p.type)) {
        error(decl.loc, "unknown parameter type '" + std::string(p.type_name) + "' in \"" +
                            std::string(d) + "\"");
        skip_value();
        recover();
        return false;
      }
      if (!parse_value(dir, &p)) {
        recover();
        return false;
      }
      params_.params.push_back(p);
    }
  }

  void skip_value() {
    const Token& t = tpeek();
    if (t.kind == TokenKind::kLBracket) {
      tnext();
      for (;;) {
        Token x = tnext();
        if (x.kind == TokenKind::kRBracket || x.kind == TokenKind::kEnd) return;
      }
    }
    if (t.kind == TokenKind::kNumber || t.kind == TokenKind::kString) tnext();
  }

  std::string param_desc(const ParsedParam& p) const {
    return "\"" + std::string(p.type_name) + " " + std::string(p.name) + "\"";
  }

  bool parse_value(const Token& dir, ParsedParam* p) {
    (void)dir;
    Token first = tpeek();
    p->value_loc = first.loc;
    bool numeric = param_type_is_numeric(p->type);
    bool bracket = first.kind == TokenKind::kLBracket;
    if (bracket) {
      tnext();
      first = tpeek();
      p->value_loc = first.loc;
    }
    // A spectrum may name a file instead of listing numbers.
    bool strings =
        !numeric || (p->type == ParamType::kSpectrum && first.kind == TokenKind::kString);
    if (first.kind == TokenKind::kWord && (first.text == "true" || first.text == "false")) {
      error(first.loc, "bare " + std::string(first.text) + " is pbrt-v4 syntax; pbrt-v3 writes \"" +
                           std::string(first.text) + "\" in quotes");
      return false;
    }
    if (!bracket && first.kind != TokenKind::kNumber && first.kind != TokenKind::kString) {
      error(first.loc,
            "parameter " + param_desc(*p) + " has no value (got " + token_desc(first) + ")");
      return false;
    }
    if (strings) {
      p->string_values = p->type != ParamType::kBool;
      std::vector<uint32_t>* bools = nullptr;
      if (p->type == ParamType::kBool)
        bools = params_.new_ints(&p->offset);
      else
        p->offset = uint32_t(params_.strings.size());
      for (;;) {
        Token t = tpeek();
        if (bracket && t.kind == TokenKind::kRBracket) {
          tnext();
          break;
        }
        if (t.kind != TokenKind::kString) {
          if (t.kind == TokenKind::kWord && (t.text == "true" || t.text == "false"))
            error(t.loc, "bare " + std::string(t.text) + " is pbrt-v4 syntax; pbrt-v3 writes \"" +
                             std::string(t.text) + "\" in quotes");
          else if (bracket && t.kind == TokenKind::kEnd)
            error(t.loc, "unterminated '[' array at end of file");
          else
            error(t.loc,
                  "parameter " + param_desc(*p) + " takes quoted strings, got " + token_desc(t));
          return false;
        }
        tnext();
        if (p->type == ParamType::kBool) {
          if (t.text == "true" || t.text == "false") {
            bools->push_back(t.text == "true");
          } else {
            error(t.loc, "value \"" + std::string(t.text) + "\" of bool parameter " +
                             param_desc(*p) + " must be \"true\" or \"false\"");
            return false;
          }
        } else {
          params_.strings.push_back(keep(t.text));
          params_.string_locs.push_back(t.loc);
        }
        ++p->count;
        if (!bracket) break;
      }
      return true;
    }
    // Numbers.
    if (p->type == ParamType::kInteger) {
      std::vector<uint32_t>* out = params_.new_ints(&p->offset);
      if (bracket) {
        if (!lx().read_integers(out)) return false;
      } else {
        Token t = tnext();
        if (t.kind != TokenKind::kNumber) {
          error(t.loc, "parameter " + param_desc(*p) + " takes integers, got " + token_desc(t));
          return false;
        }
        int32_t v;
        if (!lx().to_int(t, &v)) return false;
        out->push_back(uint32_t(v));
      }
      p->count = uint32_t(out->size());
    } else {
      std::vector<float>* out = params_.new_floats(&p->offset);
      if (bracket) {
        if (!lx().read_numbers(out)) return false;
      } else {
        Token t = tnext();
        if (t.kind != TokenKind::kNumber) {
          error(t.loc, "parameter " + param_desc(*p) + " takes numbers, got " + token_desc(t));
          return false;
        }
        float v;
        if (!lx().to_float(t, &v)) return false;
        out->push_back(v);
      }
      p->count = uint32_t(out->size());
    }
    int stride = param_type_stride(p->type);
    if (p->count == 0) {
      error(p->value_loc, "parameter " + param_desc(*p) + " has no values");
      return false;
    }
    if (p->count % stride != 0) {
      std::string unit = p->type == ParamType::kSpectrum    ? "(wavelength, value) pairs"
                         : p->type == ParamType::kBlackbody ? "(temperature, scale) pairs"
                         : param_type_is_spectrum(p->type)
                             ? "3 values per color"
                             : std::to_string(stride) + " values per element";
      std::string hint = p->type == ParamType::kBlackbody && p->count == 1
                             ? " (a lone temperature is pbrt-v4 syntax)"
                             : "";
      error(p->value_loc, "parameter " + param_desc(*p) + " needs " + unit + ", got " +
                              std::to_string(p->count) + " value" + (p->count == 1 ? "" : "s") +
                              hint);
      return false;
    }
    return true;
  }

  void include(const Token& dir) {
    std::string name;
    if (!expect_string(dir, "file name", &name)) return;
    std::string path = resolve_path(base_dir_, name);
    if (int(lexers_.size()) >= options_.max_include_depth) {
      error(dir.loc,
            "Include nested deeper than " + std::to_string(options_.max_include_depth) + " files");
      return;
    }
    char real[PATH_MAX];
    std::string canonical = ::realpath(path.c_str(), real) ? std::string(real) : path;
    for (size_t i = 0; i < canonical_.size(); ++i) {
      if (canonical_[i] == canonical) {
        error(dir.loc, "Include cycle: \"" + path + "\" is already being read");
        return;
      }
    }
    std::string err;
    uint32_t f = files_->open(path, path, dir.loc, &err);
    if (f == kNoFile) {
      error(dir.loc, "cannot open Include file \"" + path + "\": " + err);
      return;
    }
    push(f, canonical);
  }

  void directive(const Token& t) {
    if (t.kind != TokenKind::kWord) {
      if (t.kind == TokenKind::kString)
        error(t.loc, "parameter list " + token_desc(t) +
                         " without a directive before it (or a directive is misspelled)");
      else
        error(t.loc, "expected a directive, got " + token_desc(t));
      recover();
      return;
    }
    Dir d;
    if (!find_directive(t.text, &d)) {
      if (t.text == "true" || t.text == "false")
        error(t.loc, "bare " + std::string(t.text) + " is pbrt-v4 syntax; pbrt-v3 writes \"" +
                         std::string(t.text) + "\" in quotes");
      else
        error(t.loc, "unknown directive " + quote(t.text));
      recover();
      return;
    }
    std::string s1, s2, s3;
    switch (d) {
      case Dir::kV4Import:
      case Dir::kV4Attribute:
      case Dir::kV4ColorSpace:
      case Dir::kV4Option:
        error(t.loc,
              quote(t.text) + " is a pbrt-v4 directive; pbrt-v3 has no " + std::string(t.text));
        // Skip its arguments: strings, numbers and brackets up to the next word.
        recover();
        return;
      case Dir::kInclude:
        include(t);
        return;
      case Dir::kAttributeBegin:
        target_->AttributeBegin(t.loc);
        return;
      case Dir::kAttributeEnd:
        target_->AttributeEnd(t.loc);
        return;
      case Dir::kTransformBegin:
        target_->TransformBegin(t.loc);
        return;
      case Dir::kTransformEnd:
        target_->TransformEnd(t.loc);
        return;
      case Dir::kObjectEnd:
        target_->ObjectEnd(t.loc);
        return;
      case Dir::kIdentity:
        target_->Identity(t.loc);
        return;
      case Dir::kReverseOrientation:
        target_->ReverseOrientation(t.loc);
        return;
      case Dir::kWorldBegin:
        target_->WorldBegin(t.loc);
        return;
      case Dir::kWorldEnd:
        target_->WorldEnd(t.loc);
        return;
      case Dir::kActiveTransform: {
        const Token& next_token = tpeek();
        Dir unused;
        if (next_token.kind == TokenKind::kEnd ||
            (next_token.kind == TokenKind::kWord && find_directive(next_token.text, &unused))) {
          error(next_token.loc,
                "ActiveTransform needs StartTime, EndTime or All, got " + token_desc(next_token));
          return;
        }
        Token a = tnext();
        if (a.kind == TokenKind::kWord && a.text == "StartTime")
          target_->ActiveTransformDirective(t.loc, ActiveTransform::kStart);
        else if (a.kind == TokenKind::kWord && a.text == "EndTime")
          target_->ActiveTransformDirective(t.loc, ActiveTransform::kEnd);
        else if (a.kind == TokenKind::kWord && a.text == "All")
          target_->ActiveTransformDirective(t.loc, ActiveTransform::kAll);
        else {
          error(a.loc, "ActiveTransform needs StartTime, EndTime or All, got " + token_desc(a));
          recover();
        }
        return;
      }
      case Dir::kTranslate:
      case Dir::kScale: {
        std::array<double, 3> v;
        if (!expect_numbers(t, "x y z", &v)) return;
        if (d == Dir::kTranslate)
          target_->Translate(t.loc, v[0], v[1], v[2]);
        else
          target_->Scale(t.loc, v[0], v[1], v[2]);
        return;
      }
      case Dir::kRotate: {
        std::array<double, 4> v;
        if (!expect_numbers(t, "angle x y z", &v)) return;
        target_->Rotate(t.loc, v[0], v[1], v[2], v[3]);
        return;
      }
      case Dir::kLookAt: {
        std::array<double, 9> v;
        if (!expect_numbers(t, "eye, look and up points", &v)) return;
        target_->LookAt(t.loc, v);
        return;
      }
      case Dir::kTransformTimes: {
        std::array<double, 2> v;
        if (!expect_numbers(t, "start end", &v)) return;
        target_->TransformTimes(t.loc, v[0], v[1]);
        return;
      }
      case Dir::kTransform:
      case Dir::kConcatTransform: {
        std::array<double, 16> m;
        if (!expect_matrix(t, &m)) return;
        if (d == Dir::kTransform)
          target_->Transform(t.loc, m);
        else
          target_->ConcatTransform(t.loc, m);
        return;
      }
      case Dir::kCoordinateSystem:
        if (expect_string(t, "name", &s1)) target_->CoordinateSystem(t.loc, s1);
        return;
      case Dir::kCoordSysTransform:
        if (expect_string(t, "name", &s1)) target_->CoordSysTransform(t.loc, s1);
        return;
      case Dir::kNamedMaterial:
        if (expect_string(t, "material name", &s1)) target_->NamedMaterial(t.loc, s1);
        return;
      case Dir::kObjectBegin:
        if (expect_string(t, "object name", &s1)) target_->ObjectBegin(t.loc, s1);
        return;
      case Dir::kObjectInstance:
        if (expect_string(t, "object name", &s1)) target_->ObjectInstance(t.loc, s1);
        return;
      case Dir::kMediumInterface: {
        if (!expect_string(t, "medium name", &s1)) return;
        // pbrt-v3: one name sets both sides; two set inside, then outside.
        if (tpeek().kind == TokenKind::kString) {
          s2 = std::string(tnext().text);
        } else {
          s2 = s1;
        }
        target_->MediumInterface(t.loc, s1, s2);
        return;
      }
      case Dir::kTexture: {
        if (!expect_string(t, "texture name", &s1)) return;
        if (!expect_string(t, "texture class (\"float\" or \"spectrum\")", &s2)) return;
        if (!expect_string(t, "texture type", &s3)) return;
        if (!parse_params(t)) return;
        target_->Texture(t.loc, s1, s2, s3, params_);
        return;
      }
      default:
        break;
    }
    // Directives of the form: Name "string" params...
    const char* what = d == Dir::kMakeNamedMaterial || d == Dir::kMakeNamedMedium ? "name" : "type";
    if (!expect_string(t, what, &s1)) return;
    if (!parse_params(t)) return;
    switch (d) {
      case Dir::kAccelerator:
        target_->Accelerator(t.loc, s1, params_);
        break;
      case Dir::kAreaLightSource:
        target_->AreaLightSource(t.loc, s1, params_);
        break;
      case Dir::kCamera:
        target_->Camera(t.loc, s1, params_);
        break;
      case Dir::kFilm:
        target_->Film(t.loc, s1, params_);
        break;
      case Dir::kIntegrator:
        target_->Integrator(t.loc, s1, params_);
        break;
      case Dir::kLightSource:
        target_->LightSource(t.loc, s1, params_);
        break;
      case Dir::kMakeNamedMaterial:
        target_->MakeNamedMaterial(t.loc, s1, params_);
        break;
      case Dir::kMakeNamedMedium:
        target_->MakeNamedMedium(t.loc, s1, params_);
        break;
      case Dir::kMaterial:
        target_->Material(t.loc, s1, params_);
        break;
      case Dir::kPixelFilter:
        target_->PixelFilter(t.loc, s1, params_);
        break;
      case Dir::kSampler:
        target_->Sampler(t.loc, s1, params_);
        break;
      case Dir::kShape:
        target_->Shape(t.loc, s1, params_);
        break;
      default:
        break;
    }
  }

  SourceFiles* files_;
  Diagnostics* diag_;
  ParserTarget* target_;
  std::string base_dir_;
  ParseOptions options_;
  std::vector<std::unique_ptr<Lexer>> lexers_;
  std::vector<std::unique_ptr<Lexer>> finished_;
  std::vector<std::string> canonical_;
  ParamList params_;
  std::vector<double> scratch_;
};

}  // namespace

bool parse_string(const std::string& display_path, std::string text, const std::string& base_dir,
                  SourceFiles* files, Diagnostics* diag, ParserTarget* target,
                  const ParseOptions& options) {
  int errors_before = diag->error_count();
  uint32_t f = files->add_memory(display_path, std::move(text), Loc{});
  Parser parser(files, diag, target, base_dir, options);
  parser.run(f, display_path);
  return diag->error_count() == errors_before;
}

bool parse_file(const std::string& path, SourceFiles* files, Diagnostics* diag,
                ParserTarget* target, const ParseOptions& options) {
  if (path == "-") {
    std::stringstream ss;
    ss << std::cin.rdbuf();
    return parse_string("<stdin>", ss.str(), "", files, diag, target, options);
  }
  int errors_before = diag->error_count();
  std::string err;
  uint32_t f = files->open(path, path, Loc{}, &err);
  if (f == kNoFile) {
    diag->error(Loc{}, "cannot open scene file \"" + path + "\": " + err);
    return false;
  }
  char real[PATH_MAX];
  std::string canonical = ::realpath(path.c_str(), real) ? std::string(real) : path;
  Parser parser(files, diag, target, directory_of(path), options);
  parser.run(f, canonical);
  return diag->error_count() == errors_before;
}

}  // namespace pbrtc
