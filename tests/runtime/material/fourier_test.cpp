// tests/runtime/material/fourier_test.cpp — the fourier material's lobe on pbrt-v3's real
// roughgold table (dragon scene), compiled from scene text.
//
// f() on table nodes (where the Catmull-Rom weights are 1 and 0) against the series summed here
// from the file's raw numbers; reciprocity, which layerlab's tables keep; sample_f against
// pdf() by chi-square and by the shared lobe checks; the albedo below 1; and the radiance
// scaling of transmission, on a one-pair table built by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "chi2_directions.h"
#include "lobe_checks.h"
#include "runtime/core/rng.h"
#include "runtime/material/fourier_bxdf.h"
#include "runtime/material/fourier_interpolation.h"
#include "runtime/runtime_test_support.h"
#include "test_support.h"

namespace rt {
namespace {

std::string gold_path() {
  return testing_support::shared_dir() +
         "/scenes/hm-materials-partial/pbrt-v3-scenes/dragon/bsdfs/roughgold_alpha_0.2.bsdf";
}

// The file's numbers, read here independently of pbrtc: header fields at their byte offsets,
// then mu, cdf, (offset, length) pairs and coefficients.
struct RawFile {
  std::string bytes;
  int n = 0, n_coeffs = 0, m_max = 0, channels = 0;
  float word_f(size_t i) const {
    float f;
    std::memcpy(&f, bytes.data() + 4 * i, 4);
    return f;
  }
  int32_t word_i(size_t i) const {
    int32_t v;
    std::memcpy(&v, bytes.data() + 4 * i, 4);
    return v;
  }
  explicit RawFile(const std::string& path) : bytes(testing_support::read_file(path)) {
    n = word_i(3);
    n_coeffs = word_i(4);
    m_max = word_i(5);
    channels = word_i(6);
  }
  float mu(int i) const { return word_f(16 + size_t(i)); }
  size_t pair_word(int i, int o) const {
    return 16 + size_t(n) + size_t(n) * n + 2 * (size_t(o) * n + size_t(i));
  }
  int offset(int i, int o) const { return word_i(pair_word(i, o)); }
  int length(int i, int o) const { return word_i(pair_word(i, o) + 1); }
  float coeff(int k) const { return word_f(16 + size_t(n) + 3 * size_t(n) * n + size_t(k)); }
  // sum_k a_k cos(k phi) for channel c of node pair (i, o).
  double series(int i, int o, int c, double phi) const {
    double sum = 0;
    int m = length(i, o);
    for (int k = 0; k < m; ++k) sum += coeff(offset(i, o) + c * m + k) * std::cos(k * phi);
    return sum;
  }
};

class FourierGold : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string dir = testing_support::scratch_dir("fourier_gold");
    ASSERT_TRUE(testing_support::compile_text(
        dir,
        "Camera \"perspective\"\nWorldBegin\nMaterial \"fourier\" \"string bsdffile\" \"" +
            gold_path() + "\"\nShape \"sphere\"\nWorldEnd\n",
        &archive_));
    uint32_t entity = pbrta::kNoIndex;
    for (const pbrta::MaterialRecord& m : archive_.materials)
      if (archive_.type_name(m.entity) == "fourier") entity = m.entity;
    ASSERT_NE(entity, pbrta::kNoIndex);
    std::string error;
    ASSERT_TRUE(build_fourier_table(archive_, entity, &table_, &error)) << error;
    lobe_.table = &table_;
  }
  pbrta::SceneArchive archive_;
  FourierTable table_;
  FourierLobe lobe_;
};

