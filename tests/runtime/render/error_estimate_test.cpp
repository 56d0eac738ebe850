// The render's own error estimate (runtime/film/error_estimate.h) against the true
// error, on shared scenes: a long reference rendered here (16x the largest count, so
// its own noise adds at most ~3% to the measured truth), then one render whose passes
// are measured at three sample counts, both ways.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

#include "runtime/film/error_estimate.h"
#include "runtime/render/render_job.h"
#include "runtime/runtime_test_support.h"
#include "test_support.h"

namespace rt {
namespace {

double true_rel_error(const ImageRgb& x, const ImageRgb& ref) {
  double sum = 0;
  for (size_t i = 0; i < x.rgb.size(); ++i) {
    const double d = double(x.rgb[i]) - double(ref.rgb[i]);
    sum += d * d / (double(ref.rgb[i]) * double(ref.rgb[i]) + 0.01);
  }
  return std::sqrt(sum / double(x.rgb.size()));
}

struct Case {
  const char* scene;
  int resdiv;
};

// The estimate over the true error at `counts` samples per pixel.
std::map<int64_t, double> ratios(const Case& c, const std::vector<int64_t>& counts) {
  pbrta::SceneArchive archive;
  const std::string scratch = testing_support::scratch_dir(
      std::string("error_estimate_") + std::to_string(std::hash<std::string>()(c.scene)));
  EXPECT_TRUE(testing_support::compile_file(testing_support::shared_dir() + "/scenes/" + c.scene,
                                            scratch + "/scene.pbrta", &archive));
  RenderJobOptions o;
  o.quiet = true;
  o.write_files = false;
  o.keep_image = true;
  o.resdiv = c.resdiv;
  o.spp = int(16 * counts.back());
  o.seed = 1000;
  std::string error;
  RenderJobResult reference;
  EXPECT_TRUE(render_archive(archive, o, &reference, &error)) << error;
  std::map<int64_t, double> out;
  o.spp = int(counts.back());
  o.seed = 1;
  o.keep_image = false;
  o.differential_spp = 0;
  o.on_pass = [&](const Film& film, int64_t samples, double) {
    for (int64_t n : counts)
      if (n == samples) {
        const ErrorEstimate e = estimate_error(film);
        const double truth = true_rel_error(film.image(), reference.image);
        EXPECT_TRUE(e.valid);
        out[n] = e.rel_error / truth;
        std::printf("%s at %lld spp: estimated %.3g%%, true %.3g%%, ratio %.3f\n", c.scene,
                    (long long)n, 100 * e.rel_error, 100 * truth, e.rel_error / truth);
      }
  };
  RenderJobResult r;
  EXPECT_TRUE(render_archive(archive, o, &r, &error)) << error;
  return out;
}

// Independent samples: the estimate's theory holds, so does the 0.7x-1.4x band.
TEST(ErrorEstimate, TracksTheTrueErrorWithIndependentSamples) {
  const auto r = ratios({"rs-veach-mis/veach-mis/mis.pbrt", 8}, {4, 16, 64});  // random sampler
  ASSERT_EQ(r.size(), 3u);
  for (const auto& [n, ratio] : r) {
    EXPECT_GE(ratio, 0.7) << n << " spp";
    EXPECT_LE(ratio, 1.4) << n << " spp";
  }
}

// Low-discrepancy samplers on path-traced scenes: pessimistic, within 0.7x-2x.
TEST(ErrorEstimate, IsPessimisticWithinTwiceWithLowDiscrepancySamplers) {
  for (const Case& c : {Case{"rs-cornell-box/cornell_box.pbrt", 8},  // halton
                        Case{"v3-killeroo-simple/killeroo-simple.pbrt", 8}}) {
    const auto r = ratios(c, {4, 16, 64});
    ASSERT_EQ(r.size(), 3u) << c.scene;
    for (const auto& [n, ratio] : r) {
      EXPECT_GE(ratio, 0.7) << c.scene << " at " << n << " spp";
      EXPECT_LE(ratio, 2.0) << c.scene << " at " << n << " spp";
    }
  }
}

}  // namespace
}  // namespace rt
