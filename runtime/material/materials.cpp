// runtime/material/materials.cpp — reading material records and building
// each material's lobes as pbrt-v3's materials do.
#include "runtime/material/materials.h"

#include <string_view>

#include "format/bssrdf_table.h"
#include "runtime/material/bump.h"

namespace rt {

namespace {

// pbrt-v3's metal default: its measured copper eta and k spectra
// (src/materials/metal.cpp) through RGBSpectrum::FromSampled, the same
// numbers pbrtc's compiler/spectrum.cpp copper_eta_rgb()/copper_k_rgb() give.
constexpr Rgb kCopperEta(0.199989498f, 0.922085762f, 1.09987628f);
constexpr Rgb kCopperK(3.90463853f, 2.44763327f, 2.13765121f);

// The most lobes a material can add (pbrt-v3 holds at most 8 per BSDF).
int max_lobes(const std::vector<MaterialNode>& nodes, uint32_t m, int depth) {
  const MaterialNode& n = nodes[m];
  switch (n.kind) {
    case MaterialKind::kNone:
      return 0;
    case MaterialKind::kMatte:
    case MaterialKind::kMetal:
    case MaterialKind::kMirror:
    case MaterialKind::kSubstrate:
      return 1;
    case MaterialKind::kPlastic:
    case MaterialKind::kGlass:
    case MaterialKind::kSubsurface:
      return 2;
    case MaterialKind::kTranslucent:
      return 4;
    case MaterialKind::kUber:
      return 5;
    case MaterialKind::kDisney:
      return max_disney_lobes(n.disney);
    case MaterialKind::kFourier:
    case MaterialKind::kHair:
      return 1;
    case MaterialKind::kMix:
      if (depth > 16) return 1000;  // a cycle: reported as too many lobes
      return max_lobes(nodes, n.mix[0], depth + 1) + max_lobes(nodes, n.mix[1], depth + 1);
  }
  return 0;
}

// A spectrum parameter whose default is computed: `fallback` unless given
// (the archive may hold count 0 or the schema's placeholder then).
RgbInput rgb_or(const pbrta::SceneArchive& archive, uint32_t entity, std::string_view param,
                Rgb fallback) {
  const pbrta::ValueRecord* v = archive.value(entity, param);
  if (v && !(v->flags & pbrta::kValueGiven) && v->texture == pbrta::kNoIndex)
    return RgbInput{fallback, kNone};
  return rgb_input(archive, entity, param);
}

MicrofacetDistribution trowbridge_reitz(float urough, float vrough, bool remap) {
  MicrofacetDistribution d;
  d.kind = MicrofacetKind::kTrowbridgeReitz;
  d.alpha_x = remap ? roughness_to_alpha(urough) : urough;
  d.alpha_y = remap ? roughness_to_alpha(vrough) : vrough;
  return d;
}

// A subsurface or kdsubsurface material's scattering inputs and its profile table, which
// stays in the archive (the node points at it through a BssrdfTable the set owns).
bool read_subsurface(const pbrta::SceneArchive& archive, uint32_t e, MaterialNode* m,
                     std::vector<std::unique_ptr<BssrdfTable>>* tables, std::string* error) {
  auto rin = [&](std::string_view p) { return rgb_input(archive, e, p); };
  m->ss_scale = archive.get_float(e, "scale", 1);
  m->from_diffuse = archive.type_name(e) == "kdsubsurface";
  if (m->from_diffuse) {
    m->kd = rin("Kd");
    m->mfp = rin("mfp");
  } else {
    m->sigma_a = rin("sigma_a");
    m->sigma_s = rin("sigma_s");
  }
  pbrta::BssrdfTableView view;
  std::string why;
  if (!pbrta::bssrdf_table_of(archive, e, &view, &why)) {
    *error = archive.where(e) + ": error: " + why + " (recompile the scene with pbrtc 2.1)";
    return false;
  }
  auto table = std::make_unique<BssrdfTable>();
  table->n_rho = int(view.n_rho);
  table->n_radius = int(view.n_radius);
  table->rho = view.rho;
  table->radius = view.radius;
  table->profile = view.profile;
  table->rho_eff = view.rho_eff;
  table->cdf = view.cdf;
  m->bssrdf = table.get();
  tables->push_back(std::move(table));
  return true;
}

}  // namespace

bool MaterialSet::build(const pbrta::SceneArchive& archive, const TextureSet& textures,
                        std::string* error) {
  textures_ = &textures;
  nodes_.assign(archive.materials.size, MaterialNode{});
  for (uint32_t i = 0; i < archive.materials.size; ++i) {
    const pbrta::MaterialRecord& rec = archive.materials[i];
    uint32_t e = rec.entity;
    std::string_view type = archive.type_name(e);
    MaterialNode& m = nodes_[i];
    auto fin = [&](std::string_view p) { return float_input(archive, e, p); };
    auto rin = [&](std::string_view p) { return rgb_input(archive, e, p); };
    // metal and uber: pbrt-v3 uses u/vroughness only when given, else roughness.
    auto axis_roughness = [&](std::string_view p) {
      return archive.given(e, p) ? fin(p) : fin("roughness");
    };
    if (type == "none") {
      m.kind = MaterialKind::kNone;
      continue;
    }
    if (type == "matte") {
      m.kind = MaterialKind::kMatte;
      m.kd = rin("Kd");
      m.sigma = fin("sigma");
    } else if (type == "plastic") {
      m.kind = MaterialKind::kPlastic;
      m.kd = rin("Kd");
      m.ks = rin("Ks");
      m.roughness = fin("roughness");
    } else if (type == "metal") {
      m.kind = MaterialKind::kMetal;
      m.metal_eta = rgb_or(archive, e, "eta", kCopperEta);
      m.metal_k = rgb_or(archive, e, "k", kCopperK);
      m.uroughness = axis_roughness("uroughness");
      m.vroughness = axis_roughness("vroughness");
    } else if (type == "mirror") {
      m.kind = MaterialKind::kMirror;
      m.kr = rin("Kr");
    } else if (type == "glass" || type == "subsurface" || type == "kdsubsurface") {
      // The subsurface materials' surface is glass's (pbrt-v3 builds the same lobes).
      m.kind = type == "glass" ? MaterialKind::kGlass : MaterialKind::kSubsurface;
      m.kr = rin("Kr");
      m.kt = rin("Kt");
      m.eta = fin("eta");
      m.uroughness = fin("uroughness");
      m.vroughness = fin("vroughness");
      if (m.kind == MaterialKind::kSubsurface &&
          !read_subsurface(archive, e, &m, &bssrdf_tables_, error))
        return false;
    } else if (type == "uber") {
      m.kind = MaterialKind::kUber;
      m.kd = rin("Kd");
      m.ks = rin("Ks");
      m.kr = rin("Kr");
      m.kt = rin("Kt");
      m.opacity = rin("opacity");
      m.eta = fin("eta");
      m.uroughness = axis_roughness("uroughness");
      m.vroughness = axis_roughness("vroughness");
    } else if (type == "substrate") {
      m.kind = MaterialKind::kSubstrate;
      m.kd = rin("Kd");
      m.ks = rin("Ks");
      m.uroughness = fin("uroughness");
      m.vroughness = fin("vroughness");
    } else if (type == "translucent") {
      m.kind = MaterialKind::kTranslucent;
      m.kd = rin("Kd");
      m.ks = rin("Ks");
      m.reflect = rin("reflect");
      m.transmit = rin("transmit");
      m.roughness = fin("roughness");
    } else if (type == "disney") {
      m.kind = MaterialKind::kDisney;
      read_disney_inputs(archive, e, &m.disney);
    } else if (type == "fourier") {
      m.kind = MaterialKind::kFourier;
      auto table = std::make_unique<FourierTable>();
      if (!build_fourier_table(archive, e, table.get(), error)) return false;
      m.fourier = table.get();
      fourier_tables_.push_back(std::move(table));
    } else if (type == "hair") {
      m.kind = MaterialKind::kHair;
      // pbrt-v3's precedence (pbrtc warns about the ignored ones): sigma_a, color, melanin.
      if (archive.given(e, "sigma_a")) {
        m.hair_absorption = HairAbsorption::kSigmaA;
        m.sigma_a = rin("sigma_a");
      } else if (archive.given(e, "color")) {
        m.hair_absorption = HairAbsorption::kColor;
        m.hair_color = rin("color");
      } else if (archive.given(e, "eumelanin") || archive.given(e, "pheomelanin")) {
        m.hair_absorption = HairAbsorption::kMelanin;
        m.eumelanin = fin("eumelanin");
        m.pheomelanin = fin("pheomelanin");
      } else {
        m.hair_absorption = HairAbsorption::kSigmaA;
        m.sigma_a.value = hair_sigma_a_from_concentration(1.3f, 0);  // brown hair
      }
      m.eta = fin("eta");
      m.beta_m = fin("beta_m");
      m.beta_n = fin("beta_n");
      m.alpha = fin("alpha");
    } else if (type == "mix") {
      m.kind = MaterialKind::kMix;
      m.amount = rin("amount");
      for (int k = 0; k < 2; ++k) {
        m.mix[k] = rec.mix[k];
        if (m.mix[k] >= archive.materials.size || m.mix[k] == i) {
          *error = "mix material names a material that does not exist (" + archive.where(e) + ")";
          return false;
        }
      }
    } else {
      *error = "not supported yet: " + std::string(type) + " material (" + archive.where(e) + ")";
      return false;
    }
    if (m.kind != MaterialKind::kMix) {
      m.has_bump = archive.given(e, "bumpmap");
      if (m.has_bump) m.bump = fin("bumpmap");
      const pbrta::ValueRecord* remap = archive.value(e, "remaproughness");
      if (remap) m.remap_roughness = archive.get_int(e, "remaproughness", 1) != 0;
    }
  }
  for (uint32_t i = 0; i < nodes_.size(); ++i) {
    const MaterialNode& m = nodes_[i];
    if (m.kind != MaterialKind::kMix) continue;
    uint32_t e = archive.materials[i].entity;
    for (uint32_t part : m.mix)
      if (nodes_[part].kind == MaterialKind::kNone) {
        // pbrt-v3 has no BSDF to scale for "none" and fails; say so instead.
        *error = "not supported yet: mix material with the interface material \"none\" (" +
                 archive.where(e) + ")";
        return false;
      }
    if (max_lobes(nodes_, i, 0) > Bsdf::kMaxLobes) {
      *error =
          "not supported yet: mix material with more than 8 BSDF lobes (" + archive.where(e) + ")";
      return false;
    }
  }
  return true;
}

bool MaterialSet::compute_bsdf(uint32_t material, SurfaceInteraction* si, TransportMode mode,
                               bool allow_multiple_lobes, Bsdf* bsdf) const {
  const MaterialNode& m = nodes_[material];
  if (m.kind == MaterialKind::kNone) return false;
  if (m.kind == MaterialKind::kMix) {
    Rgb s1 = clamp(textures_->eval(m.amount, *si));
    Rgb s2 = clamp(Rgb(1) - s1);
    // The second material shades a copy: its bump map must not move the
    // frame the combined BSDF is expressed in (the first material's).
    SurfaceInteraction si2 = *si;
    compute_bsdf(m.mix[0], si, mode, allow_multiple_lobes, bsdf);
    Bsdf second;
    compute_bsdf(m.mix[1], &si2, mode, allow_multiple_lobes, &second);
    bsdf->scale_lobes(s1);
    second.scale_lobes(s2);
    for (int i = 0; i < second.num_lobes(); ++i) bsdf->add(second.lobe(i));
    return true;
  }
  if (m.has_bump) apply_bump(*textures_, m.bump, si);
  add_lobes(m, *si, mode, allow_multiple_lobes, bsdf);
  return true;
}

void MaterialSet::add_lobes(const MaterialNode& m, const SurfaceInteraction& si, TransportMode mode,
                            bool allow_multiple_lobes, Bsdf* bsdf) const {
  const TextureSet& tex = *textures_;
  switch (m.kind) {
    case MaterialKind::kMatte: {
      bsdf->init(si);
      Rgb r = clamp(tex.eval(m.kd, si));
      float sigma = clamp(tex.eval(m.sigma, si), 0.f, 90.f);
      if (r.is_black()) break;
      bsdf->add(sigma == 0 ? make_lambertian_reflection(r) : make_oren_nayar(r, sigma));
      break;
    }
    case MaterialKind::kPlastic: {
      bsdf->init(si);
      Rgb kd = clamp(tex.eval(m.kd, si));
      if (!kd.is_black()) bsdf->add(make_lambertian_reflection(kd));
      Rgb ks = clamp(tex.eval(m.ks, si));
      if (!ks.is_black()) {
        float rough = tex.eval(m.roughness, si);
        bsdf->add(make_microfacet_reflection(ks, trowbridge_reitz(rough, rough, m.remap_roughness),
                                             Fresnel::dielectric(1.5f, 1.f)));
      }
      break;
    }
    case MaterialKind::kMetal: {
      bsdf->init(si);
      float urough = tex.eval(m.uroughness, si), vrough = tex.eval(m.vroughness, si);
      Fresnel fr = Fresnel::conductor(Rgb(1), tex.eval(m.metal_eta, si), tex.eval(m.metal_k, si));
      bsdf->add(make_microfacet_reflection(
          Rgb(1), trowbridge_reitz(urough, vrough, m.remap_roughness), fr));
      break;
    }
    case MaterialKind::kHair: {
      const float eta = tex.eval(m.eta, si), beta_n = tex.eval(m.beta_n, si);
      bsdf->init(si, eta);
      Rgb sigma_a;
      switch (m.hair_absorption) {
        case HairAbsorption::kSigmaA:
          sigma_a = clamp(tex.eval(m.sigma_a, si));
          break;
        case HairAbsorption::kColor:
          sigma_a = hair_sigma_a_from_reflectance(clamp(tex.eval(m.hair_color, si)), beta_n);
          break;
        case HairAbsorption::kMelanin:
          sigma_a = hair_sigma_a_from_concentration(std::max(0.f, tex.eval(m.eumelanin, si)),
                                                    std::max(0.f, tex.eval(m.pheomelanin, si)));
          break;
      }
      // v runs across a curve's width: the offset h from the fiber's axis, -1 to 1.
      const float h = -1 + 2 * si.uv.y;
      bsdf->add(make_hair(
          make_hair_lobe(h, eta, sigma_a, tex.eval(m.beta_m, si), beta_n, tex.eval(m.alpha, si))));
      break;
    }
    case MaterialKind::kMirror: {
      bsdf->init(si);
      Rgb r = clamp(tex.eval(m.kr, si));
      if (!r.is_black()) bsdf->add(make_specular_reflection(r, Fresnel::no_op()));
      break;
    }
    case MaterialKind::kGlass:
    case MaterialKind::kSubsurface: {
      float eta = tex.eval(m.eta, si);
      float urough = tex.eval(m.uroughness, si), vrough = tex.eval(m.vroughness, si);
      Rgb r = clamp(tex.eval(m.kr, si)), t = clamp(tex.eval(m.kt, si));
      bsdf->init(si, eta);
      if (r.is_black() && t.is_black()) break;
      bool specular = urough == 0 && vrough == 0;
      if (specular && allow_multiple_lobes) {
        // One lobe choosing reflection or refraction by Fresnel: better
        // sampling than two delta lobes picked uniformly.
        bsdf->add(make_fresnel_specular(r, t, 1.f, eta, mode));
        break;
      }
      MicrofacetDistribution d = trowbridge_reitz(urough, vrough, m.remap_roughness);
      if (!r.is_black()) {
        Fresnel fr = Fresnel::dielectric(1.f, eta);
        bsdf->add(specular ? make_specular_reflection(r, fr)
                           : make_microfacet_reflection(r, d, fr));
      }
      if (!t.is_black())
        bsdf->add(specular ? make_specular_transmission(t, 1.f, eta, mode)
                           : make_microfacet_transmission(t, d, 1.f, eta, mode));
      break;
    }
    case MaterialKind::kUber: {
      Rgb op = clamp(tex.eval(m.opacity, si));
      Rgb t = clamp(Rgb(1) - op);
      float e = tex.eval(m.eta, si);
      if (!t.is_black()) {
        // Partial opacity: light passes straight through, undeviated.
        bsdf->init(si, 1.f);
        bsdf->add(make_specular_transmission(t, 1.f, 1.f, mode));
      } else {
        bsdf->init(si, e);
      }
      Rgb kd = op * clamp(tex.eval(m.kd, si));
      if (!kd.is_black()) bsdf->add(make_lambertian_reflection(kd));
      Rgb ks = op * clamp(tex.eval(m.ks, si));
      if (!ks.is_black()) {
        float urough = tex.eval(m.uroughness, si), vrough = tex.eval(m.vroughness, si);
        bsdf->add(make_microfacet_reflection(
            ks, trowbridge_reitz(urough, vrough, m.remap_roughness), Fresnel::dielectric(1.f, e)));
      }
      Rgb kr = op * clamp(tex.eval(m.kr, si));
      if (!kr.is_black()) bsdf->add(make_specular_reflection(kr, Fresnel::dielectric(1.f, e)));
      Rgb kt = op * clamp(tex.eval(m.kt, si));
      if (!kt.is_black()) bsdf->add(make_specular_transmission(kt, 1.f, e, mode));
      break;
    }
    case MaterialKind::kSubstrate: {
      bsdf->init(si);
      Rgb d = clamp(tex.eval(m.kd, si)), s = clamp(tex.eval(m.ks, si));
      float urough = tex.eval(m.uroughness, si), vrough = tex.eval(m.vroughness, si);
      if (!d.is_black() || !s.is_black())
        bsdf->add(make_fresnel_blend(d, s, trowbridge_reitz(urough, vrough, m.remap_roughness)));
      break;
    }
    case MaterialKind::kTranslucent: {
      const float eta = 1.5f;  // pbrt-v3's TranslucentMaterial fixes it
      bsdf->init(si, eta);
      Rgb r = clamp(tex.eval(m.reflect, si)), t = clamp(tex.eval(m.transmit, si));
      if (r.is_black() && t.is_black()) break;
      Rgb kd = clamp(tex.eval(m.kd, si));
      if (!kd.is_black()) {
        if (!r.is_black()) bsdf->add(make_lambertian_reflection(r * kd));
        if (!t.is_black()) bsdf->add(make_lambertian_transmission(t * kd));
      }
      Rgb ks = clamp(tex.eval(m.ks, si));
      if (!ks.is_black() && (!r.is_black() || !t.is_black())) {
        float rough = tex.eval(m.roughness, si);
        MicrofacetDistribution d = trowbridge_reitz(rough, rough, m.remap_roughness);
        if (!r.is_black())
          bsdf->add(make_microfacet_reflection(r * ks, d, Fresnel::dielectric(1.f, eta)));
        if (!t.is_black()) bsdf->add(make_microfacet_transmission(t * ks, d, 1.f, eta, mode));
      }
      break;
    }
    case MaterialKind::kDisney: {
      DisneyParams p = evaluate_disney(m.disney, tex, si);
      bsdf->init(si);  // pbrt-v3's DisneyMaterial leaves the BSDF's eta at 1
      DisneyLobe lobes[kMaxDisneyLobes];
      bool subsurface = false;
      int n = make_disney_lobes(p, mode, lobes, &subsurface);
      // Light enters the BSSRDF (compute_bssrdf) by refraction without loss.
      if (subsurface) bsdf->add(make_specular_transmission(Rgb(1), 1.f, p.eta, mode));
      for (int i = 0; i < n; ++i) bsdf->add(make_disney(lobes[i]));
      break;
    }
    case MaterialKind::kFourier:
      bsdf->init(si);  // pbrt-v3's FourierMaterial leaves the BSDF's eta at 1
      bsdf->add(make_fourier(m.fourier, mode));
      break;
    case MaterialKind::kNone:
    case MaterialKind::kMix:
      break;
  }
}

bool MaterialSet::compute_bssrdf(uint32_t material, const SurfaceInteraction& si,
                                 Bssrdf* out) const {
  const MaterialNode& m = nodes_[material];
  const TextureSet& tex = *textures_;
  if (m.kind == MaterialKind::kDisney) {
    if (m.disney.thin) return false;
    DisneyParams p = evaluate_disney(m.disney, tex, si);
    float diffuse_weight = (1 - p.metallic) * (1 - p.spec_trans);
    if (p.scatter_distance.is_black() || !(diffuse_weight > 0)) return false;
    // The profile's d is a fifth of the scatter distance, as in pbrt-v3 (which credits Burley
    // and Chiang for the factor).
    out->init_disney(clamp(p.color) * diffuse_weight, p.scatter_distance * 0.2f, p.eta, si.p,
                     si.shading.n, si.shading.dpdu, material);
    return true;
  }
  if (!m.bssrdf) return false;
  Rgb sigma_a, sigma_s;
  if (m.from_diffuse) {
    Rgb mfp = clamp(tex.eval(m.mfp, si)) * m.ss_scale;
    subsurface_from_diffuse(*m.bssrdf, clamp(tex.eval(m.kd, si)), mfp, &sigma_a, &sigma_s);
  } else {
    sigma_a = clamp(tex.eval(m.sigma_a, si)) * m.ss_scale;
    sigma_s = clamp(tex.eval(m.sigma_s, si)) * m.ss_scale;
  }
  out->init(m.bssrdf, sigma_a, sigma_s, tex.eval(m.eta, si), si.p, si.shading.n, si.shading.dpdu,
            material);
  return true;
}

}  // namespace rt