TEST_F(FourierGold, TableViewsTheArchiveWithTheFilesShape) {
  RawFile raw(gold_path());
  EXPECT_EQ(table_.n_mu, 58);
  EXPECT_EQ(raw.n, 58);
  EXPECT_EQ(table_.m_max, 172);
  EXPECT_EQ(table_.channels, 3);
  EXPECT_EQ(table_.eta, 1.f);
  // In place: the arrays point into the archive's words.
  const char* words = reinterpret_cast<const char*>(archive_.words.data);
  const char* words_end = words + 4 * size_t(archive_.words.size);
  EXPECT_GE(reinterpret_cast<const char*>(table_.coeffs), words);
  EXPECT_LT(reinterpret_cast<const char*>(table_.coeffs), words_end);
  for (int i : {0, 13, 28, 29, 57}) EXPECT_EQ(table_.mu[i], raw.mu(i)) << i;
  EXPECT_EQ(table_.coeffs[raw.n_coeffs - 1], raw.coeff(raw.n_coeffs - 1));
  int m;
  const float* s = table_.series(20, 40, &m);
  EXPECT_EQ(m, raw.length(20, 40));
  EXPECT_EQ(s[0], raw.coeff(raw.offset(20, 40)));
  EXPECT_EQ(table_.a0[40 * 58 + 20], raw.coeff(raw.offset(20, 40)));
  EXPECT_EQ(lobe_.flags, kReflection | kTransmission | kGlossy);
}

// Directions with exactly the node cosines: mu_o = wo.z, mu_i = -wi.z, azimuth phi between -wi
// and wo.
void node_directions(float mu_i, float mu_o, double phi, Vec3* wo, Vec3* wi) {
  float so = std::sqrt(std::max(0.f, 1 - mu_o * mu_o));
  float si = std::sqrt(std::max(0.f, 1 - mu_i * mu_i));
  *wo = {so, 0, mu_o};
  *wi = {-si * float(std::cos(phi)), -si * float(std::sin(phi)), -mu_i};
}

TEST_F(FourierGold, OnTableNodesFIsTheFilesSeriesOverMuI) {
  RawFile raw(gold_path());
  int checked = 0;
  // Reflection: mu_i < 0 < mu_o. Node 28 (0) is skipped: 1/|mu_i| is infinite there.
  for (int i : {3, 12, 20, 27})
    for (int o : {31, 40, 47, 55})
      for (double phi : {0.0, 0.35, 1.3, 2.9}) {
        Vec3 wo, wi;
        node_directions(raw.mu(i), raw.mu(o), phi, &wo, &wi);
        double y = raw.series(i, o, 0, phi), r = raw.series(i, o, 1, phi),
               b = raw.series(i, o, 2, phi);
        // pbrt-v3's green from luminance, red and blue.
        double g = 1.39829 * y - 0.100913 * b - 0.297375 * r;
        double scale = 1 / std::fabs(double(raw.mu(i)));
        Rgb f = lobe_.f(wo, wi);
        double want[3] = {std::max(0.0, r * scale), std::max(0.0, g * scale),
                          std::max(0.0, b * scale)};
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(f[c], want[c], 2e-4 * std::max(1.0, want[c]))
              << "nodes " << i << "," << o << " phi " << phi << " channel " << c;
        if (y > 1e-3) ++checked;
      }
  EXPECT_GT(checked, 20);  // most of these pairs reflect visibly
}

TEST_F(FourierGold, PureReflectionAndReciprocity) {
  // eta 1 and no transmission series: light never crosses.
  Vec3 wo = normalize(Vec3{0.3f, -0.2f, 0.7f});
  EXPECT_TRUE(lobe_.f(wo, normalize(Vec3{0.1f, 0.2f, -0.6f})).is_black());
  // On nodes the table is reciprocal to float precision: f(wo, wi) = f(wi, wo).
  RawFile raw(gold_path());
  for (int i : {5, 18, 26})
    for (int o : {33, 44, 52}) {
      Vec3 a, b;
      node_directions(raw.mu(i), raw.mu(o), 0.4, &a, &b);
      Rgb f_ab = lobe_.f(a, b), f_ba = lobe_.f(b, a);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(f_ab[c], f_ba[c], 1e-4 * std::max(1.f, f_ab[c])) << i << "," << o;
    }
  // Between nodes, as well as the splines interpolate it: they interpolate the series, which
  // hold f |mu_i|, so near grazing the 1 / |mu_i| makes f(a, b) and f(b, a) differ by several
  // percent; away from it they agree closely (measured: 1.3e-4 for cosines above 0.3).
  Rng rng(3);
  double diff = 0, sum = 0;
  for (int n = 0; n < 4000; ++n) {
    Vec3 a = uniform_sample_hemisphere({rng.next_float(), rng.next_float()});
    Vec3 b = uniform_sample_hemisphere({rng.next_float(), rng.next_float()});
    if (a.z < 0.3f || b.z < 0.3f) continue;
    Rgb f_ab = lobe_.f(a, b), f_ba = lobe_.f(b, a);
    diff += std::fabs(f_ab.g - f_ba.g);
    sum += 0.5 * (f_ab.g + f_ba.g);
  }
  std::printf("off-node reciprocity: mean |f(a,b) - f(b,a)| / mean f = %g\n", diff / sum);
  EXPECT_LT(diff / sum, 1e-3);
}

