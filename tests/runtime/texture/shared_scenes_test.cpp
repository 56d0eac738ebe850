// Every texture of the shared corpus's texture scenes (hm-textures,
// rs-procedural-textures; the big figure scenes would take too long) builds (or fails with the
// "not supported yet" message), and evaluates to finite values at a few
// surface points with and without footprints.
#include <gtest/gtest.h>

#include <string>

#include "runtime/runtime_test_support.h"
#include "runtime/texture/textures.h"
#include "test_support.h"

namespace rt {
namespace {

TEST(TexturesSharedScenes, BuildAndEvaluate) {
  int scenes = 0, textures = 0;
  for (const std::string& path : testing_support::shared_entry_scenes()) {
    if (path.find("textures") == std::string::npos ||
        testing_support::read_file(path).find("Texture") == std::string::npos)
      continue;
    SCOPED_TRACE(path);
    pbrta::SceneArchive a;
    std::string out = testing_support::scratch_dir("tex_shared") + "/scene.pbrta";
    if (!testing_support::compile_file(path, out, &a)) continue;
    TextureSet set;
    std::string error;
    if (!set.build(a, &error)) {
      EXPECT_EQ(error.rfind("not supported yet: ", 0), 0u) << error;
      continue;
    }
    ++scenes;
    for (uint32_t i = 0; i < set.size(); ++i, ++textures) {
      for (int k = 0; k < 4; ++k) {
        SurfaceInteraction si;
        si.uv = {.13f + .3f * k, .71f - .2f * k};
        si.p = {1.1f * k - 1, .3f, 2.f - k};
        if (k >= 2) {
          si.dudx = .01f * k;
          si.dvdy = .02f;
          si.dpdx = {.01f, 0, .02f};
          si.dpdy = {0, .03f, 0};
        }
        if (set.node(i).is_rgb) {
          Rgb v = set.eval_rgb(i, si);
          EXPECT_TRUE(v.is_finite()) << "texture " << i;
        } else {
          EXPECT_TRUE(std::isfinite(set.eval_float(i, si))) << "texture " << i;
        }
      }
    }
  }
  EXPECT_GE(scenes, 5);
  EXPECT_GE(textures, 10);
}

}  // namespace
}  // namespace rt
