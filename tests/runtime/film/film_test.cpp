// The film: pbrt-v3's crop and sample rectangles (checked against the crops
// of real reference renders), filtered splatting that returns a constant
// radiance exactly, scale and maxsampleluminance, tile merging that changes
// only last bits with order, robustness of add_sample, splats, and output.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <thread>
#include <vector>

#include "runtime/core/rng.h"
#include "runtime/film/film.h"
#include "runtime/runtime_test_support.h"
#include "test_support.h"

namespace rt {
namespace {

bool film_from_text(const std::string& name, const std::string& header, const FilmOptions& options,
                    Film* film, std::string* error) {
  pbrta::SceneArchive a;
  if (!testing_support::compile_text(testing_support::scratch_dir("film_" + name),
                                     header + "\nCamera \"perspective\"\nWorldBegin\nWorldEnd\n",
                                     &a))
    return false;
  return film->build(a, options, error);
}

void expect_bounds(const Bounds2i& b, int x0, int y0, int x1, int y1) {
  EXPECT_EQ(b.min.x, x0);
  EXPECT_EQ(b.min.y, y0);
  EXPECT_EQ(b.max.x, x1);
  EXPECT_EQ(b.max.y, y1);
}

TEST(Film, CropOfTheSppmReferenceMatchesItsExr) {
  // v3-caustic-glass-sppm/f16-11a.pbrt, rendered with resdiv 2: the float
  // products make the crop start at 211, not 210 (279x300 pixels).
  Film film;
  std::string error;
  FilmOptions options;
  options.resdiv = 2;
  pbrta::SceneArchive a;
  std::string dir = testing_support::scratch_dir("film_sppm_crop");
  ASSERT_TRUE(testing_support::compile_file(
      testing_support::shared_dir() + "/scenes/v3-caustic-glass-sppm/f16-11a.pbrt",
      dir + "/f16-11a.pbrta", &a));
  ASSERT_TRUE(film.build(a, options, &error)) << error;
  EXPECT_EQ(film.full_resolution(), (Point2i{700, 1000}));
  Bounds2i c = film.cropped_pixel_bounds();
  EXPECT_EQ(c.width(), 279);
  EXPECT_EQ(c.height(), 300);
  expect_bounds(c, 211, 400, 490, 700);
  EXPECT_EQ(film.filename(), "f16-11a.exr");
  EXPECT_FLOAT_EQ(film.scale(), 1.5f);

  ImageRgb ref;
  ASSERT_TRUE(read_exr(testing_support::shared_dir() + "/refs/v3-caustic-glass-sppm__f16-11a.exr",
                       &ref, &error))
      << error;
  expect_bounds(ref.data_window, c.min.x, c.min.y, c.max.x, c.max.y);
  expect_bounds(ref.display_window, 0, 0, 700, 1000);
}

TEST(Film, CropOfTheCloudReference) {
  // v3-cloud/cloud.pbrt's film, resdiv 3, with its gaussian filter.
  Film film;
  std::string error;
  FilmOptions options;
  options.resdiv = 3;
  ASSERT_TRUE(film_from_text("cloud",
                             "Film \"image\" \"integer yresolution\" [900] \"integer xresolution\" "
                             "[900]\n  \"float cropwindow\" [0 .9 0 .8]\nPixelFilter \"gaussian\"",
                             options, &film, &error))
      << error;
  EXPECT_EQ(film.full_resolution(), (Point2i{300, 300}));
  expect_bounds(film.cropped_pixel_bounds(), 0, 0, 270, 240);
  // Grown by the radius 2 with the half-pixel shift: floor(0.5 - 2), ceil(270 - 0.5 + 2).
  expect_bounds(film.sample_bounds(), -2, -2, 272, 242);

  ImageRgb ref;
  ASSERT_TRUE(read_exr(testing_support::shared_dir() + "/refs/v3-cloud__cloud.exr", &ref, &error))
      << error;
  expect_bounds(ref.data_window, 0, 0, 270, 240);
  expect_bounds(ref.display_window, 0, 0, 300, 300);
}

TEST(Film, CommandLineCropAndDefaults) {
  Film film;
  std::string error;
  FilmOptions options;
  options.has_crop = true;
  // Either order per axis, clamped to [0, 1], as pbrt-v3 reads a crop window.
  float crop[4] = {0.75f, 0.25f, -1, 0.5f};
  std::copy(crop, crop + 4, options.crop);
  ASSERT_TRUE(film_from_text("cli_crop", "Film \"image\" \"float cropwindow\" [0 .1 0 .1]", options,
                             &film, &error))
      << error;
  EXPECT_EQ(film.full_resolution(), (Point2i{1280, 720}));
  expect_bounds(film.cropped_pixel_bounds(), 320, 0, 960, 360);
  EXPECT_EQ(film.filename(), "pbrt.exr");
  EXPECT_EQ(film.max_sample_luminance(), kInfinity);
  EXPECT_FLOAT_EQ(film.diagonal(), 0.035f);
  EXPECT_EQ(film.filter().type, Filter::Type::kBox);
  // Box radius 0.5: samples exactly over the crop.
  expect_bounds(film.sample_bounds(), 320, 0, 960, 360);
}

TEST(Film, EmptyFilmsAreRefused) {
  Film film;
  std::string error;
  FilmOptions options;
  options.resdiv = 8;
  EXPECT_FALSE(
      film_from_text("tiny", "Film \"image\" \"integer xresolution\" 4", options, &film, &error));
  EXPECT_NE(error.find("no pixels"), std::string::npos) << error;
  EXPECT_NE(error.find("scene.pbrt:1"), std::string::npos) << error;
  error.clear();
  // pbrtc refuses an empty cropwindow in the scene; the command line can still give one.
  FilmOptions empty_crop;
  empty_crop.has_crop = true;
  float crop[4] = {0.5f, 0.5f, 0, 1};
  std::copy(crop, crop + 4, empty_crop.crop);
  EXPECT_FALSE(film_from_text("empty_crop", "", empty_crop, &film, &error));
  EXPECT_NE(error.find("selects no pixel"), std::string::npos) << error;
}

Filter box() {
  return Filter();
}
Filter gaussian() {
  Filter f;
  f.type = Filter::Type::kGaussian;
  f.radius = {2, 2};
  finish_gaussian(&f);
  return f;
}

const float kFull[4] = {0, 1, 0, 1};

// Splits the sample bounds into tiles of `size` and adds `per_pixel` random
// samples of radiance fn(p) per sample-bounds pixel, each to the tile that
// owns its pixel; returns the tiles in creation order.
template <class Fn>
std::vector<std::unique_ptr<FilmTile>> render_tiles(const Film& film, int size, int per_pixel,
                                                    Fn fn) {
  Bounds2i sb = film.sample_bounds();
  std::vector<std::unique_ptr<FilmTile>> tiles;
  for (int ty = sb.min.y; ty < sb.max.y; ty += size)
    for (int tx = sb.min.x; tx < sb.max.x; tx += size) {
      Bounds2i tb{{tx, ty}, {std::min(tx + size, sb.max.x), std::min(ty + size, sb.max.y)}};
      auto tile = film.make_tile(tb);
      for (int y = tb.min.y; y < tb.max.y; ++y)
        for (int x = tb.min.x; x < tb.max.x; ++x) {
          // Seeded by pixel, so any tiling sees the same samples.
          Rng rng(uint64_t(y + 1000) * 4096 + uint64_t(x + 1000));
          for (int s = 0; s < per_pixel; ++s) {
            Vec2 p{x + rng.next_float(), y + rng.next_float()};
            tile->add_sample(p, fn(p), 1);
          }
        }
      tiles.push_back(std::move(tile));
    }
  return tiles;
}

TEST(Film, BoxFilterReturnsAConstantRadianceExactly) {
  Film film;
  std::string error;
  ASSERT_TRUE(film.build({37, 23}, kFull, box(), 1, kInfinity, 35, "x.exr", &error)) << error;
  Rgb L(0.1f, 1.7f, 123.456f);
  for (auto& t : render_tiles(film, 8, 7, [&](Vec2) { return L; })) film.merge_tile(*t);
  for (int y = 0; y < 23; ++y)
    for (int x = 0; x < 37; ++x) ASSERT_EQ(film.pixel({x, y}), L) << x << " " << y;
  EXPECT_EQ(film.pixel({37, 0}), Rgb(0));  // outside: 0
}

TEST(Film, GaussianFilterKeepsAConstantRadiance) {
  Film film;
  std::string error;
  float crop[4] = {0.2f, 0.8f, 0.1f, 0.9f};
  ASSERT_TRUE(film.build({40, 30}, crop, gaussian(), 1, kInfinity, 35, "x.exr", &error)) << error;
  Rgb L(0.25f, 2.f, 7.f);
  for (auto& t : render_tiles(film, 16, 4, [&](Vec2) { return L; })) film.merge_tile(*t);
  Bounds2i c = film.cropped_pixel_bounds();
  for (int y = c.min.y; y < c.max.y; ++y)
    for (int x = c.min.x; x < c.max.x; ++x)
      for (int k = 0; k < 3; ++k) ASSERT_NEAR(film.pixel({x, y})[k], L[k], 1e-6f * L[k]);
}

TEST(Film, ScaleAndMaxSampleLuminance) {
  Film film;
  std::string error;
  ASSERT_TRUE(film_from_text("scale",
                             "Film \"image\" \"integer xresolution\" 4 \"integer yresolution\" 2 "
                             "\"float scale\" 2 \"float maxsampleluminance\" 1",
                             FilmOptions(), &film, &error))
      << error;
  EXPECT_EQ(film.max_sample_luminance(), 1.f);
  auto tile = film.make_tile(film.sample_bounds());
  tile->add_sample({0.5f, 0.5f}, Rgb(4, 4, 4));         // luminance 4: scaled down to 1
  tile->add_sample({1.5f, 0.5f}, Rgb(0.5f, 0.25f, 0));  // luminance < 1: unchanged
  tile->add_sample({2.5f, 0.5f}, Rgb(3, 0, 0), 0.5f);   // luminance 0.638: kept, weight 0.5
  film.merge_tile(*tile);
  Rgb p0 = film.pixel({0, 0});
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(p0[k], 2 * 4 / Rgb(4, 4, 4).luminance(), 1e-6);
  EXPECT_EQ(film.pixel({1, 0}), Rgb(1, 0.5f, 0));
  EXPECT_EQ(film.pixel({2, 0}), Rgb(3, 0, 0));  // sample weight 0.5 / filter weight 1, times 2
  EXPECT_EQ(film.pixel({3, 0}), Rgb(0));        // no sample
}

// The film's sums are float (pbrt-v3's), rounded once per tile merged: another order or
// another cut of the same samples moves pixels by a few float roundings, never more.
TEST(Film, TileMergeOrderChangesPixelsOnlyInTheirLastBits) {
  Film one, forward, backward;
  std::string error;
  float crop[4] = {0.1f, 0.95f, 0, 0.7f};
  for (Film* f : {&one, &forward, &backward})
    ASSERT_TRUE(f->build({48, 40}, crop, gaussian(), 1.5f, kInfinity, 35, "x.exr", &error))
        << error;
  auto radiance = [](Vec2 p) {
    return Rgb(std::sin(p.x * 0.3f) + 1.5f, p.y * 0.1f, std::fmod(p.x * p.y, 3.f));
  };
  Bounds2i sb = one.sample_bounds();
  auto big = render_tiles(one, std::max(sb.width(), sb.height()), 5, radiance);
  ASSERT_EQ(big.size(), 1u);
  one.merge_tile(*big[0]);
  auto tiles = render_tiles(forward, 7, 5, radiance);
  ASSERT_GT(tiles.size(), 30u);
  for (auto& t : tiles) forward.merge_tile(*t);
  for (auto it = tiles.rbegin(); it != tiles.rend(); ++it) backward.merge_tile(**it);
  Bounds2i c = one.cropped_pixel_bounds();
  int covered = 0;
  for (int y = c.min.y; y < c.max.y; ++y)
    for (int x = c.min.x; x < c.max.x; ++x) {
      Rgb a = one.pixel({x, y});
      for (const Film* f : {&forward, &backward})
        for (int k = 0; k < 3; ++k)
          ASSERT_NEAR(f->pixel({x, y})[k], a[k], 8 * std::numeric_limits<float>::epsilon() * a[k])
              << x << " " << y;
      covered += a.r > 0;  // red is at least 0.5 everywhere
    }
  EXPECT_EQ(covered, c.area());
}

TEST(Film, AddSampleNeverWritesOutsideItsTile) {
  Film film;
  std::string error;
  ASSERT_TRUE(film.build({16, 16}, kFull, gaussian(), 1, kInfinity, 35, "x.exr", &error)) << error;
  auto tile = film.make_tile({{4, 4}, {8, 8}});
  // Radius 2 around samples in [4, 8): pixels [2, 10).
  expect_bounds(tile->pixel_bounds(), 2, 2, 10, 10);
  const float inf = kInfinity, nan = std::nanf("");
  for (Vec2 p : {Vec2{nan, 5}, Vec2{5, inf}, Vec2{-inf, -inf}, Vec2{1e30f, -1e30f}, Vec2{-3e9f, 5},
                 Vec2{100, 100}, Vec2{-100, 5}})
    tile->add_sample(p, Rgb(1));
  for (int y = 2; y < 10; ++y)
    for (int x = 2; x < 10; ++x) EXPECT_EQ(tile->sum({x, y}).weight, 0) << x << " " << y;
  tile->add_sample({5, 5}, Rgb(inf, nan, 1e38f));  // garbage values, but no crash
  tile->add_sample({0.6f, 9.9f}, Rgb(1));          // reaches into the tile's corner
  EXPECT_GT(tile->sum({2, 9}).weight, 0);
  // A tile of samples far outside the crop has no pixels and takes samples harmlessly.
  auto outside = film.make_tile({{100, 100}, {116, 116}});
  EXPECT_TRUE(outside->pixel_bounds().empty());
  outside->add_sample({105, 105}, Rgb(1));
  film.merge_tile(*outside);
  EXPECT_EQ(film.pixel({15, 15}), Rgb(0));
}

TEST(Film, SplatsAddAcrossThreadsTimesTheSplatScale) {
  Film film;
  std::string error;
  ASSERT_TRUE(film.build({8, 8}, kFull, box(), 2, 10, 35, "x.exr", &error)) << error;
  film.add_splat({3.5f, 4.25f}, Rgb(7));  // before enable_splats(): nothing
  film.enable_splats();
  film.keep_pass_splats_apart();
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (int i = 0; i < 1000; ++i) film.add_splat({3.5f, 4.25f}, Rgb(0.5f, 0.25f, 1), t & 1);
    });
  for (auto& t : threads) t.join();
  film.add_splat({3.5f, 4.25f}, Rgb(100, 100, 100));  // luminance 100 > 10: scaled to 10
  film.add_splat({-0.5f, 2}, Rgb(1));                 // outside: dropped
  film.add_splat({2, 2}, Rgb(-1, -1, -1));            // negative luminance: dropped
  film.set_splat_scale(0.001f);
  EXPECT_EQ(film.pixel({3, 4}), Rgb(0));  // pending until the pass commits them
  film.commit_splats();
  Rgb p = film.pixel({3, 4});
  EXPECT_NEAR(p.r, 2 * 0.001 * (2000 + 10), 1e-4);
  EXPECT_NEAR(p.b, 2 * 0.001 * (4000 + 10), 1e-4);
  EXPECT_EQ(film.pixel({2, 2}), Rgb(0));
  film.set_pixel({1, 1}, Rgb(3, 2, 1));
  EXPECT_EQ(film.pixel({1, 1}), Rgb(6, 4, 2));
  // An abandoned pass's splats never count.
  film.add_splat({5.5f, 5.5f}, Rgb(1));
  film.discard_splats();
  film.commit_splats();
  EXPECT_EQ(film.pixel({5, 5}), Rgb(0));
}

