// pbrt-v3's mlt: the primary-sample-space sampler's mutations and their undoing, the image
// against bdpt's on a scene both render, and the same image for any thread count.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <memory>
#include <string>

#include "box_scene.h"
#include "runtime/render/mlt.h"
#include "runtime/render/mlt_sampler.h"
#include "runtime/render_text.h"

namespace rt {
namespace {

TEST(MltSampler, RejectRestoresAndSmallStepsStayClose) {
  MltSampler s(16, 3, 0.01f, 0.f, 3);  // never a large step after the first iteration
  s.start_iteration();
  s.start_stream(0);
  float a = s.get_1d(), b = s.get_1d();
  s.accept();
  s.start_iteration();
  s.start_stream(0);
  float a2 = s.get_1d(), b2 = s.get_1d();
  // Small steps: normal offsets of sigma 0.01, wrapped into [0, 1).
  auto wrapped = [](float x, float y) { return std::min(std::fabs(x - y), 1 - std::fabs(x - y)); };
  EXPECT_LT(wrapped(a, a2), 0.06f);
  EXPECT_LT(wrapped(b, b2), 0.06f);
  EXPECT_TRUE(a != a2 || b != b2);
  s.reject();
  s.start_iteration();
  s.start_stream(0);
  // The rejected proposal is undone: the next small step starts from a and b again.
  float a3 = s.get_1d();
  EXPECT_LT(wrapped(a, a3), 0.06f);
  // Streams interleave: stream 1's first number is a coordinate of its own.
  s.start_stream(1);
  float c = s.get_1d();
  EXPECT_GE(c, 0.f);
  EXPECT_LT(c, 1.f);
}

TEST(MltSampler, LargeStepsAreUniform) {
  MltSampler s(16, 5, 0.01f, 1.f, 1);
  double sum = 0, sum2 = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    s.start_iteration();
    s.start_stream(0);
    float x = s.get_1d();
    ASSERT_GE(x, 0.f);
    ASSERT_LT(x, 1.f);
    sum += x;
    sum2 += x * x;
    s.accept();
  }
  EXPECT_NEAR(sum / n, 0.5, 0.01);
  EXPECT_NEAR(sum2 / n - (sum / n) * (sum / n), 1.0 / 12, 0.005);
}

// restart(i) gives what a sampler made with stream i gives, whatever the restarted one did
// before (bootstrap paths share one sampler per thread).
TEST(MltSampler, RestartIsAFreshSampler) {
  auto run = [](MltSampler& s, std::vector<float>* out) {
    for (int it = 0; it < 50; ++it) {
      s.start_iteration();
      for (int stream = 0; stream < 3; ++stream) {
        s.start_stream(stream);
        for (int d = 0; d < 1 + it % 7; ++d) out->push_back(s.get_1d());
      }
      if (it % 3)
        s.accept();
      else
        s.reject();
    }
  };
  MltSampler used(16, 3, 0.01f, 0.3f, 3, 9);
  std::vector<float> ignored, fresh_values, restarted_values;
  run(used, &ignored);
  used.restart(8);
  MltSampler fresh(16, 8, 0.01f, 0.3f, 3, 9);
  run(fresh, &fresh_values);
  run(used, &restarted_values);
  EXPECT_EQ(fresh_values, restarted_values);
  EXPECT_NE(ignored, fresh_values);
}

// pbrt-v3's 1000 chains: each chain keeps the path depth the bootstrap gave it, so with few
// chains the share of each depth in the image is a coarse draw (64 chains put 7% too much light
// on the floor for a given seed, whatever the mutation count).
std::string box(const char* integrator) {
  const std::string mlt = " \"integer bootstrapsamples\" [20000] \"integer chains\" [1000]";
  return box_scene(std::string("Integrator \"") + integrator + "\" \"integer maxdepth\" [5]" +
                       (std::string(integrator) == "mlt" ? mlt : ""),
                   true, true);
}

struct MltImage {
  std::vector<Rgb> pixels;
  bool ok = false;
};

MltImage render_mlt_text(const std::string& name, int64_t mutations, int threads, uint64_t seed) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
  Rendered r = render_text(name, box("mlt"), seed, int(mutations));
  MltImage out;
  out.ok = r.ok;
  out.pixels = r.pixels;
  return out;
}

double region_mean(const std::vector<Rgb>& p, int x0, int x1, int y0, int y1) {
  double s = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) s += p[size_t(y) * 24 + x].luminance();
  return s / ((x1 - x0) * (y1 - y0));
}

// Several independent mlt renders average to bdpt's image: the whole frame and each quadrant.
TEST(Mlt, AgreesWithBdpt) {
  Rendered bdpt = render_text("mlt_box_bdpt", box("bdpt"));
  ASSERT_TRUE(bdpt.ok);
  std::vector<Rgb> sum(bdpt.pixels.size());
  const int runs = 4;
  for (int k = 0; k < runs; ++k) {
    MltImage m = render_mlt_text("mlt_box_" + std::to_string(k), 256, 2, uint64_t(k + 1));
    ASSERT_TRUE(m.ok);
    for (size_t i = 0; i < sum.size(); ++i) sum[i] += m.pixels[i] / float(runs);
  }
  for (int q = 0; q < 5; ++q) {
    int x0 = q == 4 ? 0 : (q % 2) * 12, y0 = q == 4 ? 0 : (q / 2) * 12;
    int x1 = q == 4 ? 24 : x0 + 12, y1 = q == 4 ? 24 : y0 + 12;
    double a = region_mean(bdpt.pixels, x0, x1, y0, y1), b = region_mean(sum, x0, x1, y0, y1);
    EXPECT_NEAR(b / a, 1, 0.05) << "region " << q << ": bdpt " << a << ", mlt " << b;
  }
}

// The same seed gives the same image with one thread and with two (chains and bootstrap
// samples own their generators; only the order of additions on the film may differ).
TEST(Mlt, SameImageForAnyThreadCount) {
  MltImage one = render_mlt_text("mlt_threads_1", 16, 1, 7);
  MltImage two = render_mlt_text("mlt_threads_2", 16, 2, 7);
  ASSERT_TRUE(one.ok && two.ok);
  double total = 0;
  for (size_t i = 0; i < one.pixels.size(); ++i) {
    total += one.pixels[i].luminance();
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(one.pixels[i][c], two.pixels[i][c], 1e-5f * std::max(1.f, one.pixels[i][c]));
  }
  EXPECT_GT(total, 0);
  MltImage other_seed = render_mlt_text("mlt_threads_seed", 16, 2, 8);
  double diff = 0;
  for (size_t i = 0; i < one.pixels.size(); ++i)
    diff += std::fabs(one.pixels[i].luminance() - other_seed.pixels[i].luminance());
  EXPECT_GT(diff, 0) << "another seed must give other noise";
}

}  // namespace
}  // namespace rt
