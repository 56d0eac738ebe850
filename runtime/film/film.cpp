// runtime/film/film.cpp — the film's rectangles, tiles, merging and output.
#include "runtime/film/film.h"

#include <cmath>
#include <cstdio>

#include "runtime/core/atomic_add.h"

namespace rt {
namespace {

std::string crop_text(const float c[4]) {
  char buf[128];
  std::snprintf(buf, sizeof(buf), "[%g %g %g %g]", c[0], c[1], c[2], c[3]);
  return buf;
}

}  // namespace

bool Film::build(const pbrta::SceneArchive& archive, const FilmOptions& options,
                 std::string* error) {
  uint32_t e = archive.scene().film;
  if (e >= archive.entities.size) {
    *error = "the archive has no film entity";
    return false;
  }
  if (archive.type_name(e) != "image") {
    *error = "not supported yet: film \"" + std::string(archive.type_name(e)) + "\" (" +
             archive.where(e) + ")";
    return false;
  }
  if (options.resdiv < 1) {
    *error = "resolution divisor must be at least 1, not " + std::to_string(options.resdiv);
    return false;
  }
  Filter filter;
  if (!make_filter(archive, &filter, error)) return false;

  Point2i res{archive.get_int(e, "xresolution", 1280) / options.resdiv,
              archive.get_int(e, "yresolution", 720) / options.resdiv};
  float crop[4] = {0, 1, 0, 1};
  if (options.has_crop) {
    for (int i = 0; i < 4; ++i) crop[i] = options.crop[i];
  } else if (const pbrta::ValueRecord* v = archive.value(e, "cropwindow"); v && v->count == 4) {
    for (int i = 0; i < 4; ++i) crop[i] = archive.floats(*v)[i];
  }
  // Computed defaults may be stored with count 0: pbrt.exr, and no clamping.
  std::string filename(archive.get_string(e, "filename"));
  if (filename.empty()) filename = "pbrt.exr";
  const pbrta::ValueRecord* ml = archive.value(e, "maxsampleluminance");
  float max_luminance = ml && ml->count ? archive.floats(*ml)[0] : kInfinity;
  if (!build(res, crop, filter, archive.get_float(e, "scale", 1), max_luminance,
             archive.get_float(e, "diagonal", 35), filename, error)) {
    *error += " (" + archive.where(e) + ")";
    return false;
  }
  return true;
}

bool Film::build(Point2i resolution, const float crop[4], const Filter& filter, float scale,
                 float max_sample_luminance, float diagonal_mm, const std::string& filename,
                 std::string* error) {
  if (resolution.x < 1 || resolution.y < 1) {
    *error = "film resolution " + std::to_string(resolution.x) + "x" +
             std::to_string(resolution.y) + " has no pixels";
    return false;
  }
  if (!(filter.radius.x > 0 && filter.radius.y > 0)) {
    *error = "filter radius must be positive";
    return false;
  }
  for (int i = 0; i < 4; ++i)
    if (std::isnan(crop[i])) {
      *error = "crop window " + crop_text(crop) + " is not a number";
      return false;
    }
  // pbrt-v3: each axis's pair may come in either order and is clamped to [0, 1].
  float x0 = clamp(std::min(crop[0], crop[1]), 0.f, 1.f);
  float x1 = clamp(std::max(crop[0], crop[1]), 0.f, 1.f);
  float y0 = clamp(std::min(crop[2], crop[3]), 0.f, 1.f);
  float y1 = clamp(std::max(crop[2], crop[3]), 0.f, 1.f);
  // Float products, as pbrt-v3 computes them: 700 * 0.3f rounds up to
  // 210.00002f, so that crop starts at pixel 211.
  float fx = float(resolution.x), fy = float(resolution.y);
  Bounds2i cropped{{int(std::ceil(fx * x0)), int(std::ceil(fy * y0))},
                   {int(std::ceil(fx * x1)), int(std::ceil(fy * y1))}};
  if (cropped.empty()) {
    *error = "crop window " + crop_text(crop) + " selects no pixel of the " +
             std::to_string(resolution.x) + "x" + std::to_string(resolution.y) + " film";
    return false;
  }

  full_resolution_ = resolution;
  cropped_ = cropped;
  filter_ = filter;
  scale_ = scale;
  max_luminance_ = max_sample_luminance;
  diagonal_ = diagonal_mm * 0.001f;
  splat_scale_ = 1;
  filename_ = filename;
  // pbrt-v3's filter table: one quadrant (the filters are symmetric), values
  // at the centres of a 16x16 grid over [0, radius]^2.
  for (int y = 0; y < kTableSize; ++y)
    for (int x = 0; x < kTableSize; ++x)
      table_[y * kTableSize + x] = filter_.evaluate(
          {(x + 0.5f) * filter_.radius.x / kTableSize, (y + 0.5f) * filter_.radius.y / kTableSize});
  clear_sums();
  return true;
}

void Film::build_for_sums(Point2i full_resolution, const Bounds2i& cropped, float scale) {
  full_resolution_ = full_resolution;
  cropped_ = cropped;
  scale_ = scale;
  splat_scale_ = 1;
  clear_sums();
}

void Film::clear_sums() {
  for (auto& h : pixels_) h.assign(size_t(cropped_.area()), FilmPixel());
  for (auto& h : splats_) h.clear();
  splats_enabled_ = false;
  pending_.reset();
  half_counts_[0] = half_counts_[1] = 0;
}

Bounds2i Film::sample_bounds() const {
  // Samples up to a filter radius outside the crop still reach its pixels;
  // pixel centres are at half-integers.
  return {{int(std::floor(float(cropped_.min.x) + 0.5f - filter_.radius.x)),
           int(std::floor(float(cropped_.min.y) + 0.5f - filter_.radius.y))},
          {int(std::ceil(float(cropped_.max.x) - 0.5f + filter_.radius.x)),
           int(std::ceil(float(cropped_.max.y) - 0.5f + filter_.radius.y))}};
}

std::unique_ptr<FilmTile> Film::make_tile(const Bounds2i& b) const {
  Point2i p0{int(std::ceil(float(b.min.x) - 0.5f - filter_.radius.x)),
             int(std::ceil(float(b.min.y) - 0.5f - filter_.radius.y))};
  Point2i p1{int(std::floor(float(b.max.x) - 0.5f + filter_.radius.x)) + 1,
             int(std::floor(float(b.max.y) - 0.5f + filter_.radius.y)) + 1};
  Bounds2i pixels = intersect({p0, p1}, cropped_);
  return std::unique_ptr<FilmTile>(new FilmTile(pixels, filter_.radius, table_, max_luminance_));
}

void Film::merge_tile(const FilmTile& tile) {
  Bounds2i b = intersect(tile.pixel_bounds(), cropped_);
  const Bounds2i& tb = tile.pixel_bounds();
  for (int h = 0; h < 2; ++h)
    for (int y = b.min.y; y < b.max.y; ++y)
      for (int x = b.min.x; x < b.max.x; ++x) {
        const FilmPixelSum& s =
            tile.pixels_[h][size_t(y - tb.min.y) * size_t(tb.width()) + size_t(x - tb.min.x)];
        FilmPixel& d = pixels_[h][index({x, y})];
        for (int c = 0; c < 3; ++c) d.rgb[c] = float(double(d.rgb[c]) + s.rgb[c]);
        d.weight = float(double(d.weight) + s.weight);
      }
}

void Film::enable_splats() {
  if (splats_enabled_) return;
  const size_t n = 3 * size_t(cropped_.area());
  for (auto& h : splats_) h.assign(n, 0.f);
  splats_enabled_ = true;
}

void Film::keep_pass_splats_apart() {
  if (!splats_enabled_ || pending_) return;
  const size_t n = 2 * splats_[0].size();
  pending_.reset(new std::atomic<float>[n]);
  for (size_t i = 0; i < n; ++i) pending_[i].store(0, std::memory_order_relaxed);
}

void Film::add_splat(Vec2 p_film, Rgb v, int half) {
  if (!splats_enabled_) return;
  if (!v.is_finite() || !std::isfinite(p_film.x) || !std::isfinite(p_film.y)) return;
  float lum = v.luminance();
  if (lum < 0) return;  // as pbrt-v3: a negative-luminance splat is dropped
  float fx = std::floor(p_film.x), fy = std::floor(p_film.y);
  if (!(fx >= float(cropped_.min.x) && fx < float(cropped_.max.x) && fy >= float(cropped_.min.y) &&
        fy < float(cropped_.max.y)))
    return;
  if (lum > max_luminance_) v *= max_luminance_ / lum;
  const size_t i = 3 * index({int(fx), int(fy)});
  if (pending_) {
    const size_t at = size_t(half & 1) * splats_[0].size() + i;
    for (int c = 0; c < 3; ++c) atomic_add(&pending_[at + c], v[c]);
  } else {
    for (int c = 0; c < 3; ++c) atomic_add(&splats_[half & 1][i + c], v[c]);
  }
}

void Film::commit_splats() {
  if (!splats_enabled_ || !pending_) return;
  const size_t n = splats_[0].size();
  for (int h = 0; h < 2; ++h)
    for (size_t i = 0; i < n; ++i) {
      std::atomic<float>& p = pending_[size_t(h) * n + i];
      splats_[h][i] = float(double(splats_[h][i]) + double(p.load(std::memory_order_relaxed)));
      p.store(0, std::memory_order_relaxed);
    }
}

void Film::discard_splats() {
  if (!splats_enabled_) return;
  if (!pending_) {  // the one pass there is: no splats at all
    for (auto& h : splats_) std::fill(h.begin(), h.end(), 0.f);
    return;
  }
  for (size_t i = 0; i < 2 * splats_[0].size(); ++i)
    pending_[i].store(0, std::memory_order_relaxed);
}

std::vector<double> Film::pending_splats() const {
  std::vector<double> out;
  if (!splats_enabled_ || !pending_) return out;
  out.resize(2 * splats_[0].size());
  for (size_t i = 0; i < out.size(); ++i)
    out[i] = double(pending_[i].load(std::memory_order_relaxed));
  return out;
}

void Film::set_pending_splats(const std::vector<double>& values) {
  if (!splats_enabled_ || !pending_ || values.size() != 2 * splats_[0].size()) return;
  for (size_t i = 0; i < values.size(); ++i)
    pending_[i].store(float(values[i]), std::memory_order_relaxed);
}

void Film::set_pixel(Point2i p, Rgb v) {
  if (!cropped_.inside(p)) return;
  const size_t i = index(p);
  for (int h = 0; h < 2; ++h) {
    FilmPixel& d = pixels_[h][i];
    for (int c = 0; c < 3; ++c) d.rgb[c] = h == 0 ? v[c] : 0;
    d.weight = h == 0 ? 1 : 0;
    if (splats_enabled_)
      for (int c = 0; c < 3; ++c) splats_[h][3 * i + c] = 0;
  }
}

Rgb Film::pixel(Point2i p) const {
  if (!cropped_.inside(p)) return Rgb(0);
  const size_t i = index(p);
  const FilmPixel &e = pixels_[0][i], &o = pixels_[1][i];
  const double weight = double(e.weight) + double(o.weight);
  Rgb out;
  for (int c = 0; c < 3; ++c) {
    double v = weight != 0 ? std::max(0.0, (double(e.rgb[c]) + double(o.rgb[c])) / weight) : 0.0;
    if (splats_enabled_)
      v += double(splat_scale_) * (double(splats_[0][3 * i + c]) + double(splats_[1][3 * i + c]));
    out[c] = float(v * double(scale_));
  }
  return out;
}

Rgb Film::half_pixel(Point2i p, int half) const {
  if (!cropped_.inside(p)) return Rgb(0);
  const size_t i = index(p);
  const FilmPixel& s = pixels_[half & 1][i];
  // The half's splats over its own sample count: splat_scale is for all of them.
  const int64_t n_half = half_counts_[half & 1];
  const double splat_scale =
      n_half > 0 ? double(splat_scale_) * double(sample_count()) / double(n_half) : 0.0;
  Rgb out;
  for (int c = 0; c < 3; ++c) {
    double v = s.weight != 0 ? std::max(0.0, double(s.rgb[c]) / double(s.weight)) : 0.0;
    if (splats_enabled_) v += splat_scale * splats_[half & 1][3 * i + c];
    out[c] = float(v * double(scale_));
  }
  return out;
}

ImageRgb Film::image() const {
  ImageRgb img;
  img.data_window = cropped_;
  img.display_window = {{0, 0}, full_resolution_};
  img.rgb.resize(size_t(cropped_.area()) * 3);
  size_t k = 0;
  for (int y = cropped_.min.y; y < cropped_.max.y; ++y)
    for (int x = cropped_.min.x; x < cropped_.max.x; ++x) {
      Rgb v = pixel({x, y});
      img.rgb[k++] = v.r;
      img.rgb[k++] = v.g;
      img.rgb[k++] = v.b;
    }
  return img;
}

bool Film::write(const std::string& path, std::string* error) const {
  return write_image(path, image(), error);
}

}  // namespace rt