// Without passes apart (a one-pass render) splats count at once, in the same sums as a
// pass committed whole, and dropping the pass drops them all.
TEST(Film, OnePassSplatsGoStraightIntoTheImage) {
  Film apart, direct;
  std::string error;
  for (Film* f : {&apart, &direct}) {
    ASSERT_TRUE(f->build({8, 8}, kFull, box(), 1, kInfinity, 35, "x.exr", &error)) << error;
    f->enable_splats();
  }
  apart.keep_pass_splats_apart();
  for (Film* f : {&apart, &direct}) {
    std::vector<std::thread> threads;
    for (int t = 0; t < 2; ++t)
      threads.emplace_back([f, t] {
        for (int i = 0; i < 500; ++i) f->add_splat({2.5f, 6.5f}, Rgb(0.25f, 0.5f, 1), t);
      });
    for (auto& t : threads) t.join();
    f->set_splat_scale(0.01f);
  }
  EXPECT_EQ(direct.pixel({2, 6}), Rgb(2.5f, 5, 10));  // 1000 splats at once
  EXPECT_EQ(apart.pixel({2, 6}), Rgb(0));
  apart.commit_splats();
  direct.commit_splats();  // nothing pending: no change
  for (int h = 0; h < 2; ++h) EXPECT_EQ(direct.half_splats(h), apart.half_splats(h)) << h;
  EXPECT_TRUE(direct.pending_splats().empty());
  direct.discard_splats();
  EXPECT_EQ(direct.pixel({2, 6}), Rgb(0));
}

