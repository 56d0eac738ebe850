// Rendering in passes (renderer.h), stopping rules, render states (render_state.h):
// on shared scenes, through render_archive as pbrtrun runs it.
#include <gtest/gtest.h>

#include <ImfChannelList.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <vector>

#include "runtime/film/error_estimate.h"
#include "runtime/film/render_state.h"
#include "runtime/render/render_job.h"
#include "runtime/runtime_test_support.h"
#include "test_support.h"

namespace rt {
namespace {

const std::string kSamplers = "/scenes/hm-samplers/pbrt-v3-rs/scenes/samplers/";

struct Scene {
  pbrta::SceneArchive archive;
  std::string dir;
};

std::unique_ptr<Scene> compile(const std::string& name, const std::string& path) {
  auto s = std::make_unique<Scene>();
  s->dir = testing_support::scratch_dir("passes_" + name);
  EXPECT_TRUE(testing_support::compile_file(testing_support::shared_dir() + path,
                                            s->dir + "/scene.pbrta", &s->archive));
  return s;
}

RenderJobOptions options(int spp, uint64_t seed = 0) {
  RenderJobOptions o;
  o.quiet = true;
  o.write_files = false;
  o.keep_image = true;
  o.spp = spp;
  o.seed = seed;
  return o;
}

RenderJobResult run(const Scene& s, const RenderJobOptions& o) {
  RenderJobResult r;
  std::string error;
  EXPECT_TRUE(render_archive(s.archive, o, &r, &error)) << error;
  return r;
}

// The image a (merged) state holds equals the render `all`, up to double addition order.
void expect_state_is_render(const RenderState& state, const RenderJobResult& all,
                            const std::string& what) {
  Film film;
  std::string error;
  ASSERT_TRUE(film_of_state(state, &film, &error)) << error;
  const ImageRgb m = film.image();
  ASSERT_EQ(m.rgb.size(), all.image.rgb.size());
  for (size_t i = 0; i < m.rgb.size(); ++i)
    ASSERT_NEAR(m.rgb[i], all.image.rgb[i], 1e-5f * std::max(1.f, all.image.rgb[i]))
        << what << " " << i;
}

// Stops a render at the end of the pass that reaches `at` (as Ctrl-C between passes).
struct StopAt {
  std::atomic<bool> flag{false};
  void arm(RenderJobOptions* o, int64_t at) {
    o->interrupt = &flag;
    o->on_pass = [this, at](const Film&, int64_t samples, double) {
      if (samples >= at) flag = true;
    };
  }
};

RenderJobResult run_stopped(const Scene& s, RenderJobOptions o, int64_t at) {
  StopAt stop;
  stop.arm(&o, at);
  RenderJobResult r;
  std::string error;
  EXPECT_FALSE(render_archive(s.archive, o, &r, &error));
  EXPECT_TRUE(r.interrupted) << error;
  EXPECT_EQ(r.render.samples_per_pixel, at);
  return r;
}

// Stratified and the like render in one pass when nothing can stop them early (each pass
// would rebuild their patterns), in passes when something can.
TEST(Passes, WholeCountSamplersTakeOnePassUnlessAskedToStop) {
  auto s = compile("one_pass", kSamplers + "stratified.pbrt");
  EXPECT_EQ(run(*s, options(64, 1)).render.passes, 1);
  RenderJobOptions o = options(64, 1);
  o.time_limit = 1000;
  EXPECT_EQ(run(*s, o).render.passes, 7);  // 1, 2, 4, ..., 64
}

TEST(Passes, ScheduleDoublesThenStepsByEight) {
  std::vector<int64_t> ends, whole;
  for (int64_t s = 0; s < 40; s = pass_end(s, 40, false)) ends.push_back(pass_end(s, 40, false));
  for (int64_t s = 0; s < 40; s = pass_end(s, 40, true)) whole.push_back(pass_end(s, 40, true));
  EXPECT_EQ(ends, (std::vector<int64_t>{1, 2, 4, 8, 16, 24, 32, 40}));
  EXPECT_EQ(whole, (std::vector<int64_t>{1, 2, 4, 8, 16, 32, 40}));
}

// A render stopped after the passes that reach 16 samples is the 16-sample render, bit for
// bit, with the samplers whose values do not depend on the total count.
TEST(Passes, StoppedRenderIsTheRenderOfThatCount) {
  for (const char* sampler : {"sobol", "halton", "random"}) {
    auto s = compile(sampler, kSamplers + sampler + ".pbrt");
    RenderJobOptions planned = options(64, 7);
    const RenderJobResult stopped = run_stopped(*s, planned, 16);
    RenderJobOptions direct = options(16, 7);
    direct.differential_spp = 64;  // textures filtered as the planned render filters them
    const RenderJobResult one = run(*s, direct);
    EXPECT_EQ(stopped.image.rgb, one.image.rgb) << sampler;
    EXPECT_GT(one.render.passes, 1) << sampler;
  }
}

// Tiles merged as they finish (in tile order, as soon as those before them are) leave the
// film that merging the whole pass at its end leaves (which a saved state asks for): every
// tile once, none lost to a pass's last tiles or to tiles finishing out of order.
TEST(Passes, TilesMergedAsTheyFinishMakeTheWholePassFilm) {
  // A Gaussian filter 2 pixels wide: samples reach into the neighbouring tiles.
  auto s = compile("merge_order", "/scenes/rs-procedural-textures/checkerboard.pbrt");
  RenderJobOptions streamed = options(4, 3);
  streamed.resdiv = 4;
  streamed.time_limit = 1000;  // passes (02sequence renders in one otherwise)
  // The film's sums after each pass (the image, divided, could hide their last bits).
  auto keep_sums = [](RenderJobOptions* o, std::vector<double>* sums) {
    o->on_pass = [sums](const Film& film, int64_t, double) {
      sums->clear();
      for (int h = 0; h < 2; ++h)
        for (const FilmPixel& p : film.half_sums(h))
          sums->insert(sums->end(), {p.rgb[0], p.rgb[1], p.rgb[2], p.weight});
    };
  };
  std::vector<double> streamed_sums, whole_sums;
  keep_sums(&streamed, &streamed_sums);
  RenderJobOptions whole = streamed;
  keep_sums(&whole, &whole_sums);
  whole.save_state = s->dir + "/not-written.state";  // write_files is off
  const RenderJobResult a = run(*s, streamed), b = run(*s, whole);
  EXPECT_GT(a.render.passes, 1);
  ASSERT_FALSE(streamed_sums.empty());
  EXPECT_TRUE(streamed_sums == whole_sums);
}

// Resuming a saved state continues the very render: the same image as never stopping, for
// every sampler, the whole-count ones (stratified) included. (A render that may be stopped
// and resumed checkpoints; stratified renders in passes then, so the straight one does too.)
TEST(Passes, ResumedRenderIsTheUninterruptedRender) {
  for (const char* sampler : {"sobol", "stratified"}) {
    auto s = compile(std::string("resume_") + sampler, kSamplers + sampler + ".pbrt");
    RenderJobOptions first = options(64, 3);
    first.write_files = true;
    first.outfile = s->dir + "/part.exr";
    first.save_state = s->dir + "/part.state";
    run_stopped(*s, first, 16);
    RenderJobOptions rest = options(64, 3);
    rest.resume = s->dir + "/part.state";
    const RenderJobResult resumed = run(*s, rest);
    RenderJobOptions whole = options(64, 3);
    whole.checkpoint_every = 1000;
    const RenderJobResult straight = run(*s, whole);
    EXPECT_EQ(resumed.image.rgb, straight.image.rgb) << sampler;
    EXPECT_EQ(resumed.render.samples_per_pixel, 64);
  }
}

// Two states of disjoint sample ranges merge into the render of all their samples, up to
// the order of the float additions (the sums are doubles).
TEST(Passes, MergedRangesAreTheRenderOfAllTheirSamples) {
  auto s = compile("merge", kSamplers + "halton.pbrt");
  RenderJobOptions a = options(32, 5);
  a.write_files = true;
  a.outfile = s->dir + "/a.exr";
  a.save_state = s->dir + "/a.state";
  run_stopped(*s, a, 16);
  RenderJobOptions b = a;
  b.outfile = s->dir + "/b.exr";
  b.save_state = s->dir + "/b.state";
  b.first_sample = 16;
  run(*s, b);
  RenderState merged, other;
  std::string error;
  ASSERT_TRUE(read_render_state(a.save_state, &merged, &error)) << error;
  ASSERT_TRUE(read_render_state(b.save_state, &other, &error)) << error;
  EXPECT_EQ(merged.first, 0);
  EXPECT_EQ(other.first, 16);
  ASSERT_TRUE(merge_state(&merged, other, "b.state", &error)) << error;
  EXPECT_EQ(merged.samples(), 32);
  EXPECT_TRUE(merged.resumable());  // same seed, ranges that join
  expect_state_is_render(merged, run(*s, options(32, 5)), "");
  // The same state twice would count its samples twice.
  RenderState again;
  ASSERT_TRUE(read_render_state(b.save_state, &again, &error)) << error;
  EXPECT_FALSE(merge_state(&again, other, "b.state", &error));
  EXPECT_NE(error.find("same seed"), std::string::npos) << error;
}

// --shard K/N: N disjoint sample ranges whose states merge into the whole render, for
// every sampler (the whole-count ones build their pattern for the whole count in every shard).
TEST(Passes, ShardsMergeIntoTheWholeRender) {
  for (const char* sampler : {"halton", "stratified"}) {
    auto s = compile(std::string("shards_") + sampler, kSamplers + sampler + ".pbrt");
    RenderState merged;
    std::string error;
    for (int k = 0; k < 3; ++k) {
      RenderJobOptions o = options(32, 9);
      o.write_files = true;
      o.outfile = s->dir + "/shard.exr";
      o.save_state = s->dir + "/shard" + std::to_string(k) + ".state";
      o.shard = k;
      o.shards = 3;
      const RenderJobResult r = run(*s, o);
      EXPECT_EQ(r.render.samples_per_pixel, 32 * (k + 1) / 3 - 32 * k / 3);
      RenderState part;
      ASSERT_TRUE(read_render_state(o.save_state, k == 0 ? &merged : &part, &error)) << error;
      if (k > 0) {
        ASSERT_TRUE(merge_state(&merged, part, o.save_state, &error)) << error;
      }
    }
    EXPECT_TRUE(merged.resumable());
    EXPECT_EQ(merged.samples(), 32);
    expect_state_is_render(merged, run(*s, options(32, 9)), sampler);
  }
}

TEST(Passes, StatesOfAnotherSceneOrFilmAreRefused) {
  auto s = compile("refuse", kSamplers + "halton.pbrt");
  auto t = compile("refuse_other", kSamplers + "sobol.pbrt");
  RenderJobOptions a = options(8, 1);
  a.write_files = true;
  a.outfile = s->dir + "/a.exr";
  a.save_state = s->dir + "/a.state";
  run(*s, a);
  RenderJobOptions b = a;
  b.outfile = t->dir + "/b.exr";
  b.save_state = t->dir + "/b.state";
  b.seed = 2;
  run(*t, b);
  RenderJobOptions c = a;
  c.outfile = s->dir + "/c.exr";
  c.save_state = s->dir + "/c.state";
  c.seed = 3;
  c.resdiv = 2;
  run(*s, c);
  RenderState sa, sb, sc;
  std::string error;
  ASSERT_TRUE(read_render_state(a.save_state, &sa, &error));
  ASSERT_TRUE(read_render_state(b.save_state, &sb, &error));
  ASSERT_TRUE(read_render_state(c.save_state, &sc, &error));
  EXPECT_FALSE(merge_state(&sa, sb, "b.state", &error));
  EXPECT_NE(error.find("another archive"), std::string::npos) << error;
  EXPECT_FALSE(merge_state(&sa, sc, "c.state", &error));
  EXPECT_NE(error.find("another resolution"), std::string::npos) << error;
  // Resuming with another resolution, or from a damaged file, is refused before rendering.
  RenderJobOptions r = options(8, 3);
  r.resdiv = 1;
  r.resume = c.save_state;
  RenderJobResult rr;
  EXPECT_FALSE(render_archive(s->archive, r, &rr, &error));
  EXPECT_NE(error.find("another resolution"), std::string::npos) << error;
  std::string bytes = testing_support::read_file(a.save_state);
  bytes[bytes.size() / 2] ^= 1;
  testing_support::write_file(s->dir + "/damaged.state", bytes);
  r.resume = s->dir + "/damaged.state";
  EXPECT_FALSE(render_archive(s->archive, r, &rr, &error));
  EXPECT_NE(error.find("checksum"), std::string::npos) << error;
}

// --target-error stops at the first pass whose estimate is at or below the target.
TEST(Passes, TargetErrorStopsWithinOnePassOfTheTarget) {
  auto s = compile("target", "/scenes/rs-cornell-box/cornell_box.pbrt");
  RenderJobOptions o = options(4096, 1);
  o.resdiv = 8;
  o.target_error = 0.15;
  std::vector<double> estimates;
  o.on_pass = [&](const Film& film, int64_t, double) {
    const ErrorEstimate e = estimate_error(film);
    estimates.push_back(e.valid ? e.rel_error : 1e30);
  };
  const RenderJobResult r = run(*s, o);
  ASSERT_GE(estimates.size(), 2u);
  EXPECT_EQ(r.render.stop, StopReason::kTargetError);
  EXPECT_LE(estimates.back(), 0.15);
  EXPECT_GT(estimates[estimates.size() - 2], 0.15);
  EXPECT_DOUBLE_EQ(r.render.error_estimate, estimates.back());
  EXPECT_LT(r.render.samples_per_pixel, 4096);
}

// --time-limit: the render ends before the limit or at most one pass after it.
TEST(Passes, TimeLimitOverrunsByAtMostOnePass) {
  auto s = compile("time", "/scenes/rs-cornell-box/cornell_box.pbrt");
  RenderJobOptions o = options(1 << 20, 1);
  o.resdiv = 4;
  o.time_limit = 1.5;
  o.time_origin = std::chrono::steady_clock::now();
  std::vector<double> ends;
  o.on_pass = [&](const Film&, int64_t, double) {
    ends.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - o.time_origin).count());
  };
  const RenderJobResult r = run(*s, o);
  EXPECT_EQ(r.render.stop, StopReason::kTimeLimit);
  ASSERT_GE(ends.size(), 3u);
  const double last_pass = ends.back() - ends[ends.size() - 2];
  EXPECT_LE(ends.back(), 1.5 + last_pass);
}

// --error-layer: the EXR carries the per-pixel estimate as layer "error".
TEST(Passes, ErrorLayerIsWrittenBesideTheImage) {
  auto s = compile("layer", kSamplers + "halton.pbrt");
  RenderJobOptions o = options(8, 1);
  o.write_files = true;
  o.outfile = s->dir + "/layer.exr";
  o.error_layer = true;
  run(*s, o);
  Imf::InputFile file(o.outfile.c_str());
  int found = 0;
  for (auto c = file.header().channels().begin(); c != file.header().channels().end(); ++c)
    found += std::string(c.name()).rfind("error.", 0) == 0;
  EXPECT_EQ(found, 3);
}

}  // namespace
}  // namespace rt