const Vec3 kOutgoing[] = {
    normalize(Vec3{0.3f, -0.2f, 0.93f}),
    normalize(Vec3{0.8f, 0.1f, 0.4f}),
    normalize(Vec3{-0.5f, 0.6f, 0.2f}),
    Vec3{0, 0, 1},
};

TEST_F(FourierGold, SamplingMatchesPdfByChiSquare) {
  const double kLevel = 1e-3 / std::size(kOutgoing);
  uint64_t seed = 11;
  for (Vec3 wo : kOutgoing) {
    auto sample = [&](Vec2 u, Vec3* wi) {
      float pdf;
      Rgb f = lobe_.sample_f(wo, wi, u, &pdf);
      return pdf > 0 && !f.is_black();
    };
    auto pdf = [&](Vec3 wi) { return double(lobe_.pdf(wo, wi)); };
    auto r = material_test::chi2_directions(sample, pdf, 200000, seed++);
    EXPECT_GT(r.p_value, kLevel) << "wo.z=" << wo.z << ": " << r.message;
    EXPECT_LT(r.total_mass_error, 5e-3 + 4 * r.total_mass_sigma)
        << "wo.z=" << wo.z << ": " << r.message;
  }
}

TEST_F(FourierGold, SampleAgreesWithEvaluationAndAlbedoIsBelowOne) {
  Rng rng(5);
  for (Vec3 wo : kOutgoing) {
    material_test::expect_sample_matches_evaluation(lobe_, wo, 2000, rng, "fourier gold");
    double albedo =
        material_test::expect_albedo_estimates_agree(lobe_, wo, 200000, 17, "fourier gold");
    // Rough gold reflects most green light, never more than arrives.
    EXPECT_GT(albedo, 0.3) << wo.z;
    EXPECT_LE(albedo, 1.0) << wo.z;
  }
}

TEST_F(FourierGold, IncomingCosineOutsideTheTableGivesNothing) {
  Vec3 wo = normalize(Vec3{0.3f, -0.2f, 0.7f});
  Vec3 wi;
  float pdf = 1;
  // wo.z slightly above 1 (an unnormalised vector) lies outside the nodes.
  EXPECT_TRUE(lobe_.sample_f({0, 0, 1.0001f}, &wi, {0.3f, 0.6f}, &pdf).is_black());
  EXPECT_EQ(pdf, 0.f);
  EXPECT_EQ(lobe_.pdf({0, 0, 1.0001f}, normalize(Vec3{0.1f, 0.1f, 1})), 0.f);
  EXPECT_TRUE(lobe_.f(wo, {0, 0, 1.0001f}).is_black());
}