// The two halves hold disjoint samples and add up to the image; each pair of samples
// (2i, 2i + 1) of a pixel is split between them.
TEST(Film, HalvesSplitEachPairAndAddUpToTheImage) {
  int balance[2] = {0, 0};
  for (int64_t i = 0; i < 64; i += 2) {
    const int a = sample_half({3, 7}, i), b = sample_half({3, 7}, i + 1);
    EXPECT_NE(a, b) << i;
    ++balance[a];
  }
  EXPECT_GT(balance[0], 4);  // random per pair, not always the same way
  EXPECT_GT(balance[1], 4);
  Film film;
  std::string error;
  ASSERT_TRUE(film.build({4, 4}, kFull, box(), 1, kInfinity, 35, "x.exr", &error)) << error;
  std::unique_ptr<FilmTile> tile = film.make_tile({{0, 0}, {4, 4}});
  tile->add_sample({1.5f, 1.5f}, Rgb(1, 2, 3), 1, 0);
  tile->add_sample({1.5f, 1.5f}, Rgb(3, 2, 1), 1, 1);
  film.merge_tile(*tile);
  film.set_sample_count(2);
  EXPECT_EQ(film.half_pixel({1, 1}, 0), Rgb(1, 2, 3));
  EXPECT_EQ(film.half_pixel({1, 1}, 1), Rgb(3, 2, 1));
  EXPECT_EQ(film.pixel({1, 1}), Rgb(2, 2, 2));
}

