// Tests for format/schema.h: the tables are complete, self-consistent, and carry pbrt-v3's own
// defaults and spellings (each expected value below was checked against pbrt-v3's source).

#include "format/schema.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <string_view>

namespace pbrta {
namespace {

constexpr Category kAllCategories[] = {
    Category::kShape,           Category::kMaterial,   Category::kFloatTexture,
    Category::kSpectrumTexture, Category::kLight,      Category::kAreaLight,
    Category::kCamera,          Category::kSampler,    Category::kFilm,
    Category::kFilter,          Category::kIntegrator, Category::kMedium,
    Category::kAccelerator,
};

// The parameter `param` of type `type` in category `c`, or nullptr (with a test failure).
const ParamSpec* find(Category c, std::string_view type, std::string_view param) {
  const int ti = find_type(c, type);
  EXPECT_GE(ti, 0) << category_name(c) << " \"" << type << "\" missing";
  if (ti < 0) return nullptr;
  const TypeSpec& t = category_spec(c).types[ti];
  const int pi = find_param(t, param);
  EXPECT_GE(pi, 0) << type << " has no \"" << param << "\"";
  if (pi < 0) return nullptr;
  return &t.params[pi];
}

// The default value v[0] of a parameter, or NaN when it is missing.
float default_of(Category c, std::string_view type, std::string_view param) {
  const ParamSpec* p = find(c, type, param);
  return p ? p->def.v[0] : std::nanf("");
}

TEST(Schema, EveryCategoryHasTypes) {
  for (Category c : kAllCategories) {
    const CategorySpec& spec = category_spec(c);
    EXPECT_GT(spec.num_types, 0) << category_name(c);
    EXPECT_NE(spec.types, nullptr) << category_name(c);
    EXPECT_EQ(spec.name, category_name(c));
  }
}

TEST(Schema, CategoryNamesReadAsInMessages) {
  EXPECT_EQ(category_name(Category::kShape), "shape");
  EXPECT_EQ(category_name(Category::kMaterial), "material");
  EXPECT_EQ(category_name(Category::kFloatTexture), "float texture");
  EXPECT_EQ(category_name(Category::kSpectrumTexture), "spectrum texture");
  EXPECT_EQ(category_name(Category::kLight), "light");
  EXPECT_EQ(category_name(Category::kAreaLight), "area light");
  EXPECT_EQ(category_name(Category::kCamera), "camera");
  EXPECT_EQ(category_name(Category::kSampler), "sampler");
  EXPECT_EQ(category_name(Category::kFilm), "film");
  EXPECT_EQ(category_name(Category::kFilter), "filter");
  EXPECT_EQ(category_name(Category::kIntegrator), "integrator");
  EXPECT_EQ(category_name(Category::kMedium), "medium");
  EXPECT_EQ(category_name(Category::kAccelerator), "accelerator");
}

TEST(Schema, KindNamesReadAsInMessages) {
  EXPECT_EQ(kind_name(Kind::kInt), "int");
  EXPECT_EQ(kind_name(Kind::kFloat), "float");
  EXPECT_EQ(kind_name(Kind::kRgb), "rgb");
  EXPECT_EQ(kind_name(Kind::kFloatTex), "float texture");
  EXPECT_EQ(kind_name(Kind::kSpectrumTex), "spectrum texture");
  for (int k = 0; k < static_cast<int>(Kind::kCount); ++k)
    EXPECT_FALSE(kind_name(static_cast<Kind>(k)).empty()) << k;
}

TEST(Schema, AliasesResolve) {
  EXPECT_EQ(find_type(Category::kSampler, "lowdiscrepancy"),
            find_type(Category::kSampler, "02sequence"));
  EXPECT_EQ(find_type(Category::kAreaLight, "area"), find_type(Category::kAreaLight, "diffuse"));
  EXPECT_EQ(find_type(Category::kLight, "exinfinite"), find_type(Category::kLight, "infinite"));
  EXPECT_GE(find_type(Category::kSampler, "lowdiscrepancy"), 0);
  EXPECT_GE(find_type(Category::kAreaLight, "area"), 0);
  EXPECT_GE(find_type(Category::kLight, "exinfinite"), 0);

  const TypeSpec& glass =
      category_spec(Category::kMaterial).types[find_type(Category::kMaterial, "glass")];
  EXPECT_EQ(find_param(glass, "index"), find_param(glass, "eta"));
  EXPECT_GE(find_param(glass, "index"), 0);

  const TypeSpec& mesh =
      category_spec(Category::kShape).types[find_type(Category::kShape, "trianglemesh")];
  EXPECT_EQ(find_param(mesh, "st"), find_param(mesh, "uv"));
  EXPECT_GE(find_param(mesh, "st"), 0);

  const TypeSpec& sppm =
      category_spec(Category::kIntegrator).types[find_type(Category::kIntegrator, "sppm")];
  EXPECT_EQ(find_param(sppm, "numiterations"), find_param(sppm, "iterations"));
  EXPECT_GE(find_param(sppm, "numiterations"), 0);
}

TEST(Schema, NoDuplicateTypeNames) {
  for (Category c : kAllCategories) {
    const CategorySpec& spec = category_spec(c);
    std::set<std::string_view> seen;
    for (int i = 0; i < spec.num_types; ++i) {
      const TypeSpec& t = spec.types[i];
      EXPECT_FALSE(t.name.empty()) << category_name(c) << " type " << i;
      EXPECT_TRUE(seen.insert(t.name).second) << category_name(c) << " " << t.name;
      if (!t.alias.empty()) {
        EXPECT_TRUE(seen.insert(t.alias).second) << category_name(c) << " " << t.alias;
      }
    }
  }
}

TEST(Schema, NoDuplicateParamNames) {
  for (Category c : kAllCategories) {
    const CategorySpec& spec = category_spec(c);
    for (int i = 0; i < spec.num_types; ++i) {
      const TypeSpec& t = spec.types[i];
      std::set<std::string_view> seen;
      for (int j = 0; j < t.num_params; ++j) {
        const ParamSpec& p = t.params[j];
        EXPECT_FALSE(p.name.empty()) << t.name << " param " << j;
        EXPECT_TRUE(seen.insert(p.name).second) << t.name << " " << p.name;
        if (!p.alias.empty()) {
          EXPECT_TRUE(seen.insert(p.alias).second) << t.name << " " << p.alias;
        }
      }
    }
  }
}

// Every flag combination must be one the compiler and the reader know how to handle.
TEST(Schema, RowsAreWellFormed) {
  for (Category c : kAllCategories) {
    const CategorySpec& spec = category_spec(c);
    for (int i = 0; i < spec.num_types; ++i) {
      const TypeSpec& t = spec.types[i];
      EXPECT_EQ(t.params == nullptr, t.num_params == 0) << t.name;
      for (int j = 0; j < t.num_params; ++j) {
        const ParamSpec& p = t.params[j];
        const std::string where = std::string(t.name) + "." + std::string(p.name);
        EXPECT_LT(static_cast<int>(p.kind), static_cast<int>(Kind::kCount)) << where;
        EXPECT_LE(p.arity, 4) << where;
        if (p.flags & kParamComputedDefault) {
          EXPECT_FALSE(p.note.empty()) << where;
        }
        if (p.flags & kParamFilename) {
          EXPECT_EQ(p.kind, Kind::kString) << where;
        }
        if (p.flags & kParamBulk) {
          EXPECT_EQ(p.arity, 0) << where;
        }
        if (p.arity == 0) {
          EXPECT_TRUE(p.flags & kParamBulk) << where;
        }
        // A string default must be spelled out unless the parameter is required.
        if (p.kind == Kind::kString && !(p.flags & kParamRequired)) {
          EXPECT_NE(p.def.s, nullptr) << where;
        }
      }
    }
  }
}

TEST(Schema, DefaultsMatchPbrtV3) {
  EXPECT_EQ(default_of(Category::kIntegrator, "path", "maxdepth"), 5);
  EXPECT_EQ(default_of(Category::kIntegrator, "path", "rrthreshold"), 1);
  EXPECT_EQ(default_of(Category::kIntegrator, "mlt", "largestepprobability"), 0.3f);
  EXPECT_EQ(default_of(Category::kIntegrator, "sppm", "iterations"), 64);
  EXPECT_EQ(default_of(Category::kIntegrator, "ambientocclusion", "nsamples"), 64);
  EXPECT_EQ(default_of(Category::kSampler, "halton", "pixelsamples"), 16);
  EXPECT_EQ(default_of(Category::kSampler, "random", "pixelsamples"), 4);
  EXPECT_EQ(default_of(Category::kSampler, "stratified", "xsamples"), 4);
  EXPECT_EQ(default_of(Category::kSampler, "stratified", "jitter"), 1);
  EXPECT_EQ(default_of(Category::kFilm, "image", "xresolution"), 1280);
  EXPECT_EQ(default_of(Category::kFilm, "image", "yresolution"), 720);
  EXPECT_EQ(default_of(Category::kFilm, "image", "diagonal"), 35);
  EXPECT_EQ(default_of(Category::kCamera, "perspective", "fov"), 90);
  EXPECT_EQ(default_of(Category::kCamera, "realistic", "focusdistance"), 10);
  EXPECT_EQ(default_of(Category::kMaterial, "plastic", "roughness"), 0.1f);
  EXPECT_EQ(default_of(Category::kMaterial, "metal", "roughness"), 0.01f);
  EXPECT_EQ(default_of(Category::kMaterial, "glass", "eta"), 1.5f);
  EXPECT_EQ(default_of(Category::kMaterial, "mirror", "Kr"), 0.9f);
  EXPECT_EQ(default_of(Category::kShape, "sphere", "radius"), 1);
  EXPECT_EQ(default_of(Category::kShape, "cylinder", "zmin"), -1);
  EXPECT_EQ(default_of(Category::kShape, "disk", "phimax"), 360);
  EXPECT_EQ(default_of(Category::kFilter, "gaussian", "alpha"), 2);
  EXPECT_EQ(default_of(Category::kFilter, "gaussian", "xwidth"), 2);
  EXPECT_EQ(default_of(Category::kFilter, "box", "xwidth"), 0.5f);
  EXPECT_EQ(default_of(Category::kFilter, "sinc", "xwidth"), 4);
  EXPECT_EQ(default_of(Category::kFilter, "mitchell", "B"), 1.f / 3.f);
  EXPECT_EQ(default_of(Category::kLight, "spot", "coneangle"), 30);
  EXPECT_EQ(default_of(Category::kLight, "spot", "conedeltaangle"), 5);
  EXPECT_EQ(default_of(Category::kLight, "projection", "fov"), 45);
  EXPECT_EQ(default_of(Category::kAccelerator, "kdtree", "intersectcost"), 80);
  EXPECT_EQ(default_of(Category::kAccelerator, "bvh", "maxnodeprims"), 4);
  EXPECT_EQ(default_of(Category::kSpectrumTexture, "imagemap", "maxanisotropy"), 8);
  EXPECT_EQ(default_of(Category::kSpectrumTexture, "marble", "variation"), 0.2f);

  // Spectra are grey, all three channels.
  const ParamSpec* kd = find(Category::kMaterial, "matte", "Kd");
  ASSERT_NE(kd, nullptr);
  EXPECT_EQ(kd->kind, Kind::kSpectrumTex);
  EXPECT_EQ(kd->def.v[0], 0.5f);
  EXPECT_EQ(kd->def.v[1], 0.5f);
  EXPECT_EQ(kd->def.v[2], 0.5f);

  const ParamSpec* crop = find(Category::kFilm, "image", "cropwindow");
  ASSERT_NE(crop, nullptr);
  EXPECT_EQ(crop->kind, Kind::kFloat);
  EXPECT_EQ(crop->arity, 4);
  EXPECT_EQ(crop->def.v[0], 0);
  EXPECT_EQ(crop->def.v[1], 1);
  EXPECT_EQ(crop->def.v[2], 0);
  EXPECT_EQ(crop->def.v[3], 1);

  const ParamSpec* split = find(Category::kAccelerator, "bvh", "splitmethod");
  ASSERT_NE(split, nullptr);
  ASSERT_NE(split->def.s, nullptr);
  EXPECT_EQ(std::string_view(split->def.s), "sah");

  const ParamSpec* strategy = find(Category::kIntegrator, "bdpt", "lightsamplestrategy");
  ASSERT_NE(strategy, nullptr);
  ASSERT_NE(strategy->def.s, nullptr);
  EXPECT_EQ(std::string_view(strategy->def.s), "power");
}

TEST(Schema, DependentDefaultsAreComputed) {
  const ParamSpec* zmin = find(Category::kShape, "sphere", "zmin");
  ASSERT_NE(zmin, nullptr);
  EXPECT_TRUE(zmin->flags & kParamComputedDefault);
  const ParamSpec* window = find(Category::kCamera, "perspective", "screenwindow");
  ASSERT_NE(window, nullptr);
  EXPECT_TRUE(window->flags & kParamComputedDefault);
  EXPECT_EQ(window->arity, 4);
  const ParamSpec* eta = find(Category::kMaterial, "metal", "eta");
  ASSERT_NE(eta, nullptr);
  EXPECT_TRUE(eta->flags & kParamComputedDefault);
  EXPECT_EQ(eta->note, "measured copper spectrum");
  const ParamSpec* lum = find(Category::kFilm, "image", "maxsampleluminance");
  ASSERT_NE(lum, nullptr);
  EXPECT_TRUE(lum->flags & kParamComputedDefault);
  EXPECT_TRUE(std::isinf(lum->def.v[0]));
}

TEST(Schema, FilesAndBulkDataAreFlagged) {
  const ParamSpec* ply = find(Category::kShape, "plymesh", "filename");
  ASSERT_NE(ply, nullptr);
  EXPECT_TRUE(ply->flags & kParamFilename);
  EXPECT_TRUE(ply->flags & kParamRequired);
  const ParamSpec* image = find(Category::kFloatTexture, "imagemap", "filename");
  ASSERT_NE(image, nullptr);
  EXPECT_TRUE(image->flags & kParamFilename);
  EXPECT_TRUE(image->flags & kParamRequired);
  const ParamSpec* lens = find(Category::kCamera, "realistic", "lensfile");
  ASSERT_NE(lens, nullptr);
  EXPECT_TRUE(lens->flags & kParamFilename);
  // The film's output name stays relative to the working directory, as in pbrt-v3.
  const ParamSpec* out = find(Category::kFilm, "image", "filename");
  ASSERT_NE(out, nullptr);
  EXPECT_FALSE(out->flags & kParamFilename);

  for (std::string_view name : {"P", "N", "S", "uv", "indices", "faceIndices"}) {
    const ParamSpec* p = find(Category::kShape, "trianglemesh", name);
    ASSERT_NE(p, nullptr) << name;
    EXPECT_TRUE(p->flags & kParamBulk) << name;
    EXPECT_EQ(p->arity, 0) << name;
  }
  const ParamSpec* density = find(Category::kMedium, "heterogeneous", "density");
  ASSERT_NE(density, nullptr);
  EXPECT_TRUE(density->flags & kParamBulk);
}

TEST(Schema, TextureParamsFollowTheirNamespace) {
  EXPECT_EQ(find(Category::kFloatTexture, "scale", "tex1")->kind, Kind::kFloatTex);
  EXPECT_EQ(find(Category::kSpectrumTexture, "scale", "tex1")->kind, Kind::kSpectrumTex);
  EXPECT_EQ(find(Category::kFloatTexture, "dots", "inside")->kind, Kind::kFloatTex);
  EXPECT_EQ(find(Category::kSpectrumTexture, "dots", "inside")->kind, Kind::kSpectrumTex);
  EXPECT_EQ(find(Category::kFloatTexture, "constant", "value")->kind, Kind::kFloat);
  EXPECT_EQ(find(Category::kSpectrumTexture, "constant", "value")->kind, Kind::kRgb);
  EXPECT_EQ(find(Category::kFloatTexture, "bilerp", "v00")->kind, Kind::kFloat);
  EXPECT_EQ(find(Category::kSpectrumTexture, "bilerp", "v00")->kind, Kind::kRgb);
  // Mix's amount is a float texture in both namespaces.
  EXPECT_EQ(find(Category::kSpectrumTexture, "mix", "amount")->kind, Kind::kFloatTex);
}

TEST(Schema, TwoDimensionalTexturesShareTheMappingBlock) {
  for (Category c : {Category::kFloatTexture, Category::kSpectrumTexture}) {
    for (std::string_view type : {"bilerp", "imagemap", "checkerboard", "dots"}) {
      const TypeSpec& t = category_spec(c).types[find_type(c, type)];
      EXPECT_EQ(find_param(t, "mapping"), 0) << type;
      EXPECT_EQ(find_param(t, "v2"), 6) << type;
    }
    for (std::string_view type : {"fbm", "wrinkled", "windy", "constant"}) {
      const TypeSpec& t = category_spec(c).types[find_type(c, type)];
      EXPECT_EQ(find_param(t, "mapping"), -1) << type;
    }
  }
}

TEST(Schema, MarbleIsSpectrumOnly) {
  EXPECT_EQ(find_type(Category::kFloatTexture, "marble"), -1);
  EXPECT_GE(find_type(Category::kSpectrumTexture, "marble"), 0);
}

TEST(Schema, UvTextureIsSpectrumOnly) {
  EXPECT_EQ(find_type(Category::kFloatTexture, "uv"), -1);
  EXPECT_GE(find_type(Category::kSpectrumTexture, "uv"), 0);
}

TEST(Schema, MaterialNoneHasNoParamsAndEmptyIsNotAType) {
  const int none = find_type(Category::kMaterial, "none");
  ASSERT_GE(none, 0);
  EXPECT_EQ(category_spec(Category::kMaterial).types[none].num_params, 0);
  EXPECT_EQ(find_type(Category::kMaterial, ""), -1);
}

TEST(Schema, UnknownTypeNotFound) {
  EXPECT_EQ(find_type(Category::kShape, "teapot"), -1);
  EXPECT_EQ(find_type(Category::kMaterial, "Matte"), -1);  // names are case-sensitive
  EXPECT_EQ(find_type(Category::kLight, "area"), -1);      // an area light, not a light
  EXPECT_EQ(find_type(Category::kSampler, ""), -1);
  const TypeSpec& sphere =
      category_spec(Category::kShape).types[find_type(Category::kShape, "sphere")];
  EXPECT_EQ(find_param(sphere, "radiu"), -1);
  EXPECT_EQ(find_param(sphere, ""), -1);
}

}  // namespace
}  // namespace pbrta
