#include "sim/core/stats.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "sim/core/rng.h"

namespace fovsim {
namespace {

TEST(BatchMeans, HandComputedExample) {
  // 0..19: 10 batches of 2, batch means 0.5, 2.5, ..., 18.5; their variance is 4 * var(0..9)
  // = 4 * 55/6, so the variance of the grand mean is (4 * 55/6) / 10.
  std::vector<double> x;
  for (int i = 0; i < 20; ++i) x.push_back(i);
  MeanInterval r = batch_means_interval(x);
  EXPECT_DOUBLE_EQ(r.mean, 9.5);
  EXPECT_EQ(r.batch_size, 2u);
  EXPECT_NEAR(r.half_width, kCiT975 * std::sqrt(4.0 * 55.0 / 6.0 / 10.0), 1e-12);
  EXPECT_NEAR(r.lo(), 9.5 - r.half_width, 1e-12);
}

TEST(BatchMeans, UndefinedBelowMinimumOrNonFinite) {
  std::vector<double> x(kCiMinSamples - 1, 1.0);
  MeanInterval r = batch_means_interval(x);
  EXPECT_DOUBLE_EQ(r.mean, 1.0);
  EXPECT_TRUE(std::isnan(r.half_width));
  EXPECT_TRUE(std::isnan(batch_means_interval({}).mean));
  x.push_back(1.0);
  EXPECT_DOUBLE_EQ(batch_means_interval(x).half_width, 0.0);  // constant series: exact
  x.back() = INFINITY;
  EXPECT_TRUE(std::isnan(batch_means_interval(x).half_width));
}

TEST(BatchMeans, RemainderUsesAllValuesForTheMean) {
  std::vector<double> x(25, 0.0);
  x.back() = 25.0;  // outside the 10 x 2 batches
  MeanInterval r = batch_means_interval(x);
  EXPECT_DOUBLE_EQ(r.mean, 1.0);
  EXPECT_EQ(r.batch_size, 2u);
  EXPECT_DOUBLE_EQ(r.half_width, 0.0);
}

// Coverage on AR(1) series x_t = mu + phi (x_{t-1} - mu) + e_t, e_t ~ N(0, 1), started in the
// stationary distribution so E[x_t] = mu exactly. Correlation time (1 + phi) / (1 - phi) is 19
// frames at phi = 0.9; with n = 4000, batches of 400 frames leave a variance bias of ~2%
// (Law and Kelton §9.5.3), i.e. a nominal coverage of ~94.7%. R = 2000 replications per phi:
// the binomial standard deviation at p = 0.95 is sqrt(0.95 * 0.05 / 2000) = 0.49%, so the
// accepted band [93%, 97%] is ±4.1 sigma around 95% (a false failure has probability ~1e-4 over
// the three phi even if the RNG stream changed). Runtime: 24M normal draws, well under 2 s.
TEST(BatchMeans, CoverageOnAr1SeriesIsNominal) {
  const int R = 2000;
  const size_t n = 4000;
  const double mu = 3.0;
  for (double phi : {0.0, 0.5, 0.9}) {
    Rng rng(12345, uint64_t(phi * 100) + 7);
    int covered = 0;
    std::vector<double> x(n);
    for (int rep = 0; rep < R; ++rep) {
      double d = rng.normal() / std::sqrt(1.0 - phi * phi);
      for (size_t t = 0; t < n; ++t) {
        if (t) d = phi * d + rng.normal();
        x[t] = mu + d;
      }
      MeanInterval r = batch_means_interval(x);
      covered += (r.lo() <= mu && mu <= r.hi());
    }
    double cov = double(covered) / R;
    std::printf("AR(1) phi %.1f: coverage %.4f over %d series of %zu\n", phi, cov, R, n);
    EXPECT_GE(cov, 0.93) << "phi " << phi;
    EXPECT_LE(cov, 0.97) << "phi " << phi;
  }
}

// The naive iid interval (batch size 1) undercovers on correlated frames; batch means must not.
TEST(BatchMeans, WiderThanIidIntervalOnCorrelatedSeries) {
  Rng rng(9);
  std::vector<double> x(2000);
  double d = 0;
  for (auto& v : x) v = d = 0.9 * d + rng.normal();
  double mean = 0, ss = 0;
  for (double v : x) mean += v / double(x.size());
  for (double v : x) ss += (v - mean) * (v - mean);
  double iid_hw = 1.96 * std::sqrt(ss / double(x.size() - 1) / double(x.size()));
  EXPECT_GT(batch_means_interval(x).half_width, 2.0 * iid_hw);  // sqrt(19) ~ 4.4 in theory
}

}  // namespace
}  // namespace fovsim

