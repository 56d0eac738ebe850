// compiler/scene_builder.h — pbrt-v3's meaning of the directives.
//
// SceneBuilder receives the parser's directive calls and keeps pbrt-v3's
// render options and graphics state: the transform stack with start and end
// transforms (ActiveTransform, TransformTimes), attribute blocks, the current
// material, area light, reverse orientation and media; named materials and
// float/spectrum textures (scoped to attribute blocks), named media,
// coordinate systems and object definitions (global). Every entity is
// resolved as it is met, as pbrt-v3 resolves it, into a SceneDesc.
//
// Violations of pbrt-v3's rules (world directives before WorldBegin,
// unbalanced blocks, undefined names, ...) are reported through Diagnostics
// with the directive's location; building continues so one run reports many.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "compiler/diagnostics.h"
#include "compiler/param_resolver.h"
#include "compiler/parser.h"
#include "compiler/scene_desc.h"

namespace pbrtc {

struct BuildProgress;

class SceneBuilder final : public ParserTarget {
 public:
  // base_dir: the top-level scene file's directory (relative paths resolve
  // against it). The builder fills *scene.
  SceneBuilder(SceneDesc* scene, Diagnostics* diag, const SourceFiles* files, std::string base_dir,
               BuildProgress* progress = nullptr);
  ~SceneBuilder() override;

  void Accelerator(Loc, std::string_view type, const ParamList&) override;
  void ActiveTransformDirective(Loc, ActiveTransform) override;
  void AreaLightSource(Loc, std::string_view type, const ParamList&) override;
  void AttributeBegin(Loc) override;
  void AttributeEnd(Loc) override;
  void Camera(Loc, std::string_view type, const ParamList&) override;
  void ConcatTransform(Loc, const std::array<double, 16>& m) override;
  void CoordinateSystem(Loc, std::string_view name) override;
  void CoordSysTransform(Loc, std::string_view name) override;
  void Film(Loc, std::string_view type, const ParamList&) override;
  void Identity(Loc) override;
  void Integrator(Loc, std::string_view type, const ParamList&) override;
  void LightSource(Loc, std::string_view type, const ParamList&) override;
  void LookAt(Loc, const std::array<double, 9>& v) override;
  void MakeNamedMaterial(Loc, std::string_view name, const ParamList&) override;
  void MakeNamedMedium(Loc, std::string_view name, const ParamList&) override;
  void Material(Loc, std::string_view type, const ParamList&) override;
  void MediumInterface(Loc, std::string_view inside, std::string_view outside) override;
  void NamedMaterial(Loc, std::string_view name) override;
  void ObjectBegin(Loc, std::string_view name) override;
  void ObjectEnd(Loc) override;
  void ObjectInstance(Loc, std::string_view name) override;
  void PixelFilter(Loc, std::string_view type, const ParamList&) override;
  void ReverseOrientation(Loc) override;
  void Rotate(Loc, double angle, double x, double y, double z) override;
  void Sampler(Loc, std::string_view type, const ParamList&) override;
  void Scale(Loc, double x, double y, double z) override;
  void Shape(Loc, std::string_view type, const ParamList&) override;
  void Texture(Loc, std::string_view name, std::string_view klass, std::string_view type,
               const ParamList&) override;
  void Transform(Loc, const std::array<double, 16>& m) override;
  void TransformBegin(Loc) override;
  void TransformEnd(Loc) override;
  void TransformTimes(Loc, double start, double end) override;
  void Translate(Loc, double x, double y, double z) override;
  void WorldBegin(Loc) override;
  void WorldEnd(Loc) override;
  void EndOfInput(Loc) override;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

// Called while a scene builds, so long compiles can show counts: after every
// shape (the callee throttles by time), then once per phase ("PLY meshes",
// "images") before it starts. Runs on the building thread; must be cheap.
struct BuildProgress {
  virtual ~BuildProgress() = default;
  virtual void shapes(const SceneDesc& scene) = 0;
  virtual void phase(const char* name, size_t items) = 0;
};

// Parses and builds one top-level scene file ("-" for standard input).
// Returns false if any error was reported (the SceneDesc is then incomplete).
bool build_scene(const std::string& path, SourceFiles* files, Diagnostics* diag, SceneDesc* scene,
                 BuildProgress* progress = nullptr);
// The same for scene text in memory; relative paths resolve against base_dir.
bool build_scene_from_string(const std::string& display_path, std::string text,
                             const std::string& base_dir, SourceFiles* files, Diagnostics* diag,
                             SceneDesc* scene);

}  // namespace pbrtc
