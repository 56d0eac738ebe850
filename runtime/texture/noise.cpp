// runtime/texture/noise.cpp — see noise.h.
#include "runtime/texture/noise.h"

#include <cmath>

#include "runtime/core/math.h"

namespace rt {

namespace {

// Ken Perlin's permutation of 0..255, from the reference implementation of
// "Improving Noise" (SIGGRAPH 2002, https://mrl.cs.nyu.edu/~perlin/noise/),
// the table pbrt-v3 uses. Doubled at startup so lookups need no wrapping.
constexpr int kPermSize = 256;
constexpr int kPerlinPermutation[kPermSize] = {
    151, 160, 137, 91,  90,  15,  131, 13,  201, 95,  96,  53,  194, 233, 7,   225, 140, 36,  103,
    30,  69,  142, 8,   99,  37,  240, 21,  10,  23,  190, 6,   148, 247, 120, 234, 75,  0,   26,
    197, 62,  94,  252, 219, 203, 117, 35,  11,  32,  57,  177, 33,  88,  237, 149, 56,  87,  174,
    20,  125, 136, 171, 168, 68,  175, 74,  165, 71,  134, 139, 48,  27,  166, 77,  146, 158, 231,
    83,  111, 229, 122, 60,  211, 133, 230, 220, 105, 92,  41,  55,  46,  245, 40,  244, 102, 143,
    54,  65,  25,  63,  161, 1,   216, 80,  73,  209, 76,  132, 187, 208, 89,  18,  169, 200, 196,
    135, 130, 116, 188, 159, 86,  164, 100, 109, 198, 173, 186, 3,   64,  52,  217, 226, 250, 124,
    123, 5,   202, 38,  147, 118, 126, 255, 82,  85,  212, 207, 206, 59,  227, 47,  16,  58,  17,
    182, 189, 28,  42,  223, 183, 170, 213, 119, 248, 152, 2,   44,  154, 163, 70,  221, 153, 101,
    155, 167, 43,  172, 9,   129, 22,  39,  253, 19,  98,  108, 110, 79,  113, 224, 232, 178, 185,
    112, 104, 218, 246, 97,  228, 251, 34,  242, 193, 238, 210, 144, 12,  191, 179, 162, 241, 81,
    51,  145, 235, 249, 14,  239, 107, 49,  192, 214, 31,  181, 199, 106, 157, 184, 84,  204, 176,
    115, 121, 50,  45,  127, 4,   150, 254, 138, 236, 205, 93,  222, 114, 67,  29,  24,  72,  243,
    141, 128, 195, 78,  66,  215, 61,  156, 180,
};

struct Perm {
  int p[2 * kPermSize];
  Perm() {
    for (int i = 0; i < 2 * kPermSize; ++i) p[i] = kPerlinPermutation[i % kPermSize];
  }
};
const Perm kPerm;

// Perlin's 16-entry hash-to-gradient choice (12 cube-edge gradients, four
// of them twice) as vectors: grad = dot(g[h], offset). The hash is random,
// so the branchy form (select u and v, then their signs) mispredicts about
// every other call; a table lookup does not branch. The sums are the same
// floats: the zero component adds an exact 0.
struct Gradients {
  float g[16][3];
  constexpr Gradients() : g() {
    for (int h = 0; h < 16; ++h) {
      const int u = h < 8 || h == 12 || h == 13 ? 0 : 1;  // dx, else dy
      const int v = h < 4 || h == 12 || h == 13 ? 1 : 2;  // dy, else dz
      g[h][u] = (h & 1) ? -1.f : 1.f;
      g[h][v] = (h & 2) ? -1.f : 1.f;
    }
  }
};
constexpr Gradients kGrad;

inline float grad(int hash, float dx, float dy, float dz) {
  const float* g = kGrad.g[hash & 15];
  return g[0] * dx + g[1] * dy + g[2] * dz;
}

// 6t^5 - 15t^4 + 10t^3: C2-continuous interpolation weight.
inline float fade(float t) {
  float t3 = t * t * t, t4 = t3 * t;
  return 6 * t4 * t - 15 * t4 + 10 * t3;
}

inline float smooth_step(float lo, float hi, float v) {
  float t = clamp((v - lo) / (hi - lo), 0.f, 1.f);
  return t * t * (-2 * t + 3);
}

inline float log2f_pbrt(float x) {
  return std::log(x) * 1.442695040888963387004650940071f;
}

// Octaves the footprint allows: the noise's finest feature should stay above
// the pixel spacing (pbrt-v3: n = -1 - log2(len) / 2 with len the squared length).
inline float octave_count(Vec3 dpdx, Vec3 dpdy, int max_octaves) {
  float len2 = std::max(length_squared(dpdx), length_squared(dpdy));
  return clamp(-1 - .5f * log2f_pbrt(len2), 0.f, float(max_octaves));
}

}  // namespace

float noise(float x, float y, float z) {
  int ix = int(std::floor(x)), iy = int(std::floor(y)), iz = int(std::floor(z));
  float dx = x - ix, dy = y - iy, dz = z - iz;
  ix &= kPermSize - 1;
  iy &= kPermSize - 1;
  iz &= kPermSize - 1;
  // Perlin's nested hash p[p[p[x] + y] + z], its shared prefixes computed once.
  const int* p = kPerm.p;
  const int a = p[ix] + iy, b = p[ix + 1] + iy;
  const int aa = p[a] + iz, ab = p[a + 1] + iz, ba = p[b] + iz, bb = p[b + 1] + iz;
  float w000 = grad(p[aa], dx, dy, dz);
  float w100 = grad(p[ba], dx - 1, dy, dz);
  float w010 = grad(p[ab], dx, dy - 1, dz);
  float w110 = grad(p[bb], dx - 1, dy - 1, dz);
  float w001 = grad(p[aa + 1], dx, dy, dz - 1);
  float w101 = grad(p[ba + 1], dx - 1, dy, dz - 1);
  float w011 = grad(p[ab + 1], dx, dy - 1, dz - 1);
  float w111 = grad(p[bb + 1], dx - 1, dy - 1, dz - 1);
  float wx = fade(dx), wy = fade(dy), wz = fade(dz);
  float x00 = lerp(wx, w000, w100), x10 = lerp(wx, w010, w110);
  float x01 = lerp(wx, w001, w101), x11 = lerp(wx, w011, w111);
  float y0 = lerp(wy, x00, x10), y1 = lerp(wy, x01, x11);
  return lerp(wz, y0, y1);
}

float fbm(Vec3 p, Vec3 dpdx, Vec3 dpdy, float omega, int max_octaves) {
  float n = octave_count(dpdx, dpdy, max_octaves);
  int n_int = int(std::floor(n));
  float sum = 0, lambda = 1, o = 1;
  for (int i = 0; i < n_int; ++i) {
    sum += o * noise(lambda * p);
    lambda *= 1.99f;
    o *= omega;
  }
  // The partial octave fades in rather than popping. Its weight is 0 whenever the footprint
  // allows every octave (n = max_octaves, the common case up close): then its noise, which
  // could only add a zero, is not computed.
  const float weight = smooth_step(.3f, .7f, n - n_int);
  if (weight != 0) sum += o * weight * noise(lambda * p);
  return sum;
}

float turbulence(Vec3 p, Vec3 dpdx, Vec3 dpdy, float omega, int max_octaves) {
  float n = octave_count(dpdx, dpdy, max_octaves);
  int n_int = int(std::floor(n));
  float sum = 0, lambda = 1, o = 1;
  for (int i = 0; i < n_int; ++i) {
    sum += o * std::fabs(noise(lambda * p));
    lambda *= 1.99f;
    o *= omega;
  }
  // Octaves cut for antialiasing contribute their average |noise| (about
  // 0.2) instead, so the texture does not darken with distance. As pbrt-v3,
  // the partial octave's amplitude is counted again by the first clamped one.
  const float weight = smooth_step(.3f, .7f, n - n_int);
  sum += o * (weight == 0 ? 0.2f : lerp(weight, 0.2f, std::fabs(noise(lambda * p))));
  for (int i = n_int; i < max_octaves; ++i) {
    sum += o * 0.2f;
    o *= omega;
  }
  return sum;
}

}  // namespace rt
