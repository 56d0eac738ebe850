// format/schema_tables.cpp — the parameter tables of every pbrt-v3 entity type.
//
// The facts here (type names, parameter names, kinds, defaults, aliases) were taken from pbrt-v3's
// documentation and source (mmp/pbrt-v3, RGB build: each type's Create*() function and
// core/api.cpp) as data, not code: nothing of pbrt-v3 is compiled or copied, only what it reads.
//
// Conventions, so that a reader can trust a row without reopening pbrt-v3:
// - Order inside a type follows the order pbrt-v3 reads the parameters, except that every 2D
//   texture starts with the same seven mapping parameters, so they sit at the same indices.
//   Types follow the order of pbrt-v3's Make*() dispatch. Appending is a minor format change,
//   reordering a major one (see schema.h).
// - kParamRequired marks a parameter without which pbrt-v3 reports an error (and usually creates
//   nothing). A parameter that is merely unused when absent is optional.
// - kParamComputedDefault marks a default that pbrt-v3 derives from other parameters, from the
//   scene, or from a precedence rule ("uroughness" falls back to "roughness"); the note says how.
//   Optional textures with no default at all ("bumpmap") are plain optional rows: an absent one
//   simply does nothing.
// - Spectra are kRgb (or kSpectrumTex where pbrt-v3 reads a texture); pbrt-v3's constant spectra
//   are grey, so a default of 0.5 is {0.5, 0.5, 0.5}.
// - Bulk vertex/index arrays have arity 0 and kParamBulk: the compiler moves them to the geometry
//   sections.

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <limits>
#include <string_view>

#include "format/schema.h"

