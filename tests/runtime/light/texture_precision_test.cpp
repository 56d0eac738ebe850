// pbrtc --texture-precision f16 on v3-figures f8-22's HDR environment map (unorm8 refuses it):
// the map's radiance in any direction lies within a relative half-ulp of half precision of the
// f32 archive's (the lookup is a convex combination of texels), it is not the same radiance
// everywhere (the option does something), and importance sampling is unchanged bit for bit
// (the sampling distribution stays f32).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "compiler/archive_builder.h"
#include "compiler/parser.h"
#include "compiler/scene_builder.h"
#include "runtime/core/rng.h"
#include "runtime/geometry/shape_table.h"
#include "runtime/light/lights.h"
#include "test_support.h"

namespace rt {
namespace {

struct Built {
  pbrta::SceneArchive archive;
  ShapeTable shapes;
  LightSet lights;
};

bool build(const pbrtc::SceneDesc& scene, const pbrtc::SourceFiles& files, const std::string& base,
           pbrta::PixelFormat format, Built* b) {
  pbrtc::ArchiveOptions opt;
  opt.texture_format = format;
  const std::string out =
      testing_support::scratch_dir("texprec_light_" + std::to_string(int(format))) + "/a.pbrta";
  std::string error;
  Bounds3 world;
  world.extend(Vec3{-50, -50, -50});
  world.extend(Vec3{50, 50, 50});
  if (!pbrtc::write_archive(scene, files, base, out, opt, nullptr, &error) ||
      !b->archive.load(out, 1, &error) || !b->shapes.build(b->archive, &error) ||
      !b->lights.build(b->archive, b->shapes, world, &error)) {
    ADD_FAILURE() << error;
    return false;
  }
  return true;
}

TEST(TexturePrecision, HalfEnvironmentMapKeepsItsRadianceAndItsSampling) {
  const std::string path = testing_support::shared_dir() + "/scenes/v3-figures/f8-22.pbrt";
  pbrtc::SourceFiles files;
  pbrtc::Diagnostics diag(&files, nullptr);
  pbrtc::SceneDesc scene;
  ASSERT_TRUE(pbrtc::build_scene(path, &files, &diag, &scene));
  Built f32, f16;
  ASSERT_TRUE(build(scene, files, pbrtc::directory_of(path), pbrta::PixelFormat::kFloat32, &f32));
  ASSERT_TRUE(build(scene, files, pbrtc::directory_of(path), pbrta::PixelFormat::kHalf16, &f16));
  ASSERT_EQ(f16.lights.count(), 1u);
  ASSERT_EQ(f16.lights.kind(0), LightKind::kInfinite);
  Rng rng(7);
  int differ = 0;
  float brightest = 0;
  Interaction ref;
  ref.n = Vec3{0, 0, 1};
  for (int i = 0; i < 20000; ++i) {
    RayDifferential ray;
    ray.d = uniform_sample_sphere({rng.next_float(), rng.next_float()});
    const Rgb a = f32.lights.infinite_le(ray), h = f16.lights.infinite_le(ray);
    for (int k = 0; k < 3; ++k) {
      ASSERT_LE(std::fabs(h[k] - a[k]), a[k] * (1.f / 2048) + 1e-6f) << i;
      differ += h[k] != a[k];
      brightest = std::max(brightest, a[k]);
    }
    // Sampling: the same direction, pdf and, within the bound, radiance.
    const Vec2 u{rng.next_float(), rng.next_float()};
    LightSample sa, sh;
    const Rgb la = f32.lights.sample_li(0, ref, u, &sa), lh = f16.lights.sample_li(0, ref, u, &sh);
    ASSERT_EQ(sa.pdf, sh.pdf) << i;
    ASSERT_EQ(sa.wi.x, sh.wi.x) << i;
    ASSERT_EQ(sa.wi.y, sh.wi.y) << i;
    for (int k = 0; k < 3; ++k) ASSERT_LE(std::fabs(lh[k] - la[k]), la[k] / 2048 + 1e-6f) << i;
    ASSERT_EQ(f32.lights.pdf_li(0, ref, ray.d, nullptr), f16.lights.pdf_li(0, ref, ray.d, nullptr));
  }
  EXPECT_GT(brightest, 1.f);  // HDR: what unorm8 cannot hold
  EXPECT_GT(differ, 1000);
}

}  // namespace
}  // namespace rt
