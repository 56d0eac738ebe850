// runtime/texture/textures.h — every texture of a scene, evaluated as pbrt-v3 does (book ch. 10).
//
// TextureSet::build() turns each archive.textures record into a plain-data
// node (a kind tag, its mapping, its parameters and its operands), so the hot
// path is a switch, never a virtual call, and never allocates. Texture
// indices are the archive's: a material parameter's ValueRecord.texture
// indexes archive.textures directly, and float_input()/rgb_input() wrap such
// a parameter as "constant or texture" with a branch-only fast path for the
// constant.
//
// Types (float and spectrum unless noted): constant, scale, mix, bilerp,
// imagemap (EWA by default, trilinear on request; the pyramid is the
// archive's), checkerboard (2-D with closed-form or no antialiasing, 3-D),
// dots, fbm, wrinkled, windy, uv (spectrum), marble (spectrum). ptex and
// anything else fail build() with "not supported yet: ... (file:line)".
//
// Thread safety: after build() the set is read-only; eval may run on any
// number of threads. The archive must outlive the set (image texels are
// read in place).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "format/scene_archive.h"
#include "runtime/core/interaction.h"
#include "runtime/core/math.h"
#include "runtime/core/rgb.h"
#include "runtime/texture/mapping.h"
#include "runtime/texture/mipmap.h"

namespace rt {

// A float-texture parameter: the constant `value` when texture == kNone,
// else the texture (an index into archive.textures).
struct FloatInput {
  float value = 0;
  uint32_t texture = kNone;
};
// A spectrum-texture parameter, likewise.
struct RgbInput {
  Rgb value;
  uint32_t texture = kNone;
};

// The parameter `param` of an entity as an input. value is the archived
// constant (the schema default when not given); it is 0 when the entity has
// no such parameter or the value has count 0 (a computed default, which the
// caller must compute as format/SCHEMA.md says).
FloatInput float_input(const pbrta::SceneArchive& archive, uint32_t entity, std::string_view param);
RgbInput rgb_input(const pbrta::SceneArchive& archive, uint32_t entity, std::string_view param);

enum class TextureKind : uint8_t {
  kConstant,
  kScale,
  kMix,
  kBilerp,
  kImage,
  kChecker2D,
  kChecker3D,
  kDots,
  kFbm,
  kWrinkled,
  kWindy,
  kMarble,
  kUv,
};

// One texture as plain data. Operands: scale (tex1, tex2), mix (tex1, tex2,
// amount = f[2]), checkerboard (tex1, tex2), dots (inside, outside) are
// f[0], f[1] for float textures and c[0], c[1] for spectrum ones.
struct TextureNode {
  TextureKind kind = TextureKind::kConstant;
  bool is_rgb = false;
  bool closed_form = true;  // checkerboard 2-D antialiasing
  bool trilinear = false;   // imagemap filtering
  Mapping2D map2;           // 2-D textures
  Mapping3D map3;           // solid textures
  FloatInput f[3];
  RgbInput c[2];
  Rgb v[4];  // constant value (v[0]); bilerp v00, v01, v10, v11
  int octaves = 8;
  float omega = .5f, scale = 1, variation = .2f;  // noise textures, marble
  float max_anisotropy = 8;
  uint32_t mipmap = kNone;  // index into the set's MIP maps
};

class TextureSet {
 public:
  // Builds a node for every archive.textures record. Fails with
  // "not supported yet: <what> (file:line)" for ptex and anything unknown.
  bool build(const pbrta::SceneArchive& archive, std::string* error);

  float eval(const FloatInput& in, const SurfaceInteraction& si) const {
    return in.texture == kNone ? in.value : eval_float(in.texture, si);
  }
  Rgb eval(const RgbInput& in, const SurfaceInteraction& si) const {
    return in.texture == kNone ? in.value : eval_rgb(in.texture, si);
  }
  // texture: an index into archive.textures naming a float texture.
  float eval_float(uint32_t texture, const SurfaceInteraction& si) const;
  // texture: an index into archive.textures naming a spectrum texture.
  Rgb eval_rgb(uint32_t texture, const SurfaceInteraction& si) const;

  uint32_t size() const { return uint32_t(nodes_.size()); }
  const TextureNode& node(uint32_t texture) const { return nodes_[texture]; }
  const MipMap& mipmap(uint32_t i) const { return mipmaps_[i]; }

 private:
  template <class T>
  T evaluate(const TextureNode& n, const SurfaceInteraction& si) const;
  float operand(const TextureNode& n, int i, const SurfaceInteraction& si, float*) const {
    return eval(n.f[i], si);
  }
  Rgb operand(const TextureNode& n, int i, const SurfaceInteraction& si, Rgb*) const {
    return eval(n.c[i], si);
  }

  std::vector<TextureNode> nodes_;
  std::vector<MipMap> mipmaps_;
};

}  // namespace rt
