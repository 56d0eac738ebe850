// runtime/texture/mipmap.h — pbrt-v3's MIPMap lookups over an archived image pyramid.
//
// pbrtc has already built the pyramid (resampling to powers of two, box
// filtering each level; format/ARCHIVE.md, ImageRecord); this class only
// reads it: texels with the image's wrap mode, bilinear ("triangle")
// lookups, trilinear lookups with a filter width, and pbrt-v3's EWA with its
// Gaussian weight table. Results match pbrt-v3's MIPMap<RGBSpectrum> and
// MIPMap<Float> operation for operation.
//
// Orientation: flip_rows is true for imagemap textures (pbrt-v3 flips them,
// so texel (s, t) of a level h rows high is stored row h - 1 - t) and false
// for light maps (texel (s, t) is stored row t).
//
// Formats: f32 texels are used in place from the archive; f16 and unorm8
// (pbrtc --texture-precision) levels are widened to f32 once, at init, as
// format/texel_format.h decodes them (in parallel for large levels), so
// lookups cost the same in every format. Channels: 1 or 3. texel() of a
// 1-channel image is grey; texel_float() of a 3-channel image is its
// luminance (pbrt-v3 never does either: pbrtc stores float imagemaps with one
// channel and spectrum ones with three).
//
// After init the object is read-only and may be shared between threads;
// copies share the widened texels.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "format/scene_archive.h"
#include "runtime/core/rgb.h"
#include "runtime/core/vec.h"

namespace rt {

// IEEE half to float, exactly (subnormals, infinities and NaNs included): f16 texels.
// The same as pbrta::half_to_float (format/texel_format.h).
float half_to_float(uint16_t h);

enum class ImageWrap : uint8_t { kRepeat = 0, kBlack = 1, kClamp = 2 };

class MipMap {
 public:
  // Views image `image` of the archive (which must outlive this object).
  // Fails with a message naming the image when it is malformed.
  bool init(const pbrta::SceneArchive& archive, uint32_t image, bool flip_rows, std::string* error);

  int width() const { return levels_[0].w; }
  int height() const { return levels_[0].h; }
  int levels() const { return num_levels_; }
  int channels() const { return channels_; }
  ImageWrap wrap() const { return wrap_; }

  // A level's texels, channels() floats each, rows top to bottom (as stored): in the
  // archive itself when it holds f32 texels (viewed(): they live as long as the archive),
  // else widened copies owned by this object and its copies.
  const float* level_texels(int level) const { return levels_[level].data; }
  bool viewed() const { return !widened_; }

  // Texel (s, t) of a level, (s, t) outside the level resolved by the wrap mode.
  Rgb texel(int level, int s, int t) const;
  float texel_float(int level, int s, int t) const;

  // pbrt-v3's MIPMap::triangle: bilinear interpolation of one level at st in [0,1]^2.
  Rgb bilerp(int level, Vec2 st) const;
  float bilerp_float(int level, Vec2 st) const;

  // pbrt-v3's MIPMap::Lookup(st, width): trilinear between the two levels whose
  // texel spacing brackets width (width 0: the finest level, bilinear).
  Rgb lookup_trilinear(Vec2 st, float width = 0) const;
  float lookup_trilinear_float(Vec2 st, float width = 0) const;
  // A hint: starts loading the finest level's texels a width-0 lookup at st reads.
  void prefetch_bilinear(Vec2 st) const;

  // pbrt-v3's MIPMap::Lookup(st, dst0, dst1) without doTrilinear: EWA over the
  // ellipse with axes dst0, dst1, eccentricity clamped to max_anisotropy,
  // interpolated between two levels. A zero-length minor axis is bilinear.
  Rgb lookup_ewa(Vec2 st, Vec2 dst0, Vec2 dst1, float max_anisotropy) const;
  float lookup_ewa_float(Vec2 st, Vec2 dst0, Vec2 dst1, float max_anisotropy) const;

 private:
  struct Level {
    const float* data = nullptr;  // channels_ floats per texel, rows top to bottom
    int w = 0, h = 0;
  };
  template <class T>
  T fetch(int level, int s, int t) const;
  // fetch() for a texel known to lie inside the level: no wrap (whose integer modulo per
  // texel cost EWA lookups more than their arithmetic).
  template <class T>
  T fetch_inside(int level, int s, int t) const;
  // The first float of texel (s, t) of the level, which must hold it.
  const float* texel_data(int level, int s, int t) const {
    const Level& l = levels_[level];
    const int row = flip_rows_ ? l.h - 1 - t : t;
    return l.data + (size_t(row) * l.w + s) * channels_;
  }
  // Whether texels [s0, s1] x [t0, t1] lie inside the level once moved by whole periods of a
  // repeating image (textures tiled with uscale 15 read far outside [0, 1]); if so, the move
  // in *shift_s, *shift_t (0 for clamp and black).
  bool inside(int level, int s0, int t0, int s1, int t1, int* shift_s, int* shift_t) const;
  template <class T>
  T triangle(int level, Vec2 st) const;
  template <class T>
  T trilinear(Vec2 st, float width) const;
  template <class T>
  T ewa(int level, Vec2 st, Vec2 dst0, Vec2 dst1) const;
  template <class T>
  T ewa_lookup(Vec2 st, Vec2 dst0, Vec2 dst1, float max_anisotropy) const;

  Level levels_[32];
  int num_levels_ = 0;
  int channels_ = 0;
  ImageWrap wrap_ = ImageWrap::kRepeat;
  bool flip_rows_ = false;
  std::shared_ptr<std::vector<float>> widened_;  // f16 / unorm8 texels as f32
};

}  // namespace rt