// A hand-made one-channel table, two nodes per hemisphere and constant series: transmission
// in radiance mode is scaled by 1/eta^2 for mu_i > 0 and by eta^2 for mu_i < 0.
TEST(FourierLobe, RadianceScalingOfTransmissionFollowsEta) {
  std::vector<float> mu = {-1, -0.5f, 0.5f, 1};
  std::vector<float> cdf(16, 0.f);
  std::vector<int32_t> offsets(32);
  std::vector<float> coeffs(16);
  for (int p = 0; p < 16; ++p) {
    offsets[2 * p] = p;
    offsets[2 * p + 1] = 1;
    coeffs[p] = 0.25f;
  }
  pbrta::FourierTableView v;
  v.eta = 1.5f;
  v.m_max = 1;
  v.channels = 1;
  v.mu = mu.data();
  v.cdf = cdf.data();
  v.offsets = offsets.data();
  v.coeffs = coeffs.data();
  v.n_mu = 4;
  v.n_cdf = 16;
  v.n_offsets = 32;
  v.n_coeffs = 16;
  std::string error;
  ASSERT_TRUE(pbrta::check_fourier_table(v, &error)) << error;
  FourierTable t;
  make_fourier_table(v, &t);
  FourierLobe radiance{&t, TransportMode::kRadiance};
  FourierLobe importance{&t, TransportMode::kImportance};
  Vec3 up = normalize(Vec3{0.6f, 0, 0.8f}), down = normalize(Vec3{0, 0.6f, -0.8f});
  // wo up, wi down: mu_i = -wi.z = 0.8 > 0, mu_o = 0.8: value 0.25 / 0.8, times 1/eta^2.
  EXPECT_NEAR(importance.f(up, down).g, 0.25f / 0.8f, 1e-5f);
  EXPECT_NEAR(radiance.f(up, down).g, 0.25f / 0.8f / (1.5f * 1.5f), 1e-5f);
  // wo down, wi up: mu_i = -0.8, mu_o = -0.8: times eta^2.
  EXPECT_NEAR(radiance.f(down, up).g, 0.25f / 0.8f * (1.5f * 1.5f), 1e-5f);
  // Reflection is never scaled.
  Vec3 up2 = normalize(Vec3{0, -0.6f, 0.8f});
  EXPECT_NEAR(radiance.f(up, up2).g, 0.25f / 0.8f, 1e-5f);
}

TEST(FourierInterpolation, CatmullRomWeightsReproduceCubicsAndHitNodes) {
  const float nodes[] = {-1, -0.6f, -0.1f, 0.3f, 1};
  int offset;
  float w[4];
  // On a node: weight 1 there, 0 elsewhere.
  ASSERT_TRUE(catmull_rom_weights(5, nodes, -0.1f, &offset, w));
  EXPECT_EQ(offset, 1);
  EXPECT_FLOAT_EQ(w[1], 1);
  EXPECT_FLOAT_EQ(w[0] + w[2] + w[3], 0);
  // Weights sum to 1 and reproduce a linear function exactly (finite-difference tangents are
  // exact for lines).
  for (float x : {-0.95f, -0.3f, 0.1f, 0.77f}) {
    ASSERT_TRUE(catmull_rom_weights(5, nodes, x, &offset, w));
    float sum = 0, line = 0;
    for (int k = 0; k < 4; ++k)
      if (w[k] != 0) {
        sum += w[k];
        line += w[k] * (2 * nodes[offset + k] - 1);
      }
    EXPECT_NEAR(sum, 1, 1e-6f) << x;
    EXPECT_NEAR(line, 2 * x - 1, 1e-5f) << x;
  }
  EXPECT_FALSE(catmull_rom_weights(5, nodes, 1.01f, &offset, w));
}

TEST(FourierInterpolation, SampleFourierFollowsTheSeries) {
  // 1 + 0.5 cos(phi) + 0.2 cos(2 phi): the sample's density is the series over its integral.
  const float ak[] = {1, 0.5f, 0.2f};
  const float recip[] = {0, 1, 0.5f};
  Rng rng(9);
  const int kBins = 16, kN = 200000;
  std::vector<int> hist(kBins, 0);
  for (int i = 0; i < kN; ++i) {
    float pdf, phi;
    float f = sample_fourier(ak, recip, 3, rng.next_float(), &pdf, &phi);
    ASSERT_GE(phi, 0.f);
    ASSERT_LT(phi, 2 * kPi + 1e-5f);
    double want = 1 + 0.5 * std::cos(phi) + 0.2 * std::cos(2 * phi);
    ASSERT_NEAR(f, want, 1e-4);
    ASSERT_NEAR(pdf, want / (2 * M_PI), 1e-4);
    hist[std::min(kBins - 1, int(phi / (2 * M_PI) * kBins))]++;
  }
  for (int b = 0; b < kBins; ++b) {
    double a0 = 2 * M_PI * b / kBins, a1 = 2 * M_PI * (b + 1) / kBins;
    double mass = ((a1 - a0) + 0.5 * (std::sin(a1) - std::sin(a0)) +
                   0.1 * (std::sin(2 * a1) - std::sin(2 * a0))) /
                  (2 * M_PI);
    double sigma = std::sqrt(kN * mass * (1 - mass));
    EXPECT_NEAR(hist[b], kN * mass, 5 * sigma) << b;
  }
}

}  // namespace
}  // namespace rt
