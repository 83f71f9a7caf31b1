// The search's verdict (sim/experiment/search_verdict.h): optimum on an end of the space,
// winner against runner-up within noise, constraints that never bind.
#include "sim/experiment/search_verdict.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace fovsim;

TEST(SearchVerdict, BoundaryHitsNameAxisAndEnd) {
  std::vector<SearchDim> space = {{"methods[kfr].sigma", 1.2, 3.0, 0.1},
                                  {"methods[kfr].alpha", 1, 4, 0, false, true},
                                  {"fx", 0.05, 0.8}};
  auto h = boundary_hits(space, {1.2, 4, 0.3});
  ASSERT_EQ(h.size(), 2u);
  EXPECT_EQ(h[0].dim, 0u);
  EXPECT_EQ(h[0].end, -1);
  EXPECT_EQ(h[1].dim, 1u);
  EXPECT_EQ(h[1].end, +1);
  EXPECT_EQ(describe_boundary(space, h),
            "the optimum lies on the lower end of methods[kfr].sigma (1.2); upper end of "
            "methods[kfr].alpha (4): widen the space there");
  EXPECT_TRUE(boundary_hits(space, {1.3, 2, 0.3}).empty());
  EXPECT_EQ(describe_boundary(space, {}), "");
  // The upper end as the axis can reach it: the last step below `to`.
  std::vector<SearchDim> q = {{"x", 0.0, 1.0, 0.3}};
  ASSERT_EQ(boundary_hits(q, {0.9}).size(), 1u);
  EXPECT_EQ(boundary_hits(q, {0.9})[0].end, +1);
  EXPECT_TRUE(boundary_hits(q, {0.6}).empty());
  // An axis with from == to has no ends; a point of another dimension has none either.
  std::vector<SearchDim> flat = {{"x", 2.0, 2.0}};
  EXPECT_TRUE(boundary_hits(flat, {2.0}).empty());
  EXPECT_TRUE(boundary_hits(space, {1.2}).empty());
}

TEST(SearchVerdict, PairedTieAndSeparation) {
  // Two points whose per-frame scores move together: the paired interval is narrow.
  std::vector<double> a, b, c;
  for (int i = 0; i < 40; ++i) {
    const double base = 20 + 3 * std::sin(0.3 * i);
    a.push_back(base + 0.5 + 0.01 * ((i * 7) % 5));
    b.push_back(base);
    c.push_back(base + 0.001 + 0.1 * ((i * 7) % 5 - 2));  // noise around +0.001
  }
  auto mean = [](const std::vector<double>& x) {
    double s = 0;
    for (double v : x) s += v;
    return s / double(x.size());
  };
  // a beats b by 0.5 on every frame: separated, although the means' intervals (±2) overlap.
  ScoreComparison s = compare_scores(mean(a), mean(b), a, b, 2.0, 2.0);
  EXPECT_TRUE(s.paired);
  EXPECT_EQ(s.frames, 40u);
  EXPECT_EQ(s.tied, 0);
  EXPECT_NEAR(s.delta, 0.52, 0.01);
  EXPECT_LT(s.ci95, 0.05);
  EXPECT_EQ(
      describe_comparison(s, "fpsnr").rfind("winner beats runner-up beyond noise (fpsnr +0.52", 0),
      0u);
  // c and b differ by noise around +0.001: tied.
  ScoreComparison t = compare_scores(mean(c), mean(b), c, b, 2.0, 2.0);
  EXPECT_TRUE(t.paired);
  EXPECT_EQ(t.tied, 1) << t.delta << " ± " << t.ci95;
  EXPECT_NE(describe_comparison(t, "fpsnr").find("tied within noise (fpsnr +0.001"),
            std::string::npos);
  // Without per-frame values: the intervals of the two means.
  ScoreComparison u = compare_scores(21.0, 20.0, {}, {}, 0.6, 0.8);
  EXPECT_FALSE(u.paired);
  EXPECT_DOUBLE_EQ(u.ci95, 1.0);
  EXPECT_EQ(u.tied, 1);
  EXPECT_EQ(compare_scores(21.5, 20.0, {}, {}, 0.6, 0.8).tied, 0);
  // No interval at all (too few frames): tied unknown, and said why.
  ScoreComparison v = compare_scores(21.0, 20.0, {1, 2, 3}, {1, 2, 2}, NAN, NAN);
  EXPECT_EQ(v.tied, -1);
  EXPECT_NE(describe_comparison(v, "fpsnr").find("noise unknown"), std::string::npos);
}

TEST(SearchVerdict, ConstraintsThatNeverBind) {
  SearchSpec sp;
  sp.constraints = {{"shaded_fraction", -INFINITY, 0.15}, {"fvvdp_jod_fl", 9.5, INFINITY}};
  std::vector<std::vector<double>> v = {{0.10, 9.6}, {0.12, 9.4}, {0.05, 9.9}};
  auto l = non_binding_constraints(sp, v);
  ASSERT_EQ(l.size(), 1u);
  EXPECT_EQ(l[0],
            "constraint shaded_fraction <= 0.15 does not bind: all 3 evaluated points meet it "
            "(shaded_fraction from 0.05 to 0.12)");
  v[1][0] = NAN;  // a missing value is a violation
  EXPECT_TRUE(non_binding_constraints(sp, v).empty());
  EXPECT_TRUE(is_frame_budget_column("headroom_ms"));
  EXPECT_TRUE(is_frame_budget_column("est_ms_total_hi"));
  EXPECT_FALSE(is_frame_budget_column("shaded_fraction"));
  EXPECT_EQ(budget_sentence("unfoveated full", 4.123, 11.111),
            "budget does not bind: unfoveated full fits at 4.12 ms of 11.11 ms");
  EXPECT_EQ(budget_sentence("full", 12, 11.111), "");
}
