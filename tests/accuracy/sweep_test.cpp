// A real sweep on a compiled 16x16 scene: the error falls as spp grows, the
// budgets stop the ladder, and the overrides reach the renderer.
#include "tools/accuracy/sweep.h"

#include <gtest/gtest.h>

#include <sstream>

#include "compiler/archive_builder.h"
#include "compiler/diagnostics.h"
#include "compiler/scene_builder.h"
#include "compiler/source_files.h"
#include "test_support.h"

namespace {

// A diffuse sphere on a floor under a small spherical area light: path
// tracing noise from light and BSDF sampling, on 16x16 pixels.
const char kScene[] = R"(
Film "image" "integer xresolution" [16] "integer yresolution" [16] "string filename" "tiny.exr"
LookAt 0 1 6  0 0 0  0 1 0
Camera "perspective" "float fov" [45]
Sampler "random" "integer pixelsamples" [4]
Integrator "path" "integer maxdepth" [3]
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [8 8 8]
  Translate 1 3 2
  Shape "sphere" "float radius" [0.4]
AttributeEnd
Material "matte" "rgb Kd" [0.6 0.5 0.4]
Shape "sphere" "float radius" [1]
Shape "trianglemesh" "point P" [-5 -1 -5  5 -1 -5  5 -1 5  -5 -1 5] "integer indices" [0 1 2 0 2 3]
WorldEnd
)";

class TinySweep : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    std::string dir = testing_support::scratch_dir("TinySweep");
    std::string path = testing_support::write_file(dir + "/tiny.pbrt", kScene);
    std::ostringstream messages;
    pbrtc::SourceFiles files;
    pbrtc::Diagnostics diag(&files, &messages);
    pbrtc::SceneDesc scene;
    ASSERT_TRUE(pbrtc::build_scene(path, &files, &diag, &scene, nullptr)) << messages.str();
    pbrtc::ArchiveOptions opt;
    opt.threads = 1;
    pbrtc::ArchiveStats stats;
    std::string error;
    ASSERT_TRUE(pbrtc::write_archive(scene, files, dir, dir + "/tiny.pbrta", opt, &stats, &error))
        << error;
    archive_ = new pbrta::SceneArchive;
    ASSERT_TRUE(archive_->load(dir + "/tiny.pbrta", 1, &error)) << error;
    half_a_ = new rt::ImageRgb;
    half_b_ = new rt::ImageRgb;
    reference_ = new rt::ImageRgb;
    ASSERT_TRUE(
        accuracy::render_reference(*archive_, 1024, 1, 1000, half_a_, half_b_, reference_, &error))
        << error;
  }
  static void TearDownTestSuite() {
    delete archive_;
    delete half_a_;
    delete half_b_;
    delete reference_;
  }
  static pbrta::SceneArchive* archive_;
  static rt::ImageRgb *half_a_, *half_b_, *reference_;
};
pbrta::SceneArchive* TinySweep::archive_ = nullptr;
rt::ImageRgb* TinySweep::half_a_ = nullptr;
rt::ImageRgb* TinySweep::half_b_ = nullptr;
rt::ImageRgb* TinySweep::reference_ = nullptr;

TEST_F(TinySweep, ReferenceHalvesDifferAndAverage) {
  ASSERT_TRUE(archive_);
  EXPECT_EQ(reference_->width(), 16);
  EXPECT_EQ(reference_->height(), 16);
  ASSERT_EQ(half_a_->rgb.size(), reference_->rgb.size());
  ASSERT_EQ(half_b_->rgb.size(), reference_->rgb.size());
  double mean = 0, mean_a = 0, mean_b = 0;
  size_t differ = 0, lit = 0;
  for (size_t i = 0; i < reference_->rgb.size(); ++i) {
    const float a = half_a_->rgb[i], b = half_b_->rgb[i];
    // The reference is the halves' average, to the float operation that forms it.
    EXPECT_EQ(reference_->rgb[i], 0.5f * (a + b)) << i;
    mean += reference_->rgb[i];
    mean_a += a;
    mean_b += b;
    lit += reference_->rgb[i] > 0;
    differ += a != b;
  }
  const double n = double(reference_->rgb.size());
  EXPECT_GT(mean / n, 0.01);  // the scene is lit
  // Independent seeds: the halves' noise differs in nearly every lit value (512 samples each of
  // path-traced light leave no two equal by chance)...
  EXPECT_GE(double(differ), 0.95 * double(lit)) << differ << " of " << lit << " lit values differ";
  // ...while they estimate the same image: their means agree to well within 1%.
  EXPECT_NEAR(mean_a / mean_b, 1.0, 0.01);
}