namespace pbrta {
namespace {

// ---------------------------------------------------------------------------------------------
// Row builders. They exist so that each table row reads like pbrt-v3's own FindOne*() call
// (name, default) instead of a seven-field aggregate, and so that every field is always given
// (-Wextra warns about partially initialised aggregates).

constexpr DefaultValue values(float a = 0, float b = 0, float c = 0, float d = 0) {
  return DefaultValue{{a, b, c, d}, nullptr};
}

constexpr DefaultValue text(const char* s) {
  return DefaultValue{{0, 0, 0, 0}, s};
}

constexpr ParamSpec row(std::string_view name, Kind kind, uint8_t arity, DefaultValue def) {
  return ParamSpec{name, kind, arity, kParamNone, def, {}, {}};
}

constexpr ParamSpec p_int(std::string_view name, float v) {
  return row(name, Kind::kInt, 1, values(v));
}
constexpr ParamSpec p_float(std::string_view name, float v) {
  return row(name, Kind::kFloat, 1, values(v));
}
constexpr ParamSpec p_bool(std::string_view name, bool v) {
  return row(name, Kind::kBool, 1, values(v ? 1.f : 0.f));
}
constexpr ParamSpec p_string(std::string_view name, const char* v) {
  return row(name, Kind::kString, 1, text(v));
}
// A file name with "" as its default (pbrt-v3's FindOneFilename(name, "")): optional unless
// marked required.
constexpr ParamSpec p_file(std::string_view name) {
  ParamSpec p = row(name, Kind::kString, 1, text(""));
  p.flags |= kParamFilename;
  return p;
}
constexpr ParamSpec p_point3(std::string_view name, float x, float y, float z) {
  return row(name, Kind::kPoint3, 1, values(x, y, z));
}
constexpr ParamSpec p_vector3(std::string_view name, float x, float y, float z) {
  return row(name, Kind::kVector3, 1, values(x, y, z));
}
constexpr ParamSpec p_rgb(std::string_view name, float r, float g, float b) {
  return row(name, Kind::kRgb, 1, values(r, g, b));
}
constexpr ParamSpec p_grey(std::string_view name, float v) {
  return p_rgb(name, v, v, v);
}
constexpr ParamSpec p_ftex(std::string_view name, float v) {
  return row(name, Kind::kFloatTex, 1, values(v));
}
// An optional float texture that pbrt-v3 reads with GetFloatTextureOrNull and no fallback.
constexpr ParamSpec p_ftex_optional(std::string_view name) {
  return row(name, Kind::kFloatTex, 1, values());
}
constexpr ParamSpec p_stex(std::string_view name, float grey) {
  return row(name, Kind::kSpectrumTex, 1, values(grey, grey, grey));
}
constexpr ParamSpec p_stex_rgb(std::string_view name, float r, float g, float b) {
  return row(name, Kind::kSpectrumTex, 1, values(r, g, b));
}
// A fixed-size array of floats ("cropwindow", "screenwindow").
constexpr ParamSpec p_floats4(std::string_view name, float a, float b, float c, float d) {
  return row(name, Kind::kFloat, 4, values(a, b, c, d));
}
// Bulk array data of any length.
constexpr ParamSpec p_bulk(std::string_view name, Kind kind) {
  ParamSpec p = row(name, kind, 0, values());
  p.flags |= kParamBulk;
  return p;
}

constexpr ParamSpec required(ParamSpec p) {
  p.flags |= kParamRequired;
  return p;
}
constexpr ParamSpec derived(ParamSpec p) {
  p.flags |= kParamDerived;
  return p;
}
constexpr ParamSpec computed(ParamSpec p, std::string_view note) {
  p.flags |= kParamComputedDefault;
  p.note = note;
  return p;
}
// A note on a parameter whose default is not computed but whose meaning needs one.
constexpr ParamSpec noted(ParamSpec p, std::string_view note) {
  p.note = note;
  return p;
}
constexpr ParamSpec alias(ParamSpec p, std::string_view other_spelling) {
  p.alias = other_spelling;
  return p;
}

template <std::size_t N>
constexpr TypeSpec make_type(std::string_view name, const ParamSpec (&params)[N],
                             std::string_view other_spelling = {}) {
  static_assert(N <= UINT16_MAX, "too many parameters for TypeSpec::num_params");
  return TypeSpec{name, params, static_cast<uint16_t>(N), other_spelling};
}
constexpr TypeSpec make_type_without_params(std::string_view name) {
  return TypeSpec{name, nullptr, 0, {}};
}

template <std::size_t N>
constexpr CategorySpec make_category(std::string_view name, const TypeSpec (&types)[N]) {
  static_assert(N <= UINT16_MAX, "too many types for CategorySpec::num_types");
  return CategorySpec{name, types, static_cast<uint16_t>(N)};
}

constexpr float kInfinity = std::numeric_limits<float>::infinity();

// The parameters every 2D texture reads for its TextureMapping2D. pbrt-v3 repeats this block in
// each 2D texture's Create function; "uscale"... apply to mapping "uv", "v1"/"v2" (and the deltas)
// to "planar", and "spherical"/"cylindrical" use only the texture's transform. A macro because
// constexpr arrays cannot be spliced together.
#define PBRTA_MAPPING_2D_PARAMS                                                                \
  p_string("mapping", "uv"), p_float("uscale", 1), p_float("vscale", 1), p_float("udelta", 0), \
      p_float("vdelta", 0), p_vector3("v1", 1, 0, 0), p_vector3("v2", 0, 1, 0)

// The tables keep one parameter per line, whatever clang-format would pack, so that a diff of
// the schema shows one parameter per changed line.
// clang-format off

// ---------------------------------------------------------------------------------------------
// Shapes (shapes/*.cpp).

constexpr ParamSpec kSphere[] = {
    p_float("radius", 1),
    computed(p_float("zmin", -1), "-radius"),
    computed(p_float("zmax", 1), "radius"),
    p_float("phimax", 360),
};
constexpr ParamSpec kCylinder[] = {
    p_float("radius", 1),
    p_float("zmin", -1),
    p_float("zmax", 1),
    p_float("phimax", 360),
};
constexpr ParamSpec kDisk[] = {
    p_float("height", 0),
    p_float("radius", 1),
    p_float("innerradius", 0),
    p_float("phimax", 360),
};
constexpr ParamSpec kCone[] = {
    p_float("radius", 1),
    p_float("height", 1),
    p_float("phimax", 360),
};
constexpr ParamSpec kParaboloid[] = {
    p_float("radius", 1),
    p_float("zmin", 0),
    p_float("zmax", 1),
    p_float("phimax", 360),
};
constexpr ParamSpec kHyperboloid[] = {
    p_point3("p1", 0, 0, 0),
    p_point3("p2", 1, 1, 1),
    p_float("phimax", 360),
};
constexpr ParamSpec kCurve[] = {
    p_float("width", 1),
    computed(p_float("width0", 1), "width"),
    computed(p_float("width1", 1), "width"),
    p_int("degree", 3),           // 2 or 3
    p_string("basis", "bezier"),  // "bezier" or "bspline"
    required(p_bulk("P", Kind::kPoint3)),
    p_string("type", "flat"),     // "flat", "ribbon" or "cylinder"
    p_bulk("N", Kind::kNormal3),  // ribbon curves only, one per segment end
    // pbrt-v3 also accepts "float splitdepth" (it reads the int, falling back to the float).
    p_int("splitdepth", 3),
};
constexpr ParamSpec kTriangleMesh[] = {
    required(p_bulk("indices", Kind::kInt)),
    required(p_bulk("P", Kind::kPoint3)),
    // pbrt-v3 also accepts "uv"/"st" given as a flat float array (two floats per vertex).
    alias(p_bulk("uv", Kind::kPoint2), "st"),
    p_bulk("S", Kind::kVector3),
    p_bulk("N", Kind::kNormal3),
    p_bulk("faceIndices", Kind::kInt),  // per-face ids for ptex
    p_ftex("alpha", 1),                 // a constant other than 0 means no alpha test
    p_ftex("shadowalpha", 1),
};
constexpr ParamSpec kPlyMesh[] = {
    required(p_file("filename")),
    p_ftex("alpha", 1),
    p_ftex("shadowalpha", 1),
};
constexpr ParamSpec kHeightfield[] = {
    required(p_int("nu", -1)),
    required(p_int("nv", -1)),
    required(p_bulk("Pz", Kind::kFloat)),  // nu * nv heights
};
constexpr ParamSpec kLoopSubdiv[] = {
    alias(p_int("levels", 3), "nlevels"),  // "levels" wins when both are given
    required(p_bulk("indices", Kind::kInt)),
    required(p_bulk("P", Kind::kPoint3)),
    p_string("scheme", "loop"),  // read but unused by pbrt-v3
};
constexpr ParamSpec kNurbs[] = {
    required(p_int("nu", -1)),
    required(p_int("uorder", -1)),
    required(p_bulk("uknots", Kind::kFloat)),
    computed(p_float("u0", 0), "uknots[uorder - 1]"),
    computed(p_float("u1", 0), "uknots[nu]"),
    required(p_int("nv", -1)),
    required(p_int("vorder", -1)),
    required(p_bulk("vknots", Kind::kFloat)),
    computed(p_float("v0", 0), "vknots[vorder - 1]"),
    computed(p_float("v1", 0), "vknots[nv]"),
    // One of "P" or "Pw" is required; the schema cannot say "one of", so neither is flagged.
    p_bulk("P", Kind::kPoint3),
    p_bulk("Pw", Kind::kFloat),  // homogeneous control points, four floats each
};

constexpr TypeSpec kShapes[] = {
    make_type("sphere", kSphere),
    make_type("cylinder", kCylinder),
    make_type("disk", kDisk),
    make_type("cone", kCone),
    make_type("paraboloid", kParaboloid),
    make_type("hyperboloid", kHyperboloid),
    make_type("curve", kCurve),
    make_type("trianglemesh", kTriangleMesh),
    make_type("plymesh", kPlyMesh),
    make_type("heightfield", kHeightfield),
    make_type("loopsubdiv", kLoopSubdiv),
    make_type("nurbs", kNurbs),
};

// ---------------------------------------------------------------------------------------------
// Materials (materials/*.cpp). "" is not a type: the compiler treats "" like "none".

constexpr ParamSpec kMatte[] = {
    p_stex("Kd", 0.5f),
    p_ftex("sigma", 0),  // Oren-Nayar sigma in degrees; 0 is Lambertian
    p_ftex_optional("bumpmap"),
};
constexpr ParamSpec kPlastic[] = {
    p_stex("Kd", 0.25f),
    p_stex("Ks", 0.25f),
    p_ftex("roughness", 0.1f),
    p_ftex_optional("bumpmap"),
    p_bool("remaproughness", true),
};
constexpr ParamSpec kTranslucent[] = {
    p_stex("Kd", 0.25f),
    p_stex("Ks", 0.25f),
    p_stex("reflect", 0.5f),
    p_stex("transmit", 0.5f),
    p_ftex("roughness", 0.1f),
    p_ftex_optional("bumpmap"),
    p_bool("remaproughness", true),
};
constexpr ParamSpec kGlass[] = {
    p_stex("Kr", 1),
    p_stex("Kt", 1),
    alias(p_ftex("eta", 1.5f), "index"),  // "eta" wins when both are given
    p_ftex("uroughness", 0),
    p_ftex("vroughness", 0),
    p_ftex_optional("bumpmap"),
    p_bool("remaproughness", true),
};
constexpr ParamSpec kMirror[] = {
    p_stex("Kr", 0.9f),
    p_ftex_optional("bumpmap"),
};
// Hair reads no "bumpmap" in pbrt-v3. The absorption comes from exactly one of sigma_a, color or
// eumelanin/pheomelanin, in that order of precedence, so all four keep a "given" bit.
constexpr ParamSpec kHair[] = {
    computed(p_stex("sigma_a", 0),
             "when none of sigma_a, color, eumelanin, pheomelanin is given: the absorption of "
             "eumelanin concentration 1.3 (brown hair)"),
    computed(p_stex("color", 0), "optional; used only when sigma_a is absent"),
    computed(
        p_ftex("eumelanin", 0),
        "optional; used (with pheomelanin, absent = 0) only when sigma_a and color are absent"),
    computed(p_ftex("pheomelanin", 0),
             "optional; used (with eumelanin, absent = 0) only when sigma_a and color are absent"),
    p_ftex("eta", 1.55f),
    p_ftex("beta_m", 0.3f),
    p_ftex("beta_n", 0.3f),
    p_ftex("alpha", 2),  // scale tilt in degrees
};
// Mix reads no "bumpmap". pbrt-v3 reports an error (and substitutes matte) for a missing or
// undefined named material.
constexpr ParamSpec kMix[] = {
    p_stex("amount", 0.5f),
    required(p_string("namedmaterial1", "")),
    required(p_string("namedmaterial2", "")),
};
constexpr ParamSpec kMetal[] = {
    computed(p_stex("eta", 0), "measured copper spectrum"),
    computed(p_stex("k", 0), "measured copper spectrum"),
    p_ftex("roughness", 0.01f),
    computed(p_ftex("uroughness", 0.01f), "roughness"),
    computed(p_ftex("vroughness", 0.01f), "roughness"),
    p_ftex_optional("bumpmap"),
    p_bool("remaproughness", true),
};
constexpr ParamSpec kSubstrate[] = {
    p_stex("Kd", 0.5f),
    p_stex("Ks", 0.5f),
    p_ftex("uroughness", 0.1f),
    p_ftex("vroughness", 0.1f),
    p_ftex_optional("bumpmap"),
    p_bool("remaproughness", true),
};
constexpr ParamSpec kUber[] = {
    p_stex("Kd", 0.25f),
    p_stex("Ks", 0.25f),
    p_stex("Kr", 0),
    p_stex("Kt", 0),
    p_ftex("roughness", 0.1f),
    computed(p_ftex("uroughness", 0.1f), "roughness"),
    computed(p_ftex("vroughness", 0.1f), "roughness"),
    alias(p_ftex("eta", 1.5f), "index"),  // "eta" wins when both are given
    p_stex("opacity", 1),
    p_ftex_optional("bumpmap"),
    p_bool("remaproughness", true),
};
// The photon-beam-diffusion profile of both subsurface materials, computed by pbrtc for the
// material's g and eta (format/bssrdf_table.h); archive version 2.1 added them.
constexpr ParamSpec kBssrdfRho = noted(derived(p_bulk("bssrdfrho", Kind::kFloat)),
                                       "the albedo samples, increasing in [0, 1]");
constexpr ParamSpec kBssrdfRadius = noted(derived(p_bulk("bssrdfradius", Kind::kFloat)),
                                          "the optical radius samples, increasing from 0");
constexpr ParamSpec kBssrdfProfile =
    noted(derived(p_bulk("bssrdfprofile", Kind::kFloat)),
          "albedos x radii, row-major: 2 pi r Sr(r) for unit extinction");
constexpr ParamSpec kBssrdfRhoEff = noted(derived(p_bulk("bssrdfrhoeff", Kind::kFloat)),
                                          "per albedo: the profile's integral over the radius");
constexpr ParamSpec kBssrdfCdf =
    noted(derived(p_bulk("bssrdfcdf", Kind::kFloat)),
          "albedos x radii: the profile's running integral over the radius (Catmull-Rom)");
constexpr ParamSpec kSubsurface[] = {
    // A measured-medium preset: pbrtc writes its sigma_a/sigma_s (unless given) and g = 0.
    p_string("name", ""),
    p_float("g", 0),
    p_float("scale", 1),
    p_float("eta", 1.33f),  // a plain float here, not a texture
    computed(p_stex_rgb("sigma_a", .0011f, .0024f, .014f),
             "the preset's sigma_a when \"name\" is a known preset, else this RGB"),
    computed(p_stex_rgb("sigma_s", 2.55f, 3.21f, 3.77f),
             "the preset's sigma_s when \"name\" is a known preset, else this RGB"),
    p_stex("Kr", 1),
    p_stex("Kt", 1),
    p_ftex("uroughness", 0),
    p_ftex("vroughness", 0),
    p_ftex_optional("bumpmap"),
    p_bool("remaproughness", true),
    kBssrdfRho,
    kBssrdfRadius,
    kBssrdfProfile,
    kBssrdfRhoEff,
    kBssrdfCdf,
};
constexpr ParamSpec kKdSubsurface[] = {
    p_stex("Kd", 0.5f),
    p_stex("mfp", 1),
    p_stex("Kr", 1),
    p_stex("Kt", 1),
    p_ftex("uroughness", 0),
    p_ftex("vroughness", 0),
    p_ftex_optional("bumpmap"),
    p_float("eta", 1.33f),
    p_float("scale", 1),
    p_float("g", 0),
    p_bool("remaproughness", true),
    kBssrdfRho,
    kBssrdfRadius,
    kBssrdfProfile,
    kBssrdfRhoEff,
    kBssrdfCdf,
};
constexpr ParamSpec kFourier[] = {
    p_ftex_optional("bumpmap"),
    required(p_file("bsdffile")),
    // Read from "bsdffile" at compile time, so the runtime opens no file (format/fourier_table.h).
    noted(derived(p_float("bsdfeta", 1)),
          "the table's relative index of refraction (1: reflection only)"),
    noted(derived(p_int("bsdfmmax", 0)),
          "the file's maximum Fourier series length: no node pair's series is longer"),
    noted(derived(p_int("bsdfchannels", 0)), "1 (luminance) or 3 (luminance, red, blue)"),
    noted(derived(p_bulk("bsdfmu", Kind::kFloat)),
          "the n zenith cosine nodes, non-decreasing in [-1, 1]"),
    noted(derived(p_bulk("bsdfcdf", Kind::kFloat)),
          "n*n: row o (outgoing node), column i: the running integral over incoming cosines of "
          "the series' constant term"),
    noted(derived(p_bulk("bsdfoffsets", Kind::kInt)),
          "2*n*n: per (o, i), the first coefficient and the series length m"),
    noted(derived(p_bulk("bsdfcoeffs", Kind::kFloat)),
          "all series coefficients; pair (o, i) channel c term k is at offset + c*m + k"),
};
constexpr ParamSpec kDisney[] = {
    p_stex("color", 0.5f),
    p_ftex("metallic", 0),
    p_ftex("eta", 1.5f),
    p_ftex("roughness", 0.5f),
    p_ftex("speculartint", 0),
    p_ftex("anisotropic", 0),
    p_ftex("sheen", 0),
    p_ftex("sheentint", 0.5f),
    p_ftex("clearcoat", 0),
    p_ftex("clearcoatgloss", 1),
    p_ftex("spectrans", 0),
    p_stex("scatterdistance", 0),
    p_bool("thin", false),
    p_ftex("flatness", 0),
    p_ftex("difftrans", 1),
    p_ftex_optional("bumpmap"),
};

constexpr TypeSpec kMaterials[] = {
    make_type_without_params("none"),
    make_type("matte", kMatte),
    make_type("plastic", kPlastic),
    make_type("translucent", kTranslucent),
    make_type("glass", kGlass),
    make_type("hair", kHair),
    make_type("mirror", kMirror),
    make_type("mix", kMix),
    make_type("metal", kMetal),
    make_type("substrate", kSubstrate),
    make_type("uber", kUber),
    make_type("subsurface", kSubsurface),
    make_type("kdsubsurface", kKdSubsurface),
    make_type("fourier", kFourier),
    make_type("disney", kDisney),
};

// ---------------------------------------------------------------------------------------------
// Textures (textures/*.cpp). pbrt-v3's MakeFloatTexture accepts the names "uv" and "marble", but
// their float Create functions return nothing (the texture is silently not defined), so they are
// spectrum-only here.

constexpr ParamSpec kFloatConstant[] = {
    p_float("value", 1),
};
constexpr ParamSpec kFloatScale[] = {
    p_ftex("tex1", 1),
    p_ftex("tex2", 1),
};
constexpr ParamSpec kFloatMix[] = {
    p_ftex("tex1", 0),
    p_ftex("tex2", 1),
    p_ftex("amount", 0.5f),
};
constexpr ParamSpec kFloatBilerp[] = {
    PBRTA_MAPPING_2D_PARAMS,
    p_float("v00", 0),
    p_float("v01", 1),
    p_float("v10", 0),
    p_float("v11", 1),
};
// imagemap is identical in both namespaces.
constexpr ParamSpec kImagemap[] = {
    PBRTA_MAPPING_2D_PARAMS,
    p_float("maxanisotropy", 8),
    p_bool("trilinear", false),
    p_string("wrap", "repeat"),  // "repeat", "black" or "clamp"
    p_float("scale", 1),
    required(p_file("filename")),
    computed(p_bool("gamma", false), "true when the file name ends in .tga or .png"),
};
constexpr ParamSpec kFloatCheckerboard[] = {
    PBRTA_MAPPING_2D_PARAMS,  // used only when dimension is 2
    p_int("dimension", 2),    // 2 or 3
    p_ftex("tex1", 1),
    p_ftex("tex2", 0),
    p_string("aamode", "closedform"),  // "closedform" or "none"; 2D only
};
constexpr ParamSpec kFloatDots[] = {
    PBRTA_MAPPING_2D_PARAMS,
    p_ftex("inside", 1),
    p_ftex("outside", 0),
};
// fbm and wrinkled read the same two parameters in both namespaces.
constexpr ParamSpec kNoise[] = {
    p_int("octaves", 8),
    p_float("roughness", 0.5f),
};
// ptex is identical in both namespaces.
constexpr ParamSpec kPtex[] = {
    required(p_file("filename")),
    p_float("gamma", 2.2f),
};

constexpr TypeSpec kFloatTextures[] = {
    make_type("constant", kFloatConstant),
    make_type("scale", kFloatScale),
    make_type("mix", kFloatMix),
    make_type("bilerp", kFloatBilerp),
    make_type("imagemap", kImagemap),
    make_type("checkerboard", kFloatCheckerboard),
    make_type("dots", kFloatDots),
    make_type("fbm", kNoise),
    make_type("wrinkled", kNoise),
    make_type_without_params("windy"),
    make_type("ptex", kPtex),
};

constexpr ParamSpec kSpectrumConstant[] = {
    p_grey("value", 1),
};
constexpr ParamSpec kSpectrumScale[] = {
    p_stex("tex1", 1),
    p_stex("tex2", 1),
};
constexpr ParamSpec kSpectrumMix[] = {
    p_stex("tex1", 0),
    p_stex("tex2", 1),
    p_ftex("amount", 0.5f),  // a float texture even when mixing spectra
};
constexpr ParamSpec kSpectrumBilerp[] = {
    PBRTA_MAPPING_2D_PARAMS,
    p_grey("v00", 0),
    p_grey("v01", 1),
    p_grey("v10", 0),
    p_grey("v11", 1),
};
constexpr ParamSpec kSpectrumUv[] = {
    PBRTA_MAPPING_2D_PARAMS,
};
constexpr ParamSpec kSpectrumCheckerboard[] = {
    PBRTA_MAPPING_2D_PARAMS,  // used only when dimension is 2
    p_int("dimension", 2),
    p_stex("tex1", 1),
    p_stex("tex2", 0),
    p_string("aamode", "closedform"),
};
constexpr ParamSpec kSpectrumDots[] = {
    PBRTA_MAPPING_2D_PARAMS,
    p_stex("inside", 1),
    p_stex("outside", 0),
};
constexpr ParamSpec kMarble[] = {
    p_int("octaves", 8),
    p_float("roughness", 0.5f),
    p_float("scale", 1),
    p_float("variation", 0.2f),
};

constexpr TypeSpec kSpectrumTextures[] = {
    make_type("constant", kSpectrumConstant),
    make_type("scale", kSpectrumScale),
    make_type("mix", kSpectrumMix),
    make_type("bilerp", kSpectrumBilerp),
    make_type("imagemap", kImagemap),
    make_type("uv", kSpectrumUv),
    make_type("checkerboard", kSpectrumCheckerboard),
    make_type("dots", kSpectrumDots),
    make_type("fbm", kNoise),
    make_type("wrinkled", kNoise),
    make_type("marble", kMarble),
    make_type_without_params("windy"),
    make_type("ptex", kPtex),
};

#undef PBRTA_MAPPING_2D_PARAMS

// ---------------------------------------------------------------------------------------------
// Lights (lights/*.cpp). pbrt-v3 reads "scale" as a spectrum (FindOneSpectrum), so it is kRgb.

constexpr ParamSpec kPointLight[] = {
    p_grey("I", 1),
    p_grey("scale", 1),
    p_point3("from", 0, 0, 0),
};
constexpr ParamSpec kSpotLight[] = {
    p_grey("I", 1),
    p_grey("scale", 1),
    p_float("coneangle", 30),
    p_float("conedeltaangle", 5),
    p_point3("from", 0, 0, 0),
    p_point3("to", 0, 0, 1),
};
constexpr ParamSpec kGoniometricLight[] = {
    p_grey("I", 1),
    p_grey("scale", 1),
    p_file("mapname"),
};
constexpr ParamSpec kProjectionLight[] = {
    p_grey("I", 1),
    p_grey("scale", 1),
    p_float("fov", 45),
    p_file("mapname"),
};
constexpr ParamSpec kDistantLight[] = {
    p_grey("L", 1),
    p_grey("scale", 1),
    p_point3("from", 0, 0, 0),
    p_point3("to", 0, 0, 1),
};
constexpr ParamSpec kInfiniteLight[] = {
    p_grey("L", 1),
    p_grey("scale", 1),
    p_file("mapname"),
    alias(p_int("nsamples", 1), "samples"),  // "samples" wins when both are given
};

constexpr TypeSpec kLights[] = {
    make_type("point", kPointLight),
    make_type("spot", kSpotLight),
    make_type("goniometric", kGoniometricLight),
    make_type("projection", kProjectionLight),
    make_type("distant", kDistantLight),
    make_type("infinite", kInfiniteLight, "exinfinite"),
};

constexpr ParamSpec kDiffuseAreaLight[] = {
    p_grey("L", 1),
    p_grey("scale", 1),
    alias(p_int("nsamples", 1), "samples"),  // "samples" wins when both are given
    p_bool("twosided", false),
};

constexpr TypeSpec kAreaLights[] = {
    make_type("diffuse", kDiffuseAreaLight, "area"),
};

// ---------------------------------------------------------------------------------------------
// Cameras (cameras/*.cpp). Each camera reads only what is listed for it: realistic reads none of
// the screen-window parameters, environment reads them but ignores them.

constexpr const char* kFrameNote = "film xresolution / yresolution";
constexpr const char* kScreenNote =
    "frameaspectratio f > 1: [-f, f, -1, 1]; otherwise [-1, 1, -1/f, 1/f]";

constexpr ParamSpec kPerspective[] = {
    p_float("shutteropen", 0),
    p_float("shutterclose", 1),
    p_float("lensradius", 0),
    p_float("focaldistance", 1e30f),
    computed(p_float("frameaspectratio", 0), kFrameNote),
    computed(p_floats4("screenwindow", 0, 0, 0, 0), kScreenNote),
    p_float("fov", 90),
    // pbrt-v3's default is -1: values <= 0 are ignored, a positive one replaces fov.
    noted(p_float("halffov", -1), "pbrt-v2 spelling: fov = 2 * halffov"),
};
constexpr ParamSpec kOrthographic[] = {
    p_float("shutteropen", 0),
    p_float("shutterclose", 1),
    p_float("lensradius", 0),
    p_float("focaldistance", 1e30f),
    computed(p_float("frameaspectratio", 0), kFrameNote),
    computed(p_floats4("screenwindow", 0, 0, 0, 0), kScreenNote),
};
constexpr ParamSpec kRealistic[] = {
    p_float("shutteropen", 0),
    p_float("shutterclose", 1),
    required(p_file("lensfile")),
    p_float("aperturediameter", 1),
    p_float("focusdistance", 10),
    p_bool("simpleweighting", true),
    // Read from "lensfile" at compile time, so the runtime opens no file.
    noted(derived(p_bulk("lensdata", Kind::kFloat)),
          "the lens file's elements, 4 floats each: curvature radius, thickness, index of "
          "refraction, aperture diameter (mm), front to back"),
};
constexpr ParamSpec kEnvironment[] = {
    p_float("shutteropen", 0),
    p_float("shutterclose", 1),
    p_float("lensradius", 0),
    p_float("focaldistance", 1e30f),
    computed(p_float("frameaspectratio", 0), kFrameNote),
    computed(p_floats4("screenwindow", 0, 0, 0, 0), kScreenNote),
};

constexpr TypeSpec kCameras[] = {
    make_type("perspective", kPerspective),
    make_type("orthographic", kOrthographic),
    make_type("realistic", kRealistic),
    make_type("environment", kEnvironment),
};

// ---------------------------------------------------------------------------------------------
// Samplers (samplers/*.cpp).

constexpr ParamSpec kZeroTwoSequence[] = {
    p_int("pixelsamples", 16),
    p_int("dimensions", 4),
};
constexpr ParamSpec kMaxMinDist[] = {
    p_int("pixelsamples", 16),
    p_int("dimensions", 4),
};
constexpr ParamSpec kHalton[] = {
    p_int("pixelsamples", 16),
    p_bool("samplepixelcenter", false),
};
constexpr ParamSpec kSobol[] = {
    p_int("pixelsamples", 16),
};
constexpr ParamSpec kRandom[] = {
    p_int("pixelsamples", 4),
};
constexpr ParamSpec kStratified[] = {
    p_bool("jitter", true),
    p_int("xsamples", 4),
    p_int("ysamples", 4),
    p_int("dimensions", 4),
};

constexpr TypeSpec kSamplers[] = {
    make_type("02sequence", kZeroTwoSequence, "lowdiscrepancy"),
    make_type("maxmindist", kMaxMinDist),
    make_type("halton", kHalton),
    make_type("sobol", kSobol),
    make_type("random", kRandom),
    make_type("stratified", kStratified),
};

// ---------------------------------------------------------------------------------------------
// Film (core/film.cpp). pbrt-v3's film reads no "pixelbounds" (integrators do).

constexpr ParamSpec kImageFilm[] = {
    // Read with FindOneString, not FindOneFilename: the image lands in the working directory,
    // not beside the scene, so it is deliberately not flagged kParamFilename.
    computed(p_string("filename", "pbrt.exr"), "pbrt.exr, unless the command line names one"),
    p_int("xresolution", 1280),
    p_int("yresolution", 720),
    p_floats4("cropwindow", 0, 1, 0, 1),  // x0 x1 y0 y1, clamped to [0, 1]
    p_float("scale", 1),
    p_float("diagonal", 35),  // millimetres
    computed(p_float("maxsampleluminance", kInfinity), "infinity: no clamping"),
};

constexpr TypeSpec kFilms[] = {
    make_type("image", kImageFilm),
};

// ---------------------------------------------------------------------------------------------
// Filters (filters/*.cpp). Each filter has its own default radius.

constexpr ParamSpec kBoxFilter[] = {
    p_float("xwidth", 0.5f),
    p_float("ywidth", 0.5f),
};
constexpr ParamSpec kGaussianFilter[] = {
    p_float("xwidth", 2),
    p_float("ywidth", 2),
    p_float("alpha", 2),
};
constexpr ParamSpec kMitchellFilter[] = {
    p_float("xwidth", 2),
    p_float("ywidth", 2),
    p_float("B", 1.f / 3.f),
    p_float("C", 1.f / 3.f),
};
constexpr ParamSpec kSincFilter[] = {
    p_float("xwidth", 4),
    p_float("ywidth", 4),
    p_float("tau", 3),
};
constexpr ParamSpec kTriangleFilter[] = {
    p_float("xwidth", 2),
    p_float("ywidth", 2),
};

constexpr TypeSpec kFilters[] = {
    make_type("box", kBoxFilter),
    make_type("gaussian", kGaussianFilter),
    make_type("mitchell", kMitchellFilter),
    make_type("sinc", kSincFilter),
    make_type("triangle", kTriangleFilter),
};

// ---------------------------------------------------------------------------------------------
// Integrators (integrators/*.cpp).

constexpr const char* kPixelBoundsNote = "the film's sample bounds (x0 x1 y0 y1)";

constexpr ParamSpec pixel_bounds() {
  return computed(row("pixelbounds", Kind::kInt, 4, values()), kPixelBoundsNote);
}

constexpr ParamSpec kWhitted[] = {
    p_int("maxdepth", 5),
    pixel_bounds(),
};
constexpr ParamSpec kDirectLighting[] = {
    p_int("maxdepth", 5),
    p_string("strategy", "all"),  // "all" or "one"
    pixel_bounds(),
};
constexpr ParamSpec kPath[] = {
    p_int("maxdepth", 5),
    pixel_bounds(),
    p_float("rrthreshold", 1),
    p_string("lightsamplestrategy", "spatial"),  // "uniform", "power" or "spatial"
};
constexpr ParamSpec kVolPath[] = {
    p_int("maxdepth", 5),
    pixel_bounds(),
    p_float("rrthreshold", 1),
    p_string("lightsamplestrategy", "spatial"),
};
constexpr ParamSpec kBdpt[] = {
    p_int("maxdepth", 5),  // capped at 5 when visualizing
    p_bool("visualizestrategies", false),
    p_bool("visualizeweights", false),
    pixel_bounds(),
    p_string("lightsamplestrategy", "power"),  // note: not "spatial" as for path
};
// MLT renders the whole film and reads no "pixelbounds".
constexpr ParamSpec kMlt[] = {
    p_int("maxdepth", 5),
    p_int("bootstrapsamples", 100000),
    p_int("chains", 1000),
    p_int("mutationsperpixel", 100),
    p_float("largestepprobability", 0.3f),
    p_float("sigma", 0.01f),
};
constexpr ParamSpec kAmbientOcclusion[] = {
    pixel_bounds(),
    p_bool("cossample", true),
    p_int("nsamples", 64),
};
constexpr ParamSpec kSppm[] = {
    alias(p_int("iterations", 64), "numiterations"),  // "iterations" wins when both are given
    p_int("maxdepth", 5),
    computed(p_int("photonsperiteration", -1), "-1: one photon per film pixel"),
    // pbrt-v3 writes `1 << 31`, which is INT_MIN in practice: the image is written at the end only.
    p_int("imagewritefrequency", -2147483648.f),
    p_float("radius", 1),
};

constexpr TypeSpec kIntegrators[] = {
    make_type("whitted", kWhitted),
    make_type("directlighting", kDirectLighting),
    make_type("path", kPath),
    make_type("volpath", kVolPath),
    make_type("bdpt", kBdpt),
    make_type("mlt", kMlt),
    make_type("ambientocclusion", kAmbientOcclusion),
    make_type("sppm", kSppm),
};

// ---------------------------------------------------------------------------------------------
// Media (core/api.cpp MakeMedium). Both types read the scattering parameters.

constexpr const char* kSigmaANote = "the preset's sigma_a when \"preset\" is known, else this RGB";
constexpr const char* kSigmaSNote = "the preset's sigma_s when \"preset\" is known, else this RGB";

constexpr ParamSpec kHomogeneous[] = {
    p_string("preset", ""),
    p_float("scale", 1),  // multiplies sigma_a and sigma_s
    p_float("g", 0),
    computed(p_rgb("sigma_a", .0011f, .0024f, .014f), kSigmaANote),
    computed(p_rgb("sigma_s", 2.55f, 3.21f, 3.77f), kSigmaSNote),
};
constexpr ParamSpec kHeterogeneous[] = {
    p_string("preset", ""),
    p_float("scale", 1),
    p_float("g", 0),
    computed(p_rgb("sigma_a", .0011f, .0024f, .014f), kSigmaANote),
    computed(p_rgb("sigma_s", 2.55f, 3.21f, 3.77f), kSigmaSNote),
    required(p_bulk("density", Kind::kFloat)),  // exactly nx * ny * nz values
    p_int("nx", 1),
    p_int("ny", 1),
    p_int("nz", 1),
    p_point3("p0", 0, 0, 0),
    p_point3("p1", 1, 1, 1),
};

constexpr TypeSpec kMedia[] = {
    make_type("homogeneous", kHomogeneous),
    make_type("heterogeneous", kHeterogeneous),
};

// ---------------------------------------------------------------------------------------------
// Accelerators (accelerators/*.cpp).

constexpr ParamSpec kBvh[] = {
    p_string("splitmethod", "sah"),  // "sah", "hlbvh", "middle" or "equal"
    p_int("maxnodeprims", 4),
};
constexpr ParamSpec kKdTree[] = {
    p_int("intersectcost", 80),
    p_int("traversalcost", 1),
    p_float("emptybonus", 0.5f),
    p_int("maxprims", 1),
    computed(p_int("maxdepth", -1), "-1: round(8 + 1.3 * log2(primitive count))"),
};

constexpr TypeSpec kAccelerators[] = {
    make_type("bvh", kBvh),
    make_type("kdtree", kKdTree),
};

// clang-format on

// ---------------------------------------------------------------------------------------------
// The whole schema, indexed by Category.

constexpr CategorySpec kCategories[] = {
    make_category("shape", kShapes),
    make_category("material", kMaterials),
    make_category("float texture", kFloatTextures),
    make_category("spectrum texture", kSpectrumTextures),
    make_category("light", kLights),
    make_category("area light", kAreaLights),
    make_category("camera", kCameras),
    make_category("sampler", kSamplers),
    make_category("film", kFilms),
    make_category("filter", kFilters),
    make_category("integrator", kIntegrators),
    make_category("medium", kMedia),
    make_category("accelerator", kAccelerators),
};

static_assert(std::size(kCategories) == static_cast<std::size_t>(Category::kCount),
              "one CategorySpec per Category");
// The table is indexed by the enum, so its order must follow the enum's.
static_assert(kCategories[static_cast<int>(Category::kShape)].name == "shape");
static_assert(kCategories[static_cast<int>(Category::kFloatTexture)].name == "float texture");
static_assert(kCategories[static_cast<int>(Category::kAreaLight)].name == "area light");
static_assert(kCategories[static_cast<int>(Category::kFilm)].name == "film");
static_assert(kCategories[static_cast<int>(Category::kAccelerator)].name == "accelerator");

constexpr std::string_view kKindNames[] = {
    "int",    "float",   "bool",   "string", "point2",        "vector2",
    "point3", "vector3", "normal", "rgb",    "float texture", "spectrum texture",
};
static_assert(std::size(kKindNames) == static_cast<std::size_t>(Kind::kCount), "one name per Kind");

constexpr CategorySpec kNoCategory{"unknown", nullptr, 0};

}  // namespace

const CategorySpec& category_spec(Category c) {
  const auto i = static_cast<std::size_t>(c);
  return i < std::size(kCategories) ? kCategories[i] : kNoCategory;
}

int find_type(Category c, std::string_view name) {
  const CategorySpec& spec = category_spec(c);
  for (int i = 0; i < spec.num_types; ++i) {
    const TypeSpec& t = spec.types[i];
    // An empty alias means "none", so it must never match an empty name.
    if (t.name == name || (!t.alias.empty() && t.alias == name)) return i;
  }
  return -1;
}

int find_param(const TypeSpec& t, std::string_view name) {
  for (int i = 0; i < t.num_params; ++i) {
    const ParamSpec& p = t.params[i];
    if (p.name == name || (!p.alias.empty() && p.alias == name)) return i;
  }
  return -1;
}

std::string_view kind_name(Kind k) {
  const auto i = static_cast<std::size_t>(k);
  return i < std::size(kKindNames) ? kKindNames[i] : std::string_view("unknown");
}

std::string_view category_name(Category c) {
  return category_spec(c).name;
}

}  // namespace pbrta
