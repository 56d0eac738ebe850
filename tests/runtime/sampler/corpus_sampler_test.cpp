// The hm-samplers scenes of the shared corpus (one per pbrt-v3 sampler) build
// their sampler with the sample counts the reference renders used.
#include <gtest/gtest.h>

#include "sampler_test_support.h"

namespace rt {
namespace {

TEST(CorpusSamplers, HmSamplersScenes) {
  const std::string dir =
      testing_support::shared_dir() + "/scenes/hm-samplers/pbrt-v3-rs/scenes/samplers/";
  struct {
    const char* file;
    int spp_override;
    int64_t expected;
  } cases[] = {
      {"02sequence", 1024, 1024}, {"halton", 0, 16},   {"maxmindist", 512, 512},
      {"random", 1024, 1024},     {"sobol", 512, 512}, {"stratified", 1024, 1024},
      {"stratified", 0, 16},  // xsamples/ysamples defaults 4x4; its "pixelsamples" is ignored
  };
  for (const auto& c : cases) {
    pbrta::SceneArchive archive;
    ASSERT_TRUE(testing_support::compile_file(
        dir + c.file + ".pbrt",
        testing_support::scratch_dir(std::string("corpus_") + c.file) + "/s.pbrta", &archive));
    std::string error;
    auto s = make_sampler(archive, c.spp_override, 1, {{0, 0}, {64, 64}}, &error);
    ASSERT_NE(s, nullptr) << c.file << ": " << error;
    EXPECT_EQ(s->samples_per_pixel(), c.expected) << c.file;
    std::vector<Vec2> pts = first_2d(*s, {10, 20});
    double mean_x = 0;
    for (Vec2 v : pts) mean_x += v.x;
    EXPECT_NEAR(mean_x / double(pts.size()), 0.5, c.expected >= 512 ? 0.02 : 0.1) << c.file;
  }
}

}  // namespace
}  // namespace rt
