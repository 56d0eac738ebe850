#include "compiler/image_decoder.h"

#include "compiler/image_reader.h"
#include "format/archive.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>

namespace pbrtc {

namespace {

// pbrt-v3's constants as its Float (float) holds them.
constexpr float kPi = 3.14159265358979323846f;
constexpr float kInvLog2 = 1.442695040888963387004650940071f;

// pbrt-v3's InverseGammaCorrect: the sRGB curve undone, in float.
float inverse_gamma(float v) {
  if (v <= 0.04045f) return v * 1.f / 12.92f;
  return std::pow((v + 0.055f) * 1.f / 1.055f, 2.4f);
}

// pbrt-v3's RGBSpectrum::y().
float luminance(const float* c) {
  return 0.212671f * c[0] + 0.715160f * c[1] + 0.072169f * c[2];
}

// pbrt-v3's Lanczos(x, tau = 2): a sinc windowed by a wider sinc, zero past |x| = 1.
float lanczos(float x) {
  const float tau = 2;
  x = std::abs(x);
  if (x < 1e-5f) return 1;
  if (x > 1.f) return 0;
  x *= kPi;
  float s = std::sin(x * tau) / (x * tau);
  float l = std::sin(x) / x;
  return s * l;
}

int mod(int a, int b) {
  int r = a - (a / b) * b;
  return r < 0 ? r + b : r;
}

// The texel index the wrap mode gives for i in [0, n), or -1 for black.
int wrap_index(int i, int n, ImageWrap wrap) {
  switch (wrap) {
    case ImageWrap::kRepeat:
      return mod(i, n);
    case ImageWrap::kClamp:
      return std::clamp(i, 0, n - 1);
    case ImageWrap::kBlack:
      break;
  }
  return i >= 0 && i < n ? i : -1;
}

bool is_pow2(uint32_t v) {
  return v && !(v & (v - 1));
}

struct ResampleWeight {
  int first;
  float w[4];
};

// pbrt-v3's MIPMap::resampleWeights: four Lanczos taps around each new texel's centre in the old
// image, normalized, in pbrt-v3's float order.
std::vector<ResampleWeight> resample_weights(int old_res, int new_res) {
  std::vector<ResampleWeight> wt(static_cast<size_t>(new_res));
  const float filter_width = 2.f;
  for (int i = 0; i < new_res; ++i) {
    float center = (float(i) + .5f) * float(old_res) / float(new_res);
    wt[size_t(i)].first = int(std::floor((center - filter_width) + 0.5f));
    for (int j = 0; j < 4; ++j) {
      float pos = float(wt[size_t(i)].first + j) + .5f;
      wt[size_t(i)].w[j] = lanczos((pos - center) / filter_width);
    }
    float inv =
        1 / (wt[size_t(i)].w[0] + wt[size_t(i)].w[1] + wt[size_t(i)].w[2] + wt[size_t(i)].w[3]);
    for (float& w : wt[size_t(i)].w) w *= inv;
  }
  return wt;
}

// Runs body(i) for i in [0, n), in parallel when there is enough work to pay for it. Every i
// writes its own outputs, so the result does not depend on the split.
template <class F>
void parallel_rows(int n, size_t work_per_row, const F& body) {
  if (size_t(n) * work_per_row < (size_t(1) << 16)) {
    for (int i = 0; i < n; ++i) body(i);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<int>(0, n), [&](const tbb::blocked_range<int>& r) {
    for (int i = r.begin(); i < r.end(); ++i) body(i);
  });
}

// One level of a pyramid, with pbrt-v3's MIPMap::Texel lookup.
struct LevelView {
  const float* data;
  int w, h, c;
  ImageWrap wrap;
  // The channels of texel (s, t), or nullptr for black outside the image.
  const float* texel(int s, int t) const {
    s = wrap_index(s, w, wrap);
    t = wrap_index(t, h, wrap);
    if (s < 0 || t < 0) return nullptr;
    return data + (size_t(t) * size_t(w) + size_t(s)) * size_t(c);
  }
};

LevelView level_view(const DecodedImage& im, int level) {
  return {im.levels[size_t(level)].data(), std::max(1, int(im.width >> level)),
          std::max(1, int(im.height >> level)), int(im.channels), im.wrap};
}

void flip_rows(std::vector<float>* texels, uint32_t width, uint32_t height, uint32_t channels) {
  const size_t row = size_t(width) * channels;
  for (uint32_t y = 0; y < height / 2; ++y)
    std::swap_ranges(texels->begin() + std::ptrdiff_t(y * row),
                     texels->begin() + std::ptrdiff_t((y + 1) * row),
                     texels->begin() + std::ptrdiff_t((height - 1 - y) * row));
}

// pbrt-v3's MIPMap::triangle: bilinear interpolation of one level, out[0..c).
void triangle(const DecodedImage& im, int level, float s_coord, float t_coord, float* out) {
  level = std::clamp(level, 0, int(im.levels.size()) - 1);
  const LevelView v = level_view(im, level);
  float s = s_coord * float(v.w) - 0.5f;
  float t = t_coord * float(v.h) - 0.5f;
  int s0 = int(std::floor(s)), t0 = int(std::floor(t));
  float ds = s - float(s0), dt = t - float(t0);
  const float a = (1 - ds) * (1 - dt), b = (1 - ds) * dt, c = ds * (1 - dt), d = ds * dt;
  const float* t00 = v.texel(s0, t0);
  const float* t01 = v.texel(s0, t0 + 1);
  const float* t10 = v.texel(s0 + 1, t0);
  const float* t11 = v.texel(s0 + 1, t0 + 1);
  for (int k = 0; k < v.c; ++k) {
    float x00 = t00 ? t00[k] : 0, x01 = t01 ? t01[k] : 0;
    float x10 = t10 ? t10[k] : 0, x11 = t11 ? t11[k] : 0;
    out[k] = a * x00 + b * x01 + c * x10 + d * x11;
  }
}

// pbrt-v3's MIPMap::Lookup(st, width): trilinear filtering.
void trilinear(const DecodedImage& im, float s, float t, float width, float* out) {
  const int levels = int(im.levels.size());
  float level = float(levels - 1) + std::log(std::max(width, 1e-8f)) * kInvLog2;
  if (level < 0) {
    triangle(im, 0, s, t, out);
  } else if (level >= float(levels - 1)) {
    const float* p = level_view(im, levels - 1).texel(0, 0);
    for (uint32_t k = 0; k < im.channels; ++k) out[k] = p ? p[k] : 0;
  } else {
    int i = int(std::floor(level));
    float delta = level - float(i);
    float a[4], b[4];
    triangle(im, i, s, t, a);
    triangle(im, i + 1, s, t, b);
    for (uint32_t k = 0; k < im.channels; ++k) out[k] = (1 - delta) * a[k] + delta * b[k];
  }
}

}  // namespace

ImageWrap parse_image_wrap(const std::string& word) {
  if (word == "black") return ImageWrap::kBlack;
  if (word == "clamp") return ImageWrap::kClamp;
  return ImageWrap::kRepeat;
}

ImageOptions ImageOptions::for_texture(const std::string& path, bool float_texture,
                                       const std::string& wrap, float scale, bool gamma_given,
                                       bool gamma) {
  ImageOptions o;
  o.channels = float_texture ? 1 : 3;
  const std::string ext = image_file_extension(path);
  if (gamma_given) {
    o.gamma = gamma;
  } else if (ext == ".png" || ext == ".tga" || ext == ".exr" || ext == ".pfm") {
    o.gamma = ext == ".png" || ext == ".tga";  // pbrt-v3's own rule for its own formats
  } else {
    o.gamma_if_integer = true;  // 8-bit JPEG, BMP, ... as pbrt-v3 treats its 8-bit formats
  }
  o.scale = scale;
  o.wrap = parse_image_wrap(wrap);
  o.flip = true;
  return o;
}

std::vector<std::vector<float>> build_mip_pyramid(std::vector<float> texels, uint32_t width,
                                                  uint32_t height, uint32_t channels,
                                                  ImageWrap wrap, uint32_t* pow2_width,
                                                  uint32_t* pow2_height) {
  const int c = int(channels);
  int w = int(width), h = int(height);
  if (!is_pow2(width) || !is_pow2(height)) {
    // Resample in s (the original rows), then in t, clamping negative lobes to 0 as pbrt-v3
    // does only after the second pass.
    const int W = int(round_up_pow2(width)), H = int(round_up_pow2(height));
    const std::vector<ResampleWeight> sw = resample_weights(w, W);
    std::vector<float> zoomed(size_t(W) * size_t(h) * size_t(c));
    parallel_rows(h, size_t(W) * 4 * size_t(c), [&](int t) {
      for (int s = 0; s < W; ++s) {
        float* out = &zoomed[(size_t(t) * size_t(W) + size_t(s)) * size_t(c)];
        for (int k = 0; k < c; ++k) out[k] = 0.f;
        for (int j = 0; j < 4; ++j) {
          int os = wrap_index(sw[size_t(s)].first + j, w, wrap);
          if (os < 0) continue;
          const float* in = &texels[(size_t(t) * size_t(w) + size_t(os)) * size_t(c)];
          for (int k = 0; k < c; ++k) out[k] += sw[size_t(s)].w[j] * in[k];
        }
      }
    });
    const std::vector<ResampleWeight> tw = resample_weights(h, H);
    std::vector<float> resampled(size_t(W) * size_t(H) * size_t(c));
    parallel_rows(W, size_t(H) * 4 * size_t(c), [&](int s) {
      for (int t = 0; t < H; ++t) {
        float* out = &resampled[(size_t(t) * size_t(W) + size_t(s)) * size_t(c)];
        float acc[4] = {0.f, 0.f, 0.f, 0.f};
        for (int j = 0; j < 4; ++j) {
          int ot = wrap_index(tw[size_t(t)].first + j, h, wrap);
          if (ot < 0) continue;
          const float* in = &zoomed[(size_t(ot) * size_t(W) + size_t(s)) * size_t(c)];
          for (int k = 0; k < c; ++k) acc[k] += tw[size_t(t)].w[j] * in[k];
        }
        // pbrt-v3's Clamp(v, 0, Infinity): negative lobes to 0, NaN kept.
        for (int k = 0; k < c; ++k) out[k] = acc[k] < 0.f ? 0.f : acc[k];
      }
    });
    texels = std::move(resampled);
    w = W, h = H;
  }
  *pow2_width = uint32_t(w);
  *pow2_height = uint32_t(h);

  const int num_levels = int(pbrta::full_pyramid_levels(uint32_t(w), uint32_t(h)));
  std::vector<std::vector<float>> levels(static_cast<size_t>(num_levels));
  levels[0] = std::move(texels);
  for (int i = 1; i < num_levels; ++i) {
    const LevelView prev{levels[size_t(i - 1)].data(), std::max(1, w >> (i - 1)),
                         std::max(1, h >> (i - 1)), c, wrap};
    const int sr = std::max(1, prev.w / 2), tr = std::max(1, prev.h / 2);
    std::vector<float>& out = levels[size_t(i)];
    out.resize(size_t(sr) * size_t(tr) * size_t(c));
    parallel_rows(tr, size_t(sr) * 4 * size_t(c), [&](int t) {
      for (int s = 0; s < sr; ++s) {
        // A level one texel thin still averages four lookups; the wrap mode supplies the
        // missing neighbour (black makes it 0), as in pbrt-v3.
        const float* a = prev.texel(2 * s, 2 * t);
        const float* b = prev.texel(2 * s + 1, 2 * t);
        const float* d0 = prev.texel(2 * s, 2 * t + 1);
        const float* d1 = prev.texel(2 * s + 1, 2 * t + 1);
        float* o = &out[(size_t(t) * size_t(sr) + size_t(s)) * size_t(c)];
        for (int k = 0; k < c; ++k)
          o[k] = .25f *
                 ((a ? a[k] : 0.f) + (b ? b[k] : 0.f) + (d0 ? d0[k] : 0.f) + (d1 ? d1[k] : 0.f));
      }
    });
  }
  return levels;
}

bool decode_image(const std::string& path, const ImageOptions& options, DecodedImage* out,
                  std::string* error) {
  RgbImage image;
  if (!read_image_rgb(path, &image, error)) return false;
  const uint32_t w = image.width, h = image.height;
  const bool gamma = options.gamma || (options.gamma_if_integer && image.integer_samples);
  const bool float_grey = image.float_grey;
  std::vector<float> rgb = std::move(image.rgb);
  if (options.flip) flip_rows(&rgb, w, h, 3);

  // pbrt-v3's ImageTexture::convertIn (identity for lights: scale 1, no gamma).
  const size_t n = size_t(w) * h;
  std::vector<float> texels;
  if (options.channels == 1) {
    texels.resize(n);
    for (size_t i = 0; i < n; ++i) {
      // A one-channel PFM is what pbrtc --dump writes for a float texture: taken as it is, so
      // it reads back bit for bit (y() of the replicated grey may differ by an ulp or two).
      float y = float_grey ? rgb[i * 3] : luminance(&rgb[i * 3]);
      texels[i] = options.scale * (gamma ? inverse_gamma(y) : y);
    }
  } else {
    // Converted in place: one image-sized buffer less at the peak.
    texels.swap(rgb);
    for (size_t i = 0; i < n * 3; ++i)
      texels[i] = options.scale * (gamma ? inverse_gamma(texels[i]) : texels[i]);
  }
  rgb = {};

  DecodedImage im;
  im.channels = options.channels == 1 ? 1 : 3;
  im.source_width = w;
  im.source_height = h;
  im.wrap = options.wrap;
  if (!is_pow2(w) || !is_pow2(h)) {
    // Resampling cannot be undone: keep what enters it, in the stored rows' order.
    im.source = texels;
    if (options.flip) flip_rows(&im.source, w, h, im.channels);
  }
  im.levels =
      build_mip_pyramid(std::move(texels), w, h, im.channels, options.wrap, &im.width, &im.height);
  if (options.flip)
    for (size_t l = 0; l < im.levels.size(); ++l)
      flip_rows(&im.levels[l], std::max(1u, im.width >> l), std::max(1u, im.height >> l),
                im.channels);
  *out = std::move(im);
  return true;
}

DecodedImage environment_distribution(const DecodedImage& map, const float L[3]) {
  DecodedImage d;
  d.channels = 1;
  d.width = 2 * map.width;
  d.height = 2 * map.height;
  d.source_width = map.source_width;
  d.source_height = map.source_height;
  d.wrap = ImageWrap::kRepeat;
  d.levels.resize(1);
  std::vector<float>& img = d.levels[0];
  const int width = int(d.width), height = int(d.height);
  img.resize(size_t(width) * size_t(height));
  const float fwidth = 0.5f / float(std::min(width, height));
  parallel_rows(height, size_t(width) * 16, [&](int v) {
    const float vp = (float(v) + .5f) / float(height);
    const float sin_theta = std::sin(kPi * (float(v) + .5f) / float(height));
    for (int u = 0; u < width; ++u) {
      const float up = (float(u) + .5f) / float(width);
      float rgb[4];
      trilinear(map, up, vp, fwidth, rgb);
      // pbrt-v3 multiplies L into the texels before its MIPMap; lookups are linear, so this
      // is the same up to float rounding.
      for (int k = 0; k < 3; ++k) rgb[k] *= L[k];
      img[size_t(v) * size_t(width) + size_t(u)] = luminance(rgb) * sin_theta;
    }
  });
  return d;
}

}  // namespace pbrtc