TEST_F(TinySweep, ErrorFallsWithSamples) {
  ASSERT_TRUE(archive_);
  std::vector<accuracy::SweepConfig> configs;
  std::string error;
  ASSERT_TRUE(accuracy::make_configs({"random", "halton"}, {}, {}, &configs, &error));
  accuracy::SweepOptions options;
  options.budget = {1, 16, 0};
  std::vector<accuracy::SweepRow> rows;
  ASSERT_TRUE(accuracy::run_sweep(*archive_, "tiny", *reference_, configs, options, &rows, &error))
      << error;
  ASSERT_EQ(rows.size(), 10u);  // 1, 2, 4, 8, 16 for each sampler
  for (size_t c = 0; c < 2; ++c) {
    const accuracy::SweepRow& first = rows[5 * c];
    const accuracy::SweepRow& last = rows[5 * c + 4];
    EXPECT_EQ(first.config, configs[c].name());
    EXPECT_EQ(first.spp, 1);
    EXPECT_EQ(last.spp, 16);
    EXPECT_GT(first.seconds, 0);
    // Monte Carlo: relmse falls about as 1/spp, so 16x the samples cut it by
    // far more than 4x (the reference's own noise, 1/64 of the last rung's, aside).
    EXPECT_LT(last.errors.relmse, first.errors.relmse / 4) << first.config;
    EXPECT_LT(last.errors.rmse, first.errors.rmse / 2) << first.config;
    EXPECT_LT(last.errors.mare, first.errors.mare / 2) << first.config;
  }
}

TEST_F(TinySweep, TimeBudgetStopsAfterTheFirstRung) {
  ASSERT_TRUE(archive_);
  std::vector<accuracy::SweepConfig> configs(2);
  configs[1].integrator = "directlighting";
  accuracy::SweepOptions options;
  options.budget = {1, 64, 1e-9};
  std::vector<accuracy::SweepRow> rows;
  std::string error;
  ASSERT_TRUE(accuracy::run_sweep(*archive_, "tiny", *reference_, configs, options, &rows, &error))
      << error;
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].config, "scene");
  EXPECT_EQ(rows[1].config, "directlighting");
  EXPECT_EQ(rows[1].spp, 1);
}

TEST_F(TinySweep, OverridesReachTheRenderer) {
  ASSERT_TRUE(archive_);
  rt::ImageRgb path_image, direct_image, sobol_image;
  double s = 0, rs = 0;
  std::string error;
  accuracy::SweepConfig direct;
  direct.integrator = "directlighting";
  accuracy::SweepConfig sobol;
  sobol.sampler = "sobol";
  ASSERT_TRUE(accuracy::render_image(*archive_, {}, 64, 1, 7, &path_image, &s, &rs, &error));
  ASSERT_TRUE(accuracy::render_image(*archive_, direct, 64, 1, 7, &direct_image, &s, &rs, &error));
  ASSERT_TRUE(accuracy::render_image(*archive_, sobol, 64, 1, 7, &sobol_image, &s, &rs, &error));
  // Direct lighting misses the floor's and sphere's interreflection: darker overall.
  double path_sum = 0, direct_sum = 0;
  for (size_t i = 0; i < path_image.rgb.size(); ++i) {
    path_sum += path_image.rgb[i];
    direct_sum += direct_image.rgb[i];
  }
  EXPECT_LT(direct_sum, path_sum * 0.97);
  EXPECT_NE(sobol_image.rgb, path_image.rgb);  // another sampler, other samples
  // A light strategy belongs to path, volpath and bdpt; anything else says so.
  accuracy::SweepConfig bad = direct;
  bad.strategy = "power";
  EXPECT_FALSE(accuracy::render_image(*archive_, bad, 1, 1, 7, &direct_image, &s, &rs, &error));
  EXPECT_NE(error.find("only the path, volpath and bdpt integrators"), std::string::npos) << error;
  accuracy::SweepConfig unknown;
  unknown.sampler = "pmj02bn";
  EXPECT_FALSE(accuracy::render_image(*archive_, unknown, 1, 1, 7, &direct_image, &s, &rs, &error));
  EXPECT_NE(error.find("not supported yet"), std::string::npos) << error;
}

}  // namespace
