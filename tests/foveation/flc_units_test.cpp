// FLC building blocks (Yang et al. 2021 §4-§5): Halton, Algorithm 1, acuity (eqs. 3-6), eq. 7,
// BLSO's eq. 12, contribution (eq. 14) and stochastic culling.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "sim/core/error.h"
#include "sim/core/rng.h"
#include "sim/foveation/flc_contribution.h"
#include "sim/foveation/flc_importance.h"
#include "sim/foveation/flc_sampling.h"

using namespace fovsim;

TEST(FlcHalton, RadicalInverseValues) {
  EXPECT_DOUBLE_EQ(radical_inverse(1, 2), 0.5);
  EXPECT_DOUBLE_EQ(radical_inverse(2, 2), 0.25);
  EXPECT_DOUBLE_EQ(radical_inverse(3, 2), 0.75);
  EXPECT_NEAR(radical_inverse(1, 3), 1.0 / 3.0, 1e-15);
  EXPECT_NEAR(radical_inverse(5, 3), 2.0 / 3.0 + 1.0 / 9.0, 1e-15);  // 5 = 12 in base 3
  EXPECT_EQ(radical_inverse(0, 2), 0.0);
}

TEST(FlcHalton, ShuffleIsASeededPermutation) {
  auto a = shuffled_halton(500, 7), b = shuffled_halton(500, 7), c = shuffled_halton(500, 8);
  ASSERT_EQ(a.size(), 500u);
  EXPECT_TRUE(a == b);
  EXPECT_FALSE(a == c);
  auto key = [](const glm::vec2& v) { return std::make_pair(v.x, v.y); };
  std::vector<std::pair<float, float>> ka, kc, kh;
  for (size_t i = 0; i < a.size(); ++i) {
    ka.push_back(key(a[i]));
    kc.push_back(key(c[i]));
    kh.push_back({float(radical_inverse(i + 1, 2)), float(radical_inverse(i + 1, 3))});
  }
  std::sort(ka.begin(), ka.end());
  std::sort(kc.begin(), kc.end());
  std::sort(kh.begin(), kh.end());
  EXPECT_EQ(ka, kh);
  EXPECT_EQ(kc, kh);
}

TEST(FlcSampling, ChainsFavourHighImportance) {
  // Left half importance 1, right half 0.05: with M proposals a chain ends on the right only
  // if all M proposals were there (probability 0.5^M).
  Image P(64, 64, 1, 0.05f);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 32; ++x) P.at(x, y)[0] = 1.f;
  const int ns = 2000;
  auto frac_left = [&](int m) {
    auto H = shuffled_halton(size_t(ns) * size_t(m), 3);
    auto s = flc_select_samples(P, H, ns, m);
    int left = 0;
    for (auto& e : s) {
      left += (e.pixel % 64) < 32;
      EXPECT_EQ(e.weight, P.data[e.pixel]);
    }
    return double(left) / ns;
  };
  const double f1 = frac_left(1), f8 = frac_left(8);
  EXPECT_NEAR(f1, 0.5, 0.05);  // M = 1: plain Halton, uniform
  EXPECT_GT(f8, 0.98);         // 1 - 0.5^8 = 0.996
  // Graded map: selected pixels have a higher mean importance than the map.
  Image G(64, 64, 1);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) G.at(x, y)[0] = float(x) / 63.f;
  auto H = shuffled_halton(size_t(ns) * 4, 11);
  auto s = flc_select_samples(G, H, ns, 4);
  double mean = 0;
  for (auto& e : s) mean += e.weight;
  mean /= ns;
  EXPECT_GT(mean, 0.7);  // E[max of 4 uniforms] = 0.8, map mean 0.5
}

TEST(FlcSampling, ZeroMapGivesZeroWeightsAndRejectsShortInput) {
  Image Z(16, 16, 1, 0.f);
  auto H = shuffled_halton(64, 1);
  auto s = flc_select_samples(Z, H, 16, 4);
  ASSERT_EQ(s.size(), 16u);
  for (auto& e : s) {
    EXPECT_EQ(e.weight, 0.f);
    EXPECT_LT(e.pixel, 256u);
  }
  EXPECT_THROW(flc_select_samples(Z, H, 17, 4), InternalError);  // a caller's bug
}

