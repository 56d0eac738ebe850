// Participating media against what they must compute: the Henyey-Greenstein
// sampler against its own density (chi-square), Beer-Lambert transmittance
// for homogeneous media and constant grids, delta and ratio tracking against
// the analytic answer for a linear density ramp, and the majorant grid
// against the densities it must bound. Media come from real scene text
// compiled by pbrtc.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "runtime/core/rng.h"
#include "runtime/medium/media.h"
#include "runtime/medium/phase.h"
#include "runtime/runtime_test_support.h"
#include "test_support.h"

namespace rt {
namespace {

// Independent uniform numbers behind the Sampler interface the media draw from.
class RngSampler : public Sampler {
 public:
  explicit RngSampler(uint64_t seed) : Sampler(1), rng_(seed) {}
  std::unique_ptr<Sampler> clone() const override { return std::make_unique<RngSampler>(*this); }
  float get_1d() override { return rng_.next_float(); }
  Vec2 get_2d() override {
    float x = rng_.next_float();
    return {x, rng_.next_float()};
  }

 private:
  Rng rng_;
};

struct LoadedMedia {
  pbrta::SceneArchive archive;
  MediumSet media;
};

// Compiles one MakeNamedMedium (its parameters after the name) used by a sphere, and loads it.
void load_medium(const std::string& name, const std::string& params, LoadedMedia* out) {
  const std::string text = "MakeNamedMedium \"m\" " + params +
                           "\nWorldBegin\nMediumInterface \"m\" \"\"\nMaterial \"\"\n"
                           "Shape \"sphere\"\nWorldEnd\n";
  ASSERT_TRUE(
      testing_support::compile_text(testing_support::scratch_dir(name), text, &out->archive));
  std::string error;
  ASSERT_TRUE(out->media.build(out->archive, &error)) << error;
  ASSERT_EQ(out->media.size(), 1u);
}

// The same n-vector for every density sample: nx x 1 x 1 samples (i + 1/2) / nx, so the
// trilinear density along x between the first and last sample position is exactly x.
std::string ramp_grid(int nx) {
  std::string d;
  for (int i = 0; i < nx; ++i) d += " " + std::to_string((i + 0.5) / nx);
  return "\"string type\" \"heterogeneous\" \"integer nx\" " + std::to_string(nx) +
         " \"float density\" [" + d + "]";
}

TEST(PhaseHg, IntegratesToOne) {
  for (float g : {-0.9f, -0.3f, 0.f, 0.5f, 0.95f}) {
    // Midpoint rule in cos(theta) (the function does not depend on phi).
    const int n = 200000;
    double sum = 0;
    for (int i = 0; i < n; ++i) sum += phase_hg(-1 + 2 * (i + 0.5f) / n, g);
    EXPECT_NEAR(sum * 2 * kPi * 2.0 / n, 1.0, 2e-3) << "g " << g;
  }
}

TEST(PhaseHg, SamplesFollowTheDensity) {
  const Vec3 wo = normalize(Vec3{0.3f, -0.5f, 0.8f});
  Vec3 t1, t2;
  coordinate_system(-wo, &t1, &t2);
  for (float g : {-0.7f, 0.f, 0.3f, 0.9f}) {
    constexpr int kCos = 40, kPhi = 8, kN = 400000;
    std::vector<double> observed(kCos * kPhi, 0);
    Rng rng(uint64_t(1000 + 100 * g));
    for (int i = 0; i < kN; ++i) {
      Vec3 wi;
      Vec2 u{rng.next_float(), rng.next_float()};
      float pdf = sample_hg(wo, g, u, &wi);
      ASSERT_NEAR(length(wi), 1, 1e-4);
      ASSERT_NEAR(pdf, phase_hg(dot(wo, wi), g), 1e-4f * pdf);
      float c = dot(wi, -wo);  // cosine to the forward direction
      float phi = std::atan2(dot(wi, t2), dot(wi, t1));
      if (phi < 0) phi += 2 * kPi;
      int ci = std::min(kCos - 1, int((c + 1) / 2 * kCos));
      int pi = std::min(kPhi - 1, int(phi / (2 * kPi) * kPhi));
      observed[size_t(ci * kPhi + pi)] += 1;
    }
    double chi2 = 0;
    for (int ci = 0; ci < kCos; ++ci) {
      // The probability of the cosine bin, by a fine midpoint rule; phi is uniform.
      double p = 0;
      const int sub = 2000;
      for (int k = 0; k < sub; ++k) {
        double c = -1 + (ci + (k + 0.5) / sub) * 2.0 / kCos;
        p += phase_hg(float(-c), g) * 2 * kPi * (2.0 / kCos) / sub;
      }
      for (int pi = 0; pi < kPhi; ++pi) {
        double expected = p / kPhi * kN;
        double o = observed[size_t(ci * kPhi + pi)];
        chi2 += (o - expected) * (o - expected) / expected;
      }
    }
    // 319 degrees of freedom: mean 319, sd 25; 480 is beyond six sd.
    EXPECT_LT(chi2, 480) << "g " << g;
  }
}

TEST(Media, HomogeneousTransmittanceIsBeerLambert) {
  LoadedMedia m;
  load_medium("medium_beer",
              "\"string type\" \"homogeneous\" \"rgb sigma_a\" [0.5 1 2] "
              "\"rgb sigma_s\" [1 0 0.25] \"float scale\" 2",
              &m);
  RngSampler s(1);
  // |d| = 2 and tmax 1.5: three world units.
  Ray r{{0, 0, 0}, {0, 2, 0}, 1.5f};
  Rgb tr = m.media.tr(0, r, s);
  EXPECT_FLOAT_EQ(tr.r, std::exp(-3.f * 3));
  EXPECT_FLOAT_EQ(tr.g, std::exp(-2.f * 3));
  EXPECT_FLOAT_EQ(tr.b, std::exp(-4.5f * 3));
  // An infinite ray through an attenuating medium transmits nothing, and never NaN.
  Ray inf{{0, 0, 0}, {1, 0, 0}, kInfinity};
  EXPECT_EQ(m.media.tr(0, inf, s), Rgb(0.f));
}

// Sampling the homogeneous medium: the expected weight of "reached the end" is the
// transmittance, per channel (pbrt-v3's spectral MIS over the channel picked).
TEST(Media, HomogeneousSampleExpectationIsTransmittance) {
  LoadedMedia m;
  load_medium("medium_sample",
              "\"string type\" \"homogeneous\" \"rgb sigma_a\" [0.2 0.5 1] "
              "\"rgb sigma_s\" [0.3 0.5 0.1]",
              &m);
  RngSampler s(2);
  Ray r{{0, 0, 0}, {0, 0, 1}, 1.2f};
  const int n = 200000;
  double sum[3] = {0, 0, 0};
  for (int i = 0; i < n; ++i) {
    bool scattered;
    Vec3 p;
    Rgb w = m.media.sample(0, r, s, &scattered, &p);
    ASSERT_TRUE(w.is_finite());
    if (scattered) {
      ASSERT_GT(p.z, 0);
      ASSERT_LT(p.z, 1.2f);
      continue;
    }
    for (int c = 0; c < 3; ++c) sum[c] += w[c];
  }
  const float sigma_t[3] = {0.5f, 1.0f, 1.1f};
  for (int c = 0; c < 3; ++c) {
    double expected = std::exp(-sigma_t[c] * 1.2);
    EXPECT_NEAR(sum[c] / n, expected, 0.01) << "channel " << c;
  }
}

TEST(Media, ConstantGridTransmittanceIsBeerLambert) {
  LoadedMedia m;
  load_medium("medium_constant_grid",
              "\"string type\" \"heterogeneous\" \"integer nx\" 3 \"integer ny\" 3 "
              "\"integer nz\" 3 \"float density\" ["
              "1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1] "
              "\"rgb sigma_a\" [1 1 1] \"rgb sigma_s\" [1 1 1] "
              "\"point3 p0\" [-4 -4 -4] \"point3 p1\" [4 4 4]",
              &m);
  // Well inside the outer samples the trilinear density is exactly 1; sigma_t = 2.
  RngSampler s(3);
  Ray r{{-1, 0, 0}, {1, 0, 0}, 1.5f};
  const int n = 100000;
  double sum = 0, sum2 = 0;
  for (int i = 0; i < n; ++i) {
    double t = m.media.tr(0, r, s).r;
    ASSERT_GE(t, 0);
    sum += t;
    sum2 += t * t;
  }
  double mean = sum / n, sd = std::sqrt((sum2 / n - mean * mean) / n);
  EXPECT_NEAR(mean, std::exp(-3.0), 4 * sd + 1e-6);
}

// Density x along a ray from x = a to x = b: transmittance exp(-sigma_t (b^2 - a^2) / 2).
// Delta tracking must reach b with that probability; ratio tracking must average to it.
TEST(Media, TrackingMatchesTheLinearRampAnalytically) {
  LoadedMedia m;
  load_medium("medium_ramp", ramp_grid(64) + " \"rgb sigma_a\" [1 1 1] \"rgb sigma_s\" [2 2 2]",
              &m);
  const float a = 0.1f, b = 0.9f, sigma_t = 3;
  const double expected = std::exp(-sigma_t * (b * b - a * a) / 2);
  Ray r{{a, 0.5f, 0.5f}, {b - a, 0, 0}, 1.f};
  RngSampler s(4);
  const int n = 200000;
  int passed = 0;
  double ratio = 0, mean_hit = 0;
  int hits = 0;
  for (int i = 0; i < n; ++i) {
    bool scattered;
    Vec3 p;
    Rgb w = m.media.sample(0, r, s, &scattered, &p);
    if (scattered) {
      EXPECT_FLOAT_EQ(w.r, 2.f / 3.f);  // albedo
      mean_hit += p.x;
      ++hits;
    } else {
      EXPECT_EQ(w, Rgb(1.f));
      ++passed;
    }
    ratio += m.media.tr(0, r, s).r;
  }
  const double sd = std::sqrt(expected * (1 - expected) / n);
  EXPECT_NEAR(double(passed) / n, expected, 4 * sd);
  EXPECT_NEAR(ratio / n, expected, 4 * sd);
  // Where the collisions fall: density sigma_t x exp(-sigma_t (x^2 - a^2) / 2) on [a, b],
  // normalised by 1 - expected; its mean by the midpoint rule.
  double num = 0, den = 0;
  for (int k = 0; k < 100000; ++k) {
    double x = a + (k + 0.5) * (b - a) / 100000;
    double f = sigma_t * x * std::exp(-sigma_t * (x * x - a * a) / 2);
    num += x * f;
    den += f;
  }
  EXPECT_NEAR(mean_hit / hits, num / den, 0.005);
}

// A grid medium over density (nx * ny * nz samples, x fastest), as MediumSet builds one.
Medium grid_medium(const std::vector<float>& density, int nx, int ny, int nz) {
  Medium m;
  m.kind = MediumKind::kGrid;
  m.density = density.data();
  m.nx = nx;
  m.ny = ny;
  m.nz = nz;
  return m;
}

// pbrt-v3's GridDensityMedium::Density, written out: trilinear between samples at
// (i + 1/2) / n, zero outside the grid's samples.
float reference_density(const std::vector<float>& g, int nx, int ny, int nz, Vec3 p) {
  const float x = p.x * float(nx) - 0.5f, y = p.y * float(ny) - 0.5f, z = p.z * float(nz) - 0.5f;
  const int ix = int(std::floor(x)), iy = int(std::floor(y)), iz = int(std::floor(z));
  const float dx = x - std::floor(x), dy = y - std::floor(y), dz = z - std::floor(z);
  auto d = [&](int i, int j, int k) {
    if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz) return 0.f;
    return g[size_t((k * ny + j) * nx + i)];
  };
  auto lerp1 = [](float t, float a, float b) { return (1 - t) * a + t * b; };
  const float d00 = lerp1(dx, d(ix, iy, iz), d(ix + 1, iy, iz));
  const float d10 = lerp1(dx, d(ix, iy + 1, iz), d(ix + 1, iy + 1, iz));
  const float d01 = lerp1(dx, d(ix, iy, iz + 1), d(ix + 1, iy, iz + 1));
  const float d11 = lerp1(dx, d(ix, iy + 1, iz + 1), d(ix + 1, iy + 1, iz + 1));
  return lerp1(dz, lerp1(dy, d00, d10), lerp1(dy, d01, d11));
}

// Inside the grid and at its edges, on sample positions and cell boundaries and beyond the
// samples, density_at is pbrt-v3's lookup bit for bit.
TEST(Media, GridDensityIsTrilinearBitForBit) {
  const int nx = 11, ny = 6, nz = 4;
  std::vector<float> density(size_t(nx * ny * nz));
  Rng rng(11);
  for (float& d : density) d = rng.next_float() * 3;
  Medium m = grid_medium(density, nx, ny, nz);
  std::vector<Vec3> points;
  for (int i = 0; i < 20000; ++i)
    points.push_back({rng.next_float() * 1.2f - 0.1f, rng.next_float() * 1.2f - 0.1f,
                      rng.next_float() * 1.2f - 0.1f});
  for (int i = 0; i <= 2 * nx; ++i)  // samples (odd i) and cell boundaries (even i) along x
    for (int j = 0; j <= 2 * ny; ++j)
      points.push_back({float(i) / float(2 * nx), float(j) / float(2 * ny), 0.5f});
  int inside = 0;
  for (Vec3 p : points) {
    const float want = reference_density(density, nx, ny, nz, p);
    const float got = m.density_at(p);
    ASSERT_EQ(std::memcmp(&want, &got, sizeof(float)), 0)
        << "at (" << p.x << ", " << p.y << ", " << p.z << "): " << got << " against " << want;
    inside += want > 0;
  }
  EXPECT_GT(inside, 10000);
}

// The majorant of every cell a ray crosses bounds the density at every point of the crossing;
// the walk covers the ray's interval without gaps, in order.
TEST(MajorantGrid, BoundsTheDensityAlongRandomRays) {
  const int nx = 13, ny = 7, nz = 5;
  std::vector<float> density(size_t(nx * ny * nz));
  Rng rng(7);
  for (float& d : density) d = rng.next_float() < 0.3f ? 0 : rng.next_float() * 5;
  Medium m = grid_medium(density, nx, ny, nz);
  m.majorants.build(density.data(), nx, ny, nz, 4);
  EXPECT_EQ(m.majorants.cells(), 4 * 2 * 2);
  for (int i = 0; i < 2000; ++i) {
    Vec3 o{rng.next_float(), rng.next_float(), rng.next_float()};
    Vec3 d =
        normalize(Vec3{rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f});
    // Where the ray leaves the unit cube.
    float t1 = kInfinity;
    for (int ax = 0; ax < 3; ++ax)
      if (d[ax] != 0) t1 = std::min(t1, ((d[ax] > 0 ? 1 : 0) - o[ax]) / d[ax]);
    float covered = 0;
    m.majorants.walk(o, d, 0, t1, [&](float a, float b, float majorant) {
      EXPECT_GE(a, covered - 1e-5f);
      covered = b;
      for (int k = 0; k < 16; ++k) {
        float t = a + (b - a) * (k + 0.5f) / 16;
        EXPECT_LE(m.density_at(o + d * t), majorant * (1 + 1e-6f));
      }
      return false;
    });
  }
}

}  // namespace
}  // namespace rt
