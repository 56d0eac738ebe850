// Distribution1D's two-step search (a coarse table, then one cache line of the cdf) must not
// change any result: every bucket, pmf, pdf and remapped value equals a plain binary search
// over the cdf. Distribution2D's rows must sample as Distribution1Ds over them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "runtime/core/rng.h"
#include "runtime/core/sampling.h"

namespace rt {
namespace {

// The reference: last i with cdf[i] <= u, clamped to a bucket.
int reference_bucket(const std::vector<float>& cdf, float u) {
  int n = int(cdf.size()) - 1;
  int i = int(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin()) - 1;
  return clamp(i, 0, n - 1);
}

TEST(DistributionSearch, SameBucketsAsFullSearch) {
  Rng rng(5);
  for (int trial = 0; trial < 60; ++trial) {
    int n = 1 + int(rng.next_u32(trial < 30 ? 40 : 3000));
    std::vector<float> f(static_cast<size_t>(n), 0.f);
    for (float& v : f) {
      float r = rng.next_float();
      // Runs of zeros and rare spikes make cutpoints cluster and gaps wide.
      v = r < 0.4f ? 0.f : (r > 0.98f ? 1000 * r : r);
    }
    if (trial % 10 == 0) std::fill(f.begin(), f.end(), 0.f);
    Distribution1D d(f.data(), n);
    // The cdf as the constructor computes it.
    std::vector<float> cdf(size_t(n) + 1, 0.f);
    for (int i = 1; i <= n; ++i) cdf[i] = cdf[i - 1] + std::fabs(f[i - 1]) / n;
    float integral = cdf[n];
    for (int i = 1; i <= n; ++i) cdf[i] = integral == 0 ? float(i) / n : cdf[i] / integral;

    std::vector<float> us;
    for (int k = 0; k < 3000; ++k) us.push_back(rng.next_float());
    for (int j = 0; j <= n; ++j) {  // cutpoints and their neighbours
      float t = float(j) / float(n);
      for (float u : {t, std::nextafter(t, 0.f), std::nextafter(t, 1.f)})
        if (u >= 0 && u < 1) us.push_back(u);
    }
    for (float c : cdf)
      for (float u : {c, std::nextafter(c, 0.f), std::nextafter(c, 1.f)})
        if (u >= 0 && u < 1) us.push_back(u);
    for (float u : us) {
      int expect = reference_bucket(cdf, u);
      float pmf, remapped, pdf;
      ASSERT_EQ(d.sample_discrete(u, &pmf, &remapped), expect) << "n " << n << " u " << u;
      int off = -1;
      d.sample_continuous(u, &pdf, &off);
      ASSERT_EQ(off, expect) << "n " << n << " u " << u;
      ASSERT_EQ(pmf, d.discrete_pdf(expect));
      // u rescaled within its bucket of the cdf built above.
      const float w = cdf[size_t(expect) + 1] - cdf[size_t(expect)];
      ASSERT_EQ(remapped, w > 0 ? std::min((u - cdf[size_t(expect)]) / w, kOneMinusEpsilon) : 0)
          << "n " << n << " u " << u;
    }
  }
}

}  // namespace
}  // namespace rt

namespace rt {
namespace {

// A distribution owns its values, and so do its copies and moves.
TEST(Distribution1D, CopiesOwnTheirValues) {
  std::vector<float> f = {1, 3, 0, 4};
  Distribution1D owned(f.data(), 4);
  Distribution1D owned_copy, moved;
  {
    Distribution1D a = owned, b = owned;
    owned_copy = a;  // outlives its source
    moved = std::move(b);
  }
  EXPECT_NE(owned.func_data(), f.data());
  for (const Distribution1D* d : {&owned_copy, &moved}) {
    EXPECT_NE(d->func_data(), owned.func_data());
    for (int i = 0; i < 4; ++i) EXPECT_EQ(d->value(i), f[i]);
    float pmf = 0, expect_pmf = 0;
    EXPECT_EQ(d->sample_discrete(0.3f, &pmf), owned.sample_discrete(0.3f, &expect_pmf));
    EXPECT_EQ(pmf, expect_pmf);
  }
  f[1] = 7;
  EXPECT_EQ(owned.value(1), 3);
  EXPECT_EQ(owned_copy.value(1), 3);
  EXPECT_EQ(moved.value(1), 3);
}

}  // namespace
}  // namespace rt

namespace rt {
namespace {

// Distribution2D keeps its rows in flat arrays; each row must sample exactly as a
// Distribution1D over that row does (bucket, position and pdf), after the marginal over the
// rows' integrals has chosen it. Rows of zeros, spikes and a copy (which must own its values)
// included.
TEST(Distribution2D, EachRowSamplesAsItsOwnDistribution1D) {
  Rng rng(11);
  for (int trial = 0; trial < 12; ++trial) {
    const int nu = 1 + int(rng.next_u32(trial < 6 ? 20 : 300));
    const int nv = 1 + int(rng.next_u32(40));
    std::vector<float> f(size_t(nu) * nv);
    for (float& x : f) {
      float r = rng.next_float();
      x = r < 0.3f ? 0.f : (r > 0.97f ? 500 * r : r);
    }
    for (int u = 0; u < nu; ++u) f[u] = 0;  // a dark first row
    std::vector<Distribution1D> rows;
    std::vector<float> integrals;
    for (int v = 0; v < nv; ++v) {
      rows.emplace_back(f.data() + size_t(v) * nu, nu);
      integrals.push_back(rows.back().integral());
    }
    Distribution1D marginal(integrals.data(), nv);
    Distribution2D original(f.data(), nu, nv), viewed(f.data(), nu, nv, true);
    Distribution2D copied = original;
    original = Distribution2D();  // the copy must not read the original's values
    for (int k = 0; k < 2000; ++k) {
      const Vec2 u{rng.next_float(), rng.next_float()};
      float pdf_v = 0, pdf_u = 0;
      int v = -1;
      const float y = marginal.sample_continuous(u.y, &pdf_v, &v);
      const float x = rows[size_t(v)].sample_continuous(u.x, &pdf_u);
      for (const Distribution2D* d : {&copied, &viewed}) {
        float pdf = -1;
        const Vec2 p = d->sample_continuous(u, &pdf);
        ASSERT_EQ(p.x, x) << "trial " << trial << " u " << u.x << " " << u.y;
        ASSERT_EQ(p.y, y);
        ASSERT_EQ(pdf, pdf_u * pdf_v);
        // pdf(p) is the cell's value over the whole integral.
        const int iu = clamp(int(p.x * nu), 0, nu - 1), iv = clamp(int(p.y * nv), 0, nv - 1);
        const float expect =
            marginal.integral() == 0 ? 0 : f[size_t(iv) * nu + iu] / marginal.integral();
        ASSERT_EQ(d->pdf(p), expect);
      }
    }
  }
}

}  // namespace
}  // namespace rt
