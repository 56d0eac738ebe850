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
// Sums are kept in double: the converged value does not depend on how many
// samples a pixel got or how tiles split them (a constant radiance comes back
// exactly). add_splat() (light tracing, bdpt) is thread-safe.
//
// pixel(): weighted sum / weight sum (0 where the weight is 0) clamped at 0
// (negative filter lobes), plus splats times the splat scale, times the film
// "scale" — pbrt-v3's Film::WriteImage order. write() writes the cropped
// pixels by extension (image_io.h), the data window inside the display window
// of the full resolution.
#pragma once

#include <atomic>
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

// Per-pixel accumulators (double: see the header comment).
struct FilmPixelSum {
  double rgb[3] = {0, 0, 0};
  double weight = 0;
};

class FilmTile {
 public:
  static constexpr int kTableSize = 16;

  Bounds2i pixel_bounds() const { return pixel_bounds_; }
  // Adds L, weighted by the filter centred at p_film, to every pixel of this
  // tile the filter radius covers; L is scaled down first when its luminance
  // exceeds maxsampleluminance. Never touches memory outside the tile, for any
  // input (non-finite positions are ignored).
  void add_sample(Vec2 p_film, Rgb L, float sample_weight = 1);
  const FilmPixelSum& sum(Point2i p) const;  // p inside pixel_bounds()

 private:
  friend class Film;
  FilmTile(const Bounds2i& pixel_bounds, Vec2 radius, const float* table, float max_luminance);

  Bounds2i pixel_bounds_;
  Vec2 radius_, inv_radius_;
  const float* table_;  // the film's, kTableSize^2 (the film outlives its tiles)
  float max_luminance_;
  std::vector<FilmPixelSum> pixels_;
};

class Film {
 public:
  static constexpr int kTableSize = FilmTile::kTableSize;

  bool build(const pbrta::SceneArchive& archive, const FilmOptions& options, std::string* error);
  // The same without an archive (tests, tools): a film "image" with these values.
  bool build(Point2i resolution, const float crop[4], const Filter& filter, float scale,
             float max_sample_luminance, float diagonal_mm, const std::string& filename,
             std::string* error);

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

  // Light-tracing contributions at p_film (pbrt-v3's AddSplat; thread-safe).
  void add_splat(Vec2 p_film, Rgb v);
  void set_splat_scale(float s) { splat_scale_ = s; }
  // Replaces a pixel's value outright (sppm writes its own estimate).
  void set_pixel(Point2i p, Rgb v);

  Rgb pixel(Point2i p) const;  // final value, see the header comment; 0 outside the crop
  ImageRgb image() const;      // the cropped pixels with their windows
  bool write(const std::string& path, std::string* error) const;  // by extension

 private:
  size_t index(Point2i p) const {
    return size_t(p.y - cropped_.min.y) * size_t(cropped_.width()) + size_t(p.x - cropped_.min.x);
  }

  Point2i full_resolution_;
  Bounds2i cropped_;
  Filter filter_;
  float table_[kTableSize * kTableSize] = {};
  float scale_ = 1, max_luminance_ = kInfinity, diagonal_ = 0.035f, splat_scale_ = 1;
  std::string filename_;
  std::vector<FilmPixelSum> pixels_;
  std::unique_ptr<std::atomic<double>[]> splats_;  // 3 per pixel
};

}  // namespace rt
