// runtime/film/film.h — pbrt-v3's ImageFilm: crop, filtered sample splatting, output.
//
// Film::build reads the scene's film ("image") and filter entities with the
// command-line overrides (resolution divisor, crop window) and fixes the
// pixel rectangles exactly as pbrt-v3 does, in float arithmetic (so e.g. crop
// [.3 .7 .4 .7] of 700x1000 is 279x300 pixels, as pbrt-v3 writes it).
//
// Rendering: each worker asks make_tile() for the FilmTile of the sample
// rectangle it renders, adds filter-weighted samples to it (pbrt-v3's
// FilmTile::AddSample, filter read from a 16x16 table over one quadrant, as
// pbrt-v3 does, so weights match its images exactly), and the renderer
// merges finished tiles with merge_tile() in a fixed order (not thread-safe).
// A tile adds its samples in double and the film keeps float sums, as pbrt-v3
// keeps them (32 bytes a pixel, both halves): each pixel's sum is rounded once
// per tile merged, so tiles of one pass merged in another order, or cut another
// way, change pixels in their last bits only, and the renderer's fixed order
// keeps every image reproducible. add_splat() (light tracing, bdpt) is
// thread-safe.
//
// Two halves: every sum is kept twice, once for each half of a pixel's samples
// (each sample goes to one, at no extra cost), so the render's own error can be
// estimated from two independent images (error_estimate.h) and the image is their
// sum. sample_half() splits each pair of samples (2i, 2i + 1) between the halves, at
// random per pixel and pair: by parity alone, low-discrepancy samplers would put the
// even samples in one part of the pixel and the odd in another, and the halves would
// differ at every edge however many samples they had. Splats (enable_splats() first)
// go straight to the image in a one-pass render; in passes, to a pending buffer that
// commit_splats() adds to the image at the end of a pass, or discard_splats() drops when a
// pass is abandoned.
//
// pixel(): weighted sum / weight sum (0 where the weight is 0) clamped at 0
// (negative filter lobes), plus splats times the splat scale, times the film
// "scale" — pbrt-v3's Film::WriteImage order. write() writes the cropped
// pixels by extension (image_io.h), the data window inside the display window
// of the full resolution.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "format/scene_archive.h"
#include "runtime/core/rgb.h"
#include "runtime/core/vec.h"
#include "runtime/film/filter.h"
#include "runtime/film/image_io.h"

namespace rt {

// Command-line overrides. resdiv divides xresolution/yresolution (integer
// division) and nothing else; crop (x0 x1 y0 y1, fractions) replaces the
// scene's cropwindow when has_crop.
struct FilmOptions {
  int resdiv = 1;
  bool has_crop = false;
  float crop[4] = {0, 1, 0, 1};
};

// The half (0 or 1) that sample `index` of `pixel` goes to; the two samples of a pair
// (2i, 2i + 1) go to different halves.
inline int sample_half(Point2i pixel, int64_t index) {
  uint64_t h = (uint64_t(uint32_t(pixel.x)) << 32 | uint32_t(pixel.y)) ^
               (uint64_t(index >> 1) * 0x9e3779b97f4a7c15ull);
  h ^= h >> 31;
  h *= 0xbf58476d1ce4e5b9ull;
  h ^= h >> 29;
  return int((h ^ uint64_t(index)) & 1);
}

// A tile's per-pixel accumulators, and a render state's (render_state.h).
struct FilmPixelSum {
  double rgb[3] = {0, 0, 0};
  double weight = 0;
};
// The film's (see the header comment).
struct FilmPixel {
  float rgb[3] = {0, 0, 0};
  float weight = 0;
};

class FilmTile {
 public:
  static constexpr int kTableSize = 16;

  Bounds2i pixel_bounds() const { return pixel_bounds_; }
  // Adds L, weighted by the filter centred at p_film, to every pixel of this
  // tile the filter radius covers; L is scaled down first when its luminance
  // exceeds maxsampleluminance. Never touches memory outside the tile, for any
  // input (non-finite positions are ignored).
  // half: sample_half() of the sample.
  void add_sample(Vec2 p_film, Rgb L, float sample_weight = 1, int half = 0);
  FilmPixelSum sum(Point2i p) const;  // both halves; p inside pixel_bounds()
  // One half's sums, pixel_bounds() in row order (to send a tile to another process).
  std::vector<FilmPixelSum>& half_sums(int half) { return pixels_[half & 1]; }
  const std::vector<FilmPixelSum>& half_sums(int half) const { return pixels_[half & 1]; }

 private:
  friend class Film;
  FilmTile(const Bounds2i& pixel_bounds, Vec2 radius, const float* table, float max_luminance);

  Bounds2i pixel_bounds_;
  Vec2 radius_, inv_radius_;
  const float* table_;  // the film's, kTableSize^2 (the film outlives its tiles)
  float max_luminance_;
  std::vector<FilmPixelSum> pixels_[2];  // even and odd samples
};

class Film {
 public:
  static constexpr int kTableSize = FilmTile::kTableSize;

