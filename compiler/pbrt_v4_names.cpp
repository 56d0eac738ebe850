#include "compiler/pbrt_v4_names.h"

namespace pbrtc {
namespace {

using pbrta::Category;

// The spectrum textures list holds the texture names; a float texture of the same name gets the
// same hint through the lookup below.
constexpr PbrtV4Name kNames[] = {
    {Category::kFilm, "rgb", "image", ""},
    {Category::kFilm, "gbuffer", "image", "without the extra channels"},
    {Category::kFilm, "spectral", "image", "RGB only"},
    {Category::kCamera, "spherical", "environment", "equirectangular mapping only"},
    {Category::kSampler, "independent", "random", ""},
    {Category::kSampler, "zsobol", "sobol", ""},
    {Category::kSampler, "paddedsobol", "02sequence", ""},
    {Category::kSampler, "pmj02bn", "02sequence", ""},
    {Category::kIntegrator, "simplepath", "path", ""},
    {Category::kIntegrator, "randomwalk", "path", ""},
    {Category::kIntegrator, "simplevolpath", "volpath", ""},
    {Category::kIntegrator, "lightpath", "bdpt", "which also traces from the light"},
    {Category::kIntegrator, "aov", "", ""},
    {Category::kShape, "bilinearmesh", "trianglemesh", "two triangles per quad"},
    {Category::kMaterial, "diffuse", "matte", ""},
    {Category::kMaterial, "conductor", "metal", ""},
    {Category::kMaterial, "coatedconductor", "metal", "without the coating"},
    {Category::kMaterial, "coateddiffuse", "substrate", ""},
    {Category::kMaterial, "dielectric", "glass", ""},
    {Category::kMaterial, "thindielectric", "glass", "a solid, not a thin sheet"},
    {Category::kMaterial, "diffusetransmission", "translucent", ""},
    {Category::kMaterial, "measured", "fourier", "with a .bsdf file"},
    {Category::kSpectrumTexture, "directionmix", "mix", ""},
    {Category::kMedium, "uniformgrid", "heterogeneous", ""},
    {Category::kMedium, "rgb", "heterogeneous", "one density grid"},
    {Category::kMedium, "nanovdb", "heterogeneous", "with the grid's densities written out"},
    {Category::kMedium, "cloud", "", ""},
};

}  // namespace

const PbrtV4Name* pbrt_v4_names(size_t* count) {
  *count = sizeof(kNames) / sizeof(kNames[0]);
  return kNames;
}

bool pbrt_v4_type_hint(Category c, std::string_view type, std::string* hint) {
  if (c == Category::kFloatTexture) c = Category::kSpectrumTexture;
  for (const PbrtV4Name& n : kNames) {
    if (n.category != c || n.v4 != type) continue;
    *hint = "a pbrt-v4 name; pbrt-v3 ";
    if (n.v3.empty()) {
      *hint += "has no equivalent";
    } else {
      *hint += n.how.empty() ? "calls it \"" : "comes nearest with \"";
      *hint += std::string(n.v3) + "\"";
      if (!n.how.empty()) *hint += ", " + std::string(n.how);
    }
    return true;
  }
  return false;
}

}  // namespace pbrtc
