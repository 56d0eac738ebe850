// runtime/material/materials.h — the scene's materials (book chapter 9) as
// plain data, turned into a Bsdf at each shading point.
//
// MaterialSet::build() reads every archive.materials record (indices are the
// archive's, as ShapeRecord.material uses them): matte, plastic, metal,
// mirror, glass, uber, substrate, translucent, fourier (its table read in
// place from the archive, which must outlive the set), disney (not its subsurface
// scattering: see disney_material.h), hair (on curves: v across the fiber is
// its offset h), mix and the interface material
// "none". Anything else fails with "not supported yet: <type> material
// (file:line)". compute_bsdf() follows each pbrt-v3 material's
// ComputeScatteringFunctions: bump mapping first (it updates si's shading
// frame, which the Bsdf then uses), then the lobes. Mix materials weight the
// first named material's lobes by `amount` and the second's by 1 - amount,
// as pbrt-v3's MixMaterial does (s1 = amount goes to namedmaterial1).
//
// Thread safety: read-only after build(); the TextureSet passed to build()
// must outlive the set.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "format/scene_archive.h"
#include "runtime/core/interaction.h"
#include "runtime/material/bsdf.h"
#include "runtime/material/bssrdf.h"
#include "runtime/material/disney_material.h"
#include "runtime/material/fourier_bxdf.h"
#include "runtime/texture/textures.h"

namespace rt {

enum class MaterialKind : uint8_t {
  kNone,
  kMatte,
  kPlastic,
  kMetal,
  kMirror,
  kGlass,
  kUber,
  kSubstrate,
  kTranslucent,
  kDisney,
  kFourier,
  kMix,
  kSubsurface,  // subsurface and kdsubsurface: glass's lobes and a BSSRDF
  kHair,
};

// Where the hair material's absorption comes from: pbrt-v3's order of precedence.
enum class HairAbsorption : uint8_t { kSigmaA, kColor, kMelanin };

// One material's inputs; which fields a kind reads is in materials.cpp.
struct MaterialNode {
  MaterialKind kind = MaterialKind::kNone;
  bool has_bump = false;
  bool remap_roughness = true;
  FloatInput bump;
  RgbInput kd, ks, kr, kt, opacity, reflect, transmit;
  RgbInput metal_eta, metal_k;
  RgbInput amount;  // mix
  FloatInput sigma, roughness, uroughness, vroughness, eta;
  uint32_t mix[2] = {kNone, kNone};
  DisneyInputs disney;
  const FourierTable* fourier = nullptr;  // kFourier: owned by the set
  // kSubsurface: the coefficients (sigma_a, sigma_s), or for kdsubsurface the
  // diffuse reflectance (kd) and mean free path they derive from; times scale.
  RgbInput sigma_a, sigma_s, mfp;
  bool from_diffuse = false;
  float ss_scale = 1;
  const BssrdfTable* bssrdf = nullptr;  // owned by the set
  // kHair (also eta, and sigma_a when given; without any absorption input sigma_a holds
  // pbrt-v3's default, eumelanin 1.3).
  HairAbsorption hair_absorption = HairAbsorption::kSigmaA;
  RgbInput hair_color;
  FloatInput eumelanin, pheomelanin, beta_m, beta_n, alpha;
};

class MaterialSet {
 public:
  bool build(const pbrta::SceneArchive& archive, const TextureSet& textures, std::string* error);

  uint32_t size() const { return uint32_t(nodes_.size()); }
  const MaterialNode& node(uint32_t material) const { return nodes_[material]; }
  // Type "none": no BSDF, rays pass through (the surface only bounds media).
  bool is_interface(uint32_t material) const {
    return nodes_[material].kind == MaterialKind::kNone;
  }

  // For a subsurface material, after compute_bsdf (which bump-mapped si): its BSSRDF at si,
  // pbrt-v3's TabulatedBSSRDF, or for a solid disney material with a scatter distance there
  // its DisneyBSSRDF. False for any other material (a mix carries none, as in pbrt-v3).
  bool compute_bssrdf(uint32_t material, const SurfaceInteraction& si, Bssrdf* out) const;

  // Applies bump mapping (updating si's shading frame) and fills *bsdf.
  // False, with *bsdf untouched, for the interface material.
  bool compute_bsdf(uint32_t material, SurfaceInteraction* si, TransportMode mode,
                    bool allow_multiple_lobes, Bsdf* bsdf) const;

 private:
  void add_lobes(const MaterialNode& m, const SurfaceInteraction& si, TransportMode mode,
                 bool allow_multiple_lobes, Bsdf* bsdf) const;

  const TextureSet* textures_ = nullptr;
  std::vector<MaterialNode> nodes_;
  // unique_ptr: nodes point at their tables, which must not move with the set.
  std::vector<std::unique_ptr<FourierTable>> fourier_tables_;
  std::vector<std::unique_ptr<BssrdfTable>> bssrdf_tables_;
};

}  // namespace rt