namespace fovsim {
namespace {

TEST(ShortRunInterval, DefinedFromEightToNineteenValuesWithItsReason) {
  std::vector<double> x = {1, 3, 2, 4, 3, 5, 4, 6};  // n = 8
  MeanInterval r = mean_interval(x);
  EXPECT_EQ(r.kind, IntervalKind::short_run);
  EXPECT_TRUE(r.why.empty());
  EXPECT_DOUBLE_EQ(r.mean, 3.5);
  EXPECT_GT(r.half_width, 0);
  EXPECT_GE(r.n_eff, 2.0);
  EXPECT_LE(r.n_eff, 8.0);
  x.pop_back();  // 7 values: undefined, and says why
  r = mean_interval(x);
  EXPECT_EQ(r.kind, IntervalKind::none);
  EXPECT_TRUE(std::isnan(r.half_width));
  EXPECT_EQ(r.why, "7 finite frames (an interval needs >= 8)");
  EXPECT_EQ(mean_interval({}).why, "no finite frames");
  // From 20 values on: batch means.
  std::vector<double> y(20);
  for (int i = 0; i < 20; ++i) y[size_t(i)] = i % 3;
  EXPECT_EQ(mean_interval(y).kind, IntervalKind::batch_means);
  EXPECT_EQ(batch_means_interval(x).why, "7 finite frames (batch means needs >= 20)");
  // A constant short series is exact.
  EXPECT_DOUBLE_EQ(mean_interval(std::vector<double>(12, 2.5)).half_width, 0.0);
}

TEST(ShortRunInterval, IidFormulaWhenTheSeriesAlternates) {
  // Strongly negative lag-1 autocorrelation is clamped to 0: n_eff = n, the i.i.d. t-interval.
  std::vector<double> x;
  for (int i = 0; i < 10; ++i) x.push_back(i % 2 ? 1.0 : -1.0);
  MeanInterval r = short_run_interval(x);
  EXPECT_DOUBLE_EQ(r.n_eff, 10.0);
  const double s = std::sqrt(10.0 / 9.0);
  EXPECT_NEAR(r.half_width, 2.262157163 * s / std::sqrt(10.0), 1e-9);
}

// Coverage of the short-run interval on stationary AR(1) series of 12 values (R = 2000 each):
// nominal for independent frames, ~90% at phi = 0.5, and it undercovers at phi = 0.9 — the
// caveat docs/intervals.md states (measured there: phi 0 96%, 0.5 90%, 0.9 ~80%).
TEST(ShortRunInterval, CoverageOnShortAr1Series) {
  const int R = 2000;
  const size_t n = 12;
  for (double phi : {0.0, 0.5, 0.9}) {
    Rng rng(777, uint64_t(phi * 100) + 3);
    int covered = 0;
    std::vector<double> x(n);
    for (int rep = 0; rep < R; ++rep) {
      double d = rng.normal() / std::sqrt(1.0 - phi * phi);
      for (size_t t = 0; t < n; ++t) {
        if (t) d = phi * d + rng.normal();
        x[t] = d;
      }
      MeanInterval r = short_run_interval(x);
      covered += (r.lo() <= 0 && 0 <= r.hi());
    }
    const double cov = double(covered) / R;
    std::printf("short-run AR(1) phi %.1f n %zu: coverage %.4f\n", phi, n, cov);
    if (phi == 0.0) {
      EXPECT_GE(cov, 0.93);
      EXPECT_LE(cov, 0.985);
    } else if (phi == 0.5) {
      EXPECT_GE(cov, 0.86);
    } else {
      EXPECT_GE(cov, 0.70);
      EXPECT_LT(cov, 0.93);  // the stated undercoverage
    }
  }
}

}  // namespace
}  // namespace fovsim
