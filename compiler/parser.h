// compiler/parser.h — pbrt-v3 scene syntax to directive calls.
//
// The parser reads directives and their parameter lists from the lexer and calls
// a ParserTarget once per directive, with the directive's location. It knows the
// syntax (what arguments each directive takes, how a parameter is declared,
// how values are written) and nothing of meaning: the scene builder gives the
// calls pbrt-v3's semantics. Include is handled here: the named file (resolved
// against the top-level file's directory, as pbrt-v3 resolves every relative
// path) is read in place, with cycles and missing files reported at the
// Include. On a syntax error the parser reports it and skips to the next
// directive name, so one run reports many errors.
#pragma once

#include <array>
#include <string>
#include <string_view>

#include "compiler/diagnostics.h"
#include "compiler/params.h"
#include "compiler/source_files.h"

namespace pbrtc {

enum class ActiveTransform { kStart, kEnd, kAll };

// One call per directive. The ParamList is only valid during the call.
class ParserTarget {
 public:
  virtual ~ParserTarget() = default;
  virtual void Accelerator(Loc, std::string_view type, const ParamList&) = 0;
  virtual void ActiveTransformDirective(Loc, ActiveTransform) = 0;
  virtual void AreaLightSource(Loc, std::string_view type, const ParamList&) = 0;
  virtual void AttributeBegin(Loc) = 0;
  virtual void AttributeEnd(Loc) = 0;
  virtual void Camera(Loc, std::string_view type, const ParamList&) = 0;
  virtual void ConcatTransform(Loc, const std::array<double, 16>& m) = 0;
  virtual void CoordinateSystem(Loc, std::string_view name) = 0;
  virtual void CoordSysTransform(Loc, std::string_view name) = 0;
  virtual void Film(Loc, std::string_view type, const ParamList&) = 0;
  virtual void Identity(Loc) = 0;
  virtual void Integrator(Loc, std::string_view type, const ParamList&) = 0;
  virtual void LightSource(Loc, std::string_view type, const ParamList&) = 0;
  virtual void LookAt(Loc, const std::array<double, 9>& v) = 0;
  virtual void MakeNamedMaterial(Loc, std::string_view name, const ParamList&) = 0;
  virtual void MakeNamedMedium(Loc, std::string_view name, const ParamList&) = 0;
  virtual void Material(Loc, std::string_view type, const ParamList&) = 0;
  virtual void MediumInterface(Loc, std::string_view inside, std::string_view outside) = 0;
  virtual void NamedMaterial(Loc, std::string_view name) = 0;
  virtual void ObjectBegin(Loc, std::string_view name) = 0;
  virtual void ObjectEnd(Loc) = 0;
  virtual void ObjectInstance(Loc, std::string_view name) = 0;
  virtual void PixelFilter(Loc, std::string_view type, const ParamList&) = 0;
  virtual void ReverseOrientation(Loc) = 0;
  virtual void Rotate(Loc, double angle, double x, double y, double z) = 0;
  virtual void Sampler(Loc, std::string_view type, const ParamList&) = 0;
  virtual void Scale(Loc, double x, double y, double z) = 0;
  virtual void Shape(Loc, std::string_view type, const ParamList&) = 0;
  virtual void Texture(Loc, std::string_view name, std::string_view klass, std::string_view type,
                       const ParamList&) = 0;
  virtual void Transform(Loc, const std::array<double, 16>& m) = 0;
  virtual void TransformBegin(Loc) = 0;
  virtual void TransformEnd(Loc) = 0;
  virtual void TransformTimes(Loc, double start, double end) = 0;
  virtual void Translate(Loc, double x, double y, double z) = 0;
  virtual void WorldBegin(Loc) = 0;
  virtual void WorldEnd(Loc) = 0;
  // Called once when the input ends (after the last file), with the location
  // of its end, so the target can report blocks left open. The Loc is invalid
  // when a lexical error (already reported) cut the input short: then nothing
  // left open should be reported.
  virtual void EndOfInput(Loc) = 0;
};

struct ParseOptions {
  int max_include_depth = 64;
};

// Parses one top-level scene file (path "-" reads standard input). base_dir is
// the directory relative paths resolve against (the top-level file's).
// Returns false if any error was reported.
bool parse_file(const std::string& path, SourceFiles* files, Diagnostics* diag,
                ParserTarget* target, const ParseOptions& options = {});
// Parses text held in memory as if it were a file named display_path whose
// relative paths resolve against base_dir (tests, fuzzing).
bool parse_string(const std::string& display_path, std::string text, const std::string& base_dir,
                  SourceFiles* files, Diagnostics* diag, ParserTarget* target,
                  const ParseOptions& options = {});

// The directory pbrt-v3 resolves a top-level file's relative paths against
// ("" for the current directory); and a path resolved against it.
std::string directory_of(const std::string& path);
std::string resolve_path(const std::string& base_dir, std::string_view path);

}  // namespace pbrtc
