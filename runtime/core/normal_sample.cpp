// runtime/core/normal_sample.cpp — see normal_sample.h.
#include "runtime/core/normal_sample.h"

#include <cmath>
#include <cstdint>

namespace rt {

namespace {

// 128 layers of equal area v under exp(-x^2 / 2), the base layer's strip and tail included:
// r is where the tail starts. Both constants are Marsaglia and Tsang's (2000), section 4.
constexpr int kLayers = 128;
constexpr double kR = 3.442619855899;
constexpr double kV = 9.91256303526217e-3;
// The value is a 25-bit signed integer m in [-2^24, 2^24); x = m w[i].
constexpr double kScale = 16777216.0;  // 2^24

struct Ziggurat {
  // Layer i spans [0, x_i) (x_0 is the base's equivalent width v / f(r)); m is inside the
  // box under the curve when |m| < k[i]; f[i] = exp(-x_i^2 / 2).
  uint32_t k[kLayers];
  float w[kLayers], f[kLayers];

  Ziggurat() {
    auto density = [](double x) { return std::exp(-0.5 * x * x); };
    double x = kR;
    const double base = kV / density(kR);
    k[0] = uint32_t(kR / base * kScale);
    k[1] = 0;
    w[0] = float(base / kScale);
    w[kLayers - 1] = float(kR / kScale);
    f[0] = 1;
    f[kLayers - 1] = float(density(kR));
    for (int i = kLayers - 2; i >= 1; --i) {
      const double inner = std::sqrt(-2 * std::log(kV / x + density(x)));
      k[i + 1] = uint32_t(inner / x * kScale);
      x = inner;
      f[i] = float(density(x));
      w[i] = float(x / kScale);
    }
  }
};

const Ziggurat& tables() {
  static const Ziggurat z;
  return z;
}

// Uniform in (0, 1]: a logarithm's argument.
float open_uniform(Rng& rng) {
  return (float(rng.next_u32() >> 8) + 1) * 0x1p-24f;
}

}  // namespace

float normal_sample(Rng& rng) {
  const Ziggurat& z = tables();
  for (;;) {
    const uint32_t u = rng.next_u32();
    const int i = int(u & (kLayers - 1));
    const int32_t m = int32_t(u) >> 7;  // arithmetic shift: the top 25 bits, signed
    const uint32_t mag = m < 0 ? uint32_t(-int64_t(m)) : uint32_t(m);
    const float x = float(m) * z.w[i];
    if (mag < z.k[i]) return x;  // inside the layer's box: under the curve
    if (i == 0) {
      // The tail beyond r (Marsaglia's 1964 method).
      float t, y;
      do {
        t = -std::log(open_uniform(rng)) / float(kR);
        y = -std::log(open_uniform(rng));
      } while (y + y < t * t);
      return m < 0 ? -(float(kR) + t) : float(kR) + t;
    }
    // The wedge between the box and the curve: accept under the density.
    const float f_hi = z.f[i - 1], f_lo = z.f[i];
    if (f_lo + rng.next_float() * (f_hi - f_lo) < std::exp(-0.5f * x * x)) return x;
  }
}

}  // namespace rt