TEST(FlcImportance, AcuityFollowsEqs3To6) {
  FlcImportanceParams p;
  const double half_diag = 512.0 * std::sqrt(2.0), tan_half = std::tan(deg2rad(55.0));
  EXPECT_DOUBLE_EQ(flc_acuity(0.0, half_diag, tan_half, p), 1.0);
  // Inside the fovea (k <= sqrt(r)) h >= 1 -> clamped to 1.
  EXPECT_DOUBLE_EQ(flc_acuity(p.fovea_frac * half_diag * 0.999, half_diag, tan_half, p), 1.0);
  EXPECT_DOUBLE_EQ(flc_acuity(1e6, half_diag, tan_half, p), p.omega_p);
  // Just outside: h = 1 + s (m - e).
  const double d = 0.5 * half_diag;
  const double m = std::atan(p.fovea_frac * tan_half), e = std::atan(0.5 * tan_half);
  EXPECT_NEAR(flc_acuity(d, half_diag, tan_half, p), std::clamp(1.0 + 2.25 * (m - e), 0.2, 1.0),
              1e-12);
  double prev = 1.0;
  for (double r = 0; r < 2000; r += 7) {
    double a = flc_acuity(r, half_diag, tan_half, p);
    EXPECT_LE(a, prev + 1e-15);
    EXPECT_GE(a, p.omega_p);
    prev = a;
  }
  // Exact eccentricity overrides eq. 6.
  EXPECT_NEAR(flc_acuity(0.0, half_diag, tan_half, p, m + 0.1), 1.0 - 2.25 * 0.1, 1e-12);
}

TEST(FlcImportance, ColourDifferenceEq7) {
  const float a[3] = {0.5f, 0.5f, 0.5f}, red[3] = {1.f, 0.f, 0.f}, black[3] = {0.f, 0.f, 0.f};
  EXPECT_EQ(flc_color_difference(a, a), 0.0);
  EXPECT_NEAR(flc_color_difference(red, black), std::sqrt(3.0 * 256.0 * 256.0),
              1e-9);  // (2 + 1) * 256^2
  EXPECT_NEAR(flc_color_difference(black, red), std::sqrt(1.0 * 256.0 * 256.0),
              1e-9);  // (2 - 1) * 256^2
}

TEST(FlcImportance, MapCombinesPartsByEq9) {
  GBuffer g;
  g.resize(32, 16, kDepth | kPosition | kNormal | kAlbedo);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x) {
      size_t i = size_t(y) * 32 + size_t(x);
      g.depth[i] = x < 16 ? 2.f : 4.f;  // depth edge between x = 15 and 16
      g.normal[i] = glm::vec3(0, 0, 1);
      if (x == 31 && y == 0) g.depth[i] = std::numeric_limits<float>::infinity();  // a miss
    }
  Image color(32, 16, 3, 0.5f);
  FlcImportanceParams p;
  p.omega_p = 0.2;
  p.slope = 1e6;  // acuity = omega_p outside the gaze pixel
  p.fovea_frac = 1e-6;
  FlcImportanceMaps m;
  flc_importance_map(g, color, nullptr, glm::dvec2(-1000, -1000), 1.0, nullptr, p, m, true);
  EXPECT_EQ(m.importance.at(31, 0)[0], 0.f);        // miss
  EXPECT_FLOAT_EQ(m.importance.at(15, 8)[0], 1.f);  // silhouette, p_b = 1 without history
  EXPECT_FLOAT_EQ(m.importance.at(16, 8)[0], 1.f);
  EXPECT_FLOAT_EQ(m.importance.at(5, 8)[0], 0.2f);  // acuity floor
  EXPECT_FLOAT_EQ(m.silhouette.at(5, 8)[0], 0.f);
  // History brightness: p_b = min(1, delta * b).
  Image hist(32, 16, 1, 0.01f);
  flc_importance_map(g, color, &hist, glm::dvec2(-1000, -1000), 1.0, nullptr, p, m, false);
  EXPECT_NEAR(m.importance.at(5, 8)[0], 0.2 * 0.2, 1e-6);  // 0.2 * min(1, 20 * 0.01)
  EXPECT_NEAR(m.importance.at(15, 8)[0], 0.2, 1e-6);
  Image zero(32, 16, 1, 0.f);
  flc_importance_map(g, color, &zero, glm::dvec2(16, 8), 1.0, nullptr, p, m, false);
  for (float v : m.importance.data) EXPECT_EQ(v, 0.f);
}