TEST(Film, WritesTheCropInsideTheFullFrame) {
  Film film;
  std::string error;
  float crop[4] = {0.25f, 0.75f, 0.5f, 1};
  ASSERT_TRUE(film.build({20, 10}, crop, box(), 1, kInfinity, 35, "x.exr", &error)) << error;
  for (auto& t : render_tiles(film, 5, 2, [](Vec2 p) { return Rgb(std::floor(p.x) * 1000, 1, 0); }))
    film.merge_tile(*t);
  std::string dir = testing_support::scratch_dir("film_write");
  ASSERT_TRUE(film.write(dir + "/crop.exr", &error)) << error;
  ASSERT_TRUE(film.write(dir + "/crop.png", &error)) << error;
  ImageRgb back;
  ASSERT_TRUE(read_exr(dir + "/crop.exr", &back, &error)) << error;
  expect_bounds(back.data_window, 5, 5, 15, 10);
  expect_bounds(back.display_window, 0, 0, 20, 10);
  EXPECT_EQ(back.rgb[0], 5000.f);
  EXPECT_EQ(back.rgb[3 * (back.width() * back.height() - 1)],
            14000.f);  // float32, above half's max
  EXPECT_FALSE(film.write(dir + "/crop.tif", &error));
  EXPECT_NE(error.find(".tif"), std::string::npos) << error;
  EXPECT_FALSE(std::filesystem::exists(dir + "/crop.tif"));
}

}  // namespace
}  // namespace rt