  bool build(const pbrta::SceneArchive& archive, const FilmOptions& options, std::string* error);
  // The same without an archive (tests, tools): a film "image" with these values.
  bool build(Point2i resolution, const float crop[4], const Filter& filter, float scale,
             float max_sample_luminance, float diagonal_mm, const std::string& filename,
             std::string* error);

  // Only the windows and scale, to hold sums made elsewhere (render_state.h); no filter.
  void build_for_sums(Point2i full_resolution, const Bounds2i& cropped, float scale);

  Point2i full_resolution() const { return full_resolution_; }
  Bounds2i cropped_pixel_bounds() const { return cropped_; }
  Bounds2i sample_bounds() const;               // pbrt-v3's Film::GetSampleBounds
  float diagonal() const { return diagonal_; }  // metres
  float scale() const { return scale_; }
  float max_sample_luminance() const { return max_luminance_; }
  const std::string& filename() const { return filename_; }
  const Filter& filter() const { return filter_; }

  // pbrt-v3's GetFilmTile: the pixels that samples in tile_sample_bounds can
  // reach through the filter, inside the crop.
  std::unique_ptr<FilmTile> make_tile(const Bounds2i& tile_sample_bounds) const;
  void merge_tile(const FilmTile& tile);  // not thread-safe

  // Light-tracing contributions at p_film (pbrt-v3's AddSplat; thread-safe), after
  // enable_splats() (a no-op before). By default they go straight into the image: for a
  // render that is one pass, kept or dropped whole (discard_splats() then clears them all).
  // After keep_pass_splats_apart() (before the first splat; not thread-safe) they wait in a
  // pending buffer, 24 bytes a pixel more, until the pass under way is committed or dropped.
  void enable_splats();
  void keep_pass_splats_apart();
  bool has_splats() const { return splats_enabled_; }
  void add_splat(Vec2 p_film, Rgb v, int half = 0);
  void commit_splats();   // pending splats join the image (not thread-safe)
  void discard_splats();  // pending splats are dropped (an abandoned pass)
  // The pending splats as plain values (2 halves x 3 per pixel; empty without splats or
  // passes apart) and back (not thread-safe): to add up the splats of processes rendering
  // one pass.
  std::vector<double> pending_splats() const;
  void set_pending_splats(const std::vector<double>& values);
  void set_splat_scale(float s) { splat_scale_ = s; }
  // Samples per pixel rendered so far, for the half images' splat scales: half 0
  // holds about ceil(n / 2) of them, half 1 floor(n / 2) (exactly, for even n).
  void set_sample_count(int64_t n) { set_half_counts((n + 1) / 2, n / 2); }
  // The same for a merge of several renders: each half's own count.
  void set_half_counts(int64_t even, int64_t odd) {
    half_counts_[0] = even;
    half_counts_[1] = odd;
  }
  int64_t sample_count() const { return half_counts_[0] + half_counts_[1]; }
  int64_t half_count(int half) const { return half_counts_[half & 1]; }
  // Replaces a pixel's value outright (sppm writes its own estimate).
  void set_pixel(Point2i p, Rgb v);

  Rgb pixel(Point2i p) const;  // final value, see the header comment; 0 outside the crop
  // The image of one half's samples alone, as pixel() computes it.
  Rgb half_pixel(Point2i p, int half) const;
  // The raw sums of one half (render states, merging): pixel sums and committed splats
  // (3 per pixel, all zero without splats), in cropped-pixel row order.
  std::vector<FilmPixel>& half_sums(int half) { return pixels_[half]; }
  const std::vector<FilmPixel>& half_sums(int half) const { return pixels_[half]; }
  std::vector<float>& half_splats(int half) { return splats_[half]; }
  const std::vector<float>& half_splats(int half) const { return splats_[half]; }
  ImageRgb image() const;  // the cropped pixels with their windows
  bool write(const std::string& path, std::string* error) const;  // by extension

 private:
  void clear_sums();  // for the windows set: zero sums, no splats, no samples
  size_t index(Point2i p) const {
    return size_t(p.y - cropped_.min.y) * size_t(cropped_.width()) + size_t(p.x - cropped_.min.x);
  }

  Point2i full_resolution_;
  Bounds2i cropped_;
  Filter filter_;
  float table_[kTableSize * kTableSize] = {};
  float scale_ = 1, max_luminance_ = kInfinity, diagonal_ = 0.035f, splat_scale_ = 1;
  std::string filename_;
  int64_t half_counts_[2] = {0, 0};
  std::vector<FilmPixel> pixels_[2];  // even and odd samples
  // Light-tracing splats, 3 per pixel (empty without splats), in float as pbrt-v3 keeps its
  // splats: committed (a pass's sums added in double, then rounded) and, with passes apart,
  // the pass under way's, which an abandoned pass drops. 24 bytes a pixel, 48 with passes
  // apart; in double they were 96.
  std::vector<float> splats_[2];
  bool splats_enabled_ = false;
  std::unique_ptr<std::atomic<float>[]> pending_;  // 2 halves x 3 per pixel, or none
};

}  // namespace rt