TEST(FlcBlso, Eq12Branches) {
  const double xi = 0.01, k = 34;
  EXPECT_EQ(blso_g(-0.5, xi, k), 1.0);
  EXPECT_EQ(blso_g(-xi, xi, k), 1.0);
  EXPECT_EQ(blso_g(0.0, xi, k), 0.0);
  EXPECT_EQ(blso_g(0.5 * xi, xi, k), 0.0);
  EXPECT_NEAR(blso_g(0.04, xi, k), 1.0 - std::exp(-34.0 * 0.2), 1e-12);
  EXPECT_LT(blso_g(xi, xi, k), blso_g(0.1, xi, k));
}

TEST(FlcContribution, SinglePairMatchesEq14) {
  std::vector<VPL> v(1);
  v[0].position = glm::vec3(0.f);
  v[0].normal = glm::vec3(0, 1, 0);
  v[0].flux = glm::vec3(2.f);
  std::vector<FlcShadingPoint> pts(2);
  pts[0].p = glm::vec3(0, 2, 0);
  pts[0].n = glm::vec3(0, -1, 0);
  pts[0].weight = 0.5f;
  pts[1].p = glm::vec3(0, -2, 0);  // behind the VPL: no contribution
  pts[1].n = glm::vec3(0, 1, 0);
  pts[1].weight = 1.f;
  ContributionSettings s;
  s.visibility = FlcVisibility::None;
  s.eps2 = 0.25f;
  Counters c;
  auto C = flc_contributions(v, {}, pts, s, nullptr, &c);
  ASSERT_EQ(C.size(), 1u);
  EXPECT_NEAR(C[0], (2.0 * 1 * 1 * 0.5 / (4.0 + 0.25)) / 2.0, 1e-6);
  EXPECT_EQ(c.get(Counter::contribution_evals), 2.0);
  // No samples, no VPLs: finite empty results.
  EXPECT_EQ(flc_contributions(v, {}, {}, s, nullptr)[0], 0.0);
  EXPECT_TRUE(flc_contributions({}, {}, pts, s, nullptr).empty());
}

TEST(FlcCull, BudgetExtremes) {
  std::vector<double> C = {1, 0, 3, 2, 0.5};
  auto all = flc_cull(C, 5, 0.02, 1);
  EXPECT_EQ(all.kept, (std::vector<uint32_t>{0, 1, 2, 3, 4}));
  for (float w : all.weight) EXPECT_EQ(w, 1.f);
  EXPECT_EQ(flc_cull(C, 100, 0.02, 1).kept.size(), 5u);
  EXPECT_TRUE(flc_cull(C, 0, 0.02, 1).kept.empty());
  EXPECT_TRUE(flc_cull({}, 10, 0.02, 1).kept.empty());
  // All-zero or non-finite contributions: uniform, finite weights.
  auto z = flc_cull(std::vector<double>(10, 0.0), 5, 0.0, 3);
  EXPECT_EQ(z.kept.size(), 5u);
  for (float w : z.weight) EXPECT_FLOAT_EQ(w, 2.f);
  auto nf = flc_cull({NAN, 1.0, INFINITY, 2.0}, 2, 0.0, 3);
  for (float w : nf.weight) EXPECT_TRUE(std::isfinite(w));
}

TEST(FlcCull, ExactBudgetUnbiasedAndFavoursLargeContributions) {
  Rng r(5);
  std::vector<double> C(400);
  for (auto& v : C) v = std::pow(r.uniform(), 4.0);
  C[17] = 50.0;  // dominant VPL: always kept
  const double total = std::accumulate(C.begin(), C.end(), 0.0);
  double mean_est = 0;
  const int trials = 1000;
  std::vector<int> kept_count(C.size(), 0);
  for (int t = 0; t < trials; ++t) {
    auto k = flc_cull(C, 64, 0.02, uint64_t(t));
    EXPECT_NEAR(double(k.kept.size()), 64.0, 1.0);
    double est = 0;
    for (size_t j = 0; j < k.kept.size(); ++j) {
      est += k.weight[j] * C[k.kept[j]];
      ++kept_count[k.kept[j]];
    }
    mean_est += est / trials;
  }
  EXPECT_NEAR(mean_est / total, 1.0, 0.02);  // Horvitz-Thompson: unbiased
  EXPECT_EQ(kept_count[17], trials);
  // The 10% largest are kept more often than the 10% smallest.
  std::vector<size_t> idx(C.size());
  std::iota(idx.begin(), idx.end(), 0);
  std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return C[a] < C[b]; });
  double lo = 0, hi = 0;
  for (size_t j = 0; j < 40; ++j) {
    lo += kept_count[idx[j]];
    hi += kept_count[idx[idx.size() - 1 - j]];
  }
  EXPECT_GT(hi, 5 * lo);
}
