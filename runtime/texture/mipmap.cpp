// runtime/texture/mipmap.cpp — see mipmap.h.
#include "runtime/texture/mipmap.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include "format/texel_format.h"

namespace rt {

namespace {

// pbrt-v3's EWA weight table: a Gaussian exp(-alpha r^2), shifted to reach 0
// at r = 1, sampled at 128 values of r^2.
constexpr int kWeightLutSize = 128;

struct WeightLut {
  float w[kWeightLutSize];
  WeightLut() {
    const float alpha = 2;
    for (int i = 0; i < kWeightLutSize; ++i) {
      float r2 = float(i) / float(kWeightLutSize - 1);
      w[i] = std::exp(-alpha * r2) - std::exp(-alpha);
    }
  }
};
const WeightLut kWeights;

// pbrt-v3's Log2 (natural log times 1/ln 2), so level choices round as pbrt-v3's do.
inline float log2f_pbrt(float x) {
  return std::log(x) * 1.442695040888963387004650940071f;
}

// Remainder with the sign of b (pbrt-v3's Mod), for repeat wrapping.
inline int mod(int a, int b) {
  int r = a - (a / b) * b;
  return r < 0 ? r + b : r;
}

template <class T>
T from_texel(const float* p, int channels);
template <>
inline float from_texel<float>(const float* p, int channels) {
  return channels == 1 ? p[0] : Rgb(p[0], p[1], p[2]).luminance();
}
template <>
inline Rgb from_texel<Rgb>(const float* p, int channels) {
  return channels == 1 ? Rgb(p[0]) : Rgb(p[0], p[1], p[2]);
}

// A level's stored texels to floats; large levels in parallel (a 4k x 4k RGB map is 50 M
// values).
void widen(uint32_t format, const uint8_t* in, uint64_t count, float* out) {
  const uint64_t grain = uint64_t(1) << 16;
  if (count < 4 * grain) {
    pbrta::decode_texels(format, in, size_t(count), out);
    return;
  }
  const uint64_t bytes_per = pbrta::texel_bytes(format);
  tbb::parallel_for(
      tbb::blocked_range<uint64_t>(0, count, grain), [&](const tbb::blocked_range<uint64_t>& r) {
        pbrta::decode_texels(format, in + r.begin() * bytes_per, size_t(r.size()), out + r.begin());
      });
}

}  // namespace

float half_to_float(uint16_t h) {
  return pbrta::half_to_float(h);
}

bool MipMap::init(const pbrta::SceneArchive& archive, uint32_t image, bool flip_rows,
                  std::string* error) {
  if (image >= archive.images.size) {
    *error = "image " + std::to_string(image) + " out of range (" +
             std::to_string(archive.images.size) + " images)";
    return false;
  }
  const pbrta::ImageRecord& im = archive.images[image];
  std::string at = "image " + std::to_string(image) + ": ";
  if ((im.channels != 1 && im.channels != 3) || im.levels == 0 || im.levels > 32 || im.wrap > 2 ||
      im.format > uint32_t(pbrta::PixelFormat::kUnorm8)) {
    *error = at + "malformed image record";
    return false;
  }
  const pbrta::ArchiveReader& r = archive.reader();
  if (im.section >= r.section_count() || r.section_data(im.section) == nullptr) {
    *error = at + "texels section not loaded";
    return false;
  }
  channels_ = int(im.channels);
  wrap_ = ImageWrap(im.wrap);
  flip_rows_ = flip_rows;
  num_levels_ = int(im.levels);
  const uint8_t* base = r.section_data(im.section);
  uint64_t size = r.section_size(im.section);
  const uint64_t bytes_per = pbrta::texel_bytes(im.format);
  // Pass 1: place the levels and check them (SceneArchive::load checked too;
  // this keeps the class safe on its own).
  uint64_t offsets[32];
  uint64_t total_texels = 0, off = im.offset;
  for (int l = 0; l < num_levels_; ++l) {
    int w = std::max(1, int(im.width >> l)), h = std::max(1, int(im.height >> l));
    uint64_t count = uint64_t(w) * uint64_t(h) * im.channels;
    if (off % 16 != 0 || off > size || count * bytes_per > size - off) {
      *error = at + "level " + std::to_string(l) + " lies outside its section";
      return false;
    }
    levels_[l].w = w;
    levels_[l].h = h;
    offsets[l] = off;
    total_texels += count;
    off = (off + count * bytes_per + 15) & ~uint64_t(15);
  }
  if (bytes_per == 4) {
    for (int l = 0; l < num_levels_; ++l)
      levels_[l].data = reinterpret_cast<const float*>(base + offsets[l]);
    return true;
  }
  // Pass 2: widen f16 / unorm8 to f32 once, with format/texel_format's decoding (the values
  // pbrtc --dump writes). Widening at load rather than per lookup: a lookup then reads floats
  // as for f32 archives. Measured on a 1024^2 RGB level: converting each half per texel made
  // a bilinear lookup about 3x slower than reading floats, while widening the whole level
  // takes about 1 ms (a table of all halves); the price is the widened copy's f32 memory
  // beside the texels section.
  widened_ = std::make_shared<std::vector<float>>(total_texels);
  float* out = widened_->data();
  for (int l = 0; l < num_levels_; ++l) {
    const uint64_t count = uint64_t(levels_[l].w) * levels_[l].h * im.channels;
    widen(im.format, base + offsets[l], count, out);
    levels_[l].data = out;
    out += count;
  }
  return true;
}

template <class T>
T MipMap::fetch(int level, int s, int t) const {
  const Level& l = levels_[level];
  switch (wrap_) {
    case ImageWrap::kRepeat:
      s = mod(s, l.w);
      t = mod(t, l.h);
      break;
    case ImageWrap::kClamp:
      s = clamp(s, 0, l.w - 1);
      t = clamp(t, 0, l.h - 1);
      break;
    case ImageWrap::kBlack:
      if (s < 0 || s >= l.w || t < 0 || t >= l.h) return T(0.f);
      break;
  }
  return fetch_inside<T>(level, s, t);
}

bool MipMap::inside(int level, int s0, int t0, int s1, int t1, int* shift_s, int* shift_t) const {
  const Level& l = levels_[level];
  *shift_s = *shift_t = 0;
  if (wrap_ == ImageWrap::kRepeat) {
    *shift_s = mod(s0, l.w) - s0;
    *shift_t = mod(t0, l.h) - t0;
  }
  return s0 + *shift_s >= 0 && t0 + *shift_t >= 0 && s1 + *shift_s < l.w && t1 + *shift_t < l.h;
}

template <class T>
T MipMap::fetch_inside(int level, int s, int t) const {
  return from_texel<T>(texel_data(level, s, t), channels_);
}

Rgb MipMap::texel(int level, int s, int t) const {
  return fetch<Rgb>(level, s, t);
}
float MipMap::texel_float(int level, int s, int t) const {
  return fetch<float>(level, s, t);
}

template <class T>
T MipMap::triangle(int level, Vec2 st) const {
  level = clamp(level, 0, num_levels_ - 1);
  float s = st.x * levels_[level].w - 0.5f;
  float t = st.y * levels_[level].h - 0.5f;
  int s0 = int(std::floor(s)), t0 = int(std::floor(t));
  float ds = s - s0, dt = t - t0;
  auto blend = [&](auto texel) {
    return (1 - ds) * (1 - dt) * texel(s0, t0) + (1 - ds) * dt * texel(s0, t0 + 1) +
           ds * (1 - dt) * texel(s0 + 1, t0) + ds * dt * texel(s0 + 1, t0 + 1);
  };
  int ks, kt;
  if (inside(level, s0, t0, s0 + 1, t0 + 1, &ks, &kt))
    return blend([&](int is, int it) { return fetch_inside<T>(level, is + ks, it + kt); });
  return blend([&](int is, int it) { return fetch<T>(level, is, it); });
}

Rgb MipMap::bilerp(int level, Vec2 st) const {
  return triangle<Rgb>(level, st);
}
float MipMap::bilerp_float(int level, Vec2 st) const {
  return triangle<float>(level, st);
}

void MipMap::prefetch_bilinear(Vec2 st) const {
  const Level& l = levels_[0];
  if (!l.data || !(st.x >= 0 && st.x <= 1 && st.y >= 0 && st.y <= 1)) return;
  // Texels s0, s0 + 1 of rows t0, t0 + 1 (triangle()'s), clamped into the level: the first
  // and last byte of each row's pair, which may straddle a cache line.
  const int s0 = clamp(int(st.x * l.w - 0.5f), 0, l.w - 2 < 0 ? 0 : l.w - 2);
  const int t0 = clamp(int(st.y * l.h - 0.5f), 0, l.h - 1);
  for (int t : {t0, std::min(t0 + 1, l.h - 1)}) {
    const float* p = texel_data(0, s0, t);
    __builtin_prefetch(p);
    __builtin_prefetch(p + 2 * channels_ - 1);
  }
}

template <class T>
T MipMap::trilinear(Vec2 st, float width) const {
  // The level whose texel spacing equals width: 2^(level - (levels - 1)) = width.
  float level = num_levels_ - 1 + log2f_pbrt(std::max(width, 1e-8f));
  if (level < 0) return triangle<T>(0, st);
  if (!(level < num_levels_ - 1)) return fetch<T>(num_levels_ - 1, 0, 0);  // NaN too
  int ilevel = int(std::floor(level));
  float delta = level - ilevel;
  return lerp(delta, triangle<T>(ilevel, st), triangle<T>(ilevel + 1, st));
}

Rgb MipMap::lookup_trilinear(Vec2 st, float width) const {
  return trilinear<Rgb>(st, width);
}
float MipMap::lookup_trilinear_float(Vec2 st, float width) const {
  return trilinear<float>(st, width);
}

template <class T>
T MipMap::ewa(int level, Vec2 st, Vec2 dst0, Vec2 dst1) const {
  if (level >= num_levels_) return fetch<T>(num_levels_ - 1, 0, 0);
  // To this level's texel units, texel centres at integers.
  float w = float(levels_[level].w), h = float(levels_[level].h);
  st.x = st.x * w - 0.5f;
  st.y = st.y * h - 0.5f;
  dst0.x *= w;
  dst0.y *= h;
  dst1.x *= w;
  dst1.y *= h;
  // The implicit ellipse A s^2 + B s t + C t^2 = 1 spanned by the axes, each
  // widened by one texel so it always covers at least one texel centre.
  float a = dst0.y * dst0.y + dst1.y * dst1.y + 1;
  float b = -2 * (dst0.x * dst0.y + dst1.x * dst1.y);
  float c = dst0.x * dst0.x + dst1.x * dst1.x + 1;
  float inv_f = 1 / (a * c - b * b * 0.25f);
  a *= inv_f;
  b *= inv_f;
  c *= inv_f;
  float det = -b * b + 4 * a * c;
  float inv_det = 1 / det;
  float u_sqrt = std::sqrt(det * c), v_sqrt = std::sqrt(a * det);
  int s0 = int(std::ceil(st.x - 2 * inv_det * u_sqrt));
  int s1 = int(std::floor(st.x + 2 * inv_det * u_sqrt));
  int t0 = int(std::ceil(st.y - 2 * inv_det * v_sqrt));
  int t1 = int(std::floor(st.y + 2 * inv_det * v_sqrt));
  T sum(0.f);
  float sum_w = 0;
  auto accumulate = [&](auto texel) {
    for (int it = t0; it <= t1; ++it) {
      float tt = it - st.y;
      for (int is = s0; is <= s1; ++is) {
        float ss = is - st.x;
        float r2 = a * ss * ss + b * ss * tt + c * tt * tt;
        if (r2 < 1) {
          int index = std::min(int(r2 * kWeightLutSize), kWeightLutSize - 1);
          float weight = kWeights.w[index];
          sum += texel(is, it) * weight;
          sum_w += weight;
        }
      }
    }
  };
  int ks, kt;
  if (inside(level, s0, t0, s1, t1, &ks, &kt))
    accumulate([&](int is, int it) { return fetch_inside<T>(level, is + ks, it + kt); });
  else
    accumulate([&](int is, int it) { return fetch<T>(level, is, it); });
  return sum / sum_w;
}

template <class T>
T MipMap::ewa_lookup(Vec2 st, Vec2 dst0, Vec2 dst1, float max_anisotropy) const {
  // dst0 becomes the major axis.
  float len0 = dst0.x * dst0.x + dst0.y * dst0.y, len1 = dst1.x * dst1.x + dst1.y * dst1.y;
  if (len0 < len1) std::swap(dst0, dst1);
  float major = std::sqrt(std::max(len0, len1));
  float minor = std::sqrt(std::min(len0, len1));
  // Too eccentric an ellipse would touch too many texels: widen the minor axis.
  if (minor * max_anisotropy < major && minor > 0) {
    float scale = major / (minor * max_anisotropy);
    dst1 = dst1 * scale;
    minor *= scale;
  }
  if (minor == 0) return triangle<T>(0, st);
  float lod = std::max(0.f, num_levels_ - 1.f + log2f_pbrt(minor));
  // Both levels past the pyramid: pbrt-v3 blends the coarsest texel with itself.
  if (!(lod < num_levels_)) return fetch<T>(num_levels_ - 1, 0, 0);
  int ilod = int(std::floor(lod));
  return lerp(lod - ilod, ewa<T>(ilod, st, dst0, dst1), ewa<T>(ilod + 1, st, dst0, dst1));
}

Rgb MipMap::lookup_ewa(Vec2 st, Vec2 dst0, Vec2 dst1, float max_anisotropy) const {
  return ewa_lookup<Rgb>(st, dst0, dst1, max_anisotropy);
}
float MipMap::lookup_ewa_float(Vec2 st, Vec2 dst0, Vec2 dst1, float max_anisotropy) const {
  return ewa_lookup<float>(st, dst0, dst1, max_anisotropy);
}

}  // namespace rt
