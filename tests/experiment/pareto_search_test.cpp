// Pareto front on a constructed set, iso-budget selection, and the ask/tell search on an
// analytic constrained problem with a known optimum.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/experiment/pareto.h"
#include "sim/experiment/search.h"

using namespace fovsim;

namespace {
ResultTable points(const std::vector<std::tuple<std::string, std::string, double, double>>& pts) {
  ResultTable t;
  for (auto& [gpu, label, ms, q] : pts) {
    ResultRow r;
    r.set_text("gpu", gpu);
    r.set_text("label", label);
    r.set("est_ms_total", ms);
    r.set("fpsnr", q);
    t.add(r);
  }
  return t;
}
}  // namespace

TEST(Pareto, ConstructedFront) {
  // (ms, quality): front = rows 0, 2, 4 (and the duplicate 5 of 4); 1 and 3 are dominated;
  // 6 has NaN quality (dominated by anything finite and as fast or faster).
  auto t = points({{"g", "a", 1.0, 20},
                   {"g", "a", 2.0, 19},
                   {"g", "b", 2.0, 30},
                   {"g", "b", 3.0, 29},
                   {"g", "c", 5.0, 40},
                   {"g", "c", 5.0, 40},
                   {"g", "c", 6.0, NAN}});
  std::vector<Objective> obj = {{"est_ms_total", false}, {"fpsnr", true}};
  EXPECT_EQ(pareto_front(t, obj, {"gpu"}), (std::vector<size_t>{0, 2, 4, 5}));
  EXPECT_TRUE(dominates({1, 30}, {2, 30}, obj));
  EXPECT_FALSE(dominates({2, 30}, {2, 30}, obj));
  EXPECT_FALSE(dominates({1, 10}, {2, 30}, obj));
}

TEST(Pareto, GroupsAreSeparateFronts) {
  auto t = points({{"fast", "a", 1.0, 20}, {"slow", "a", 2.0, 10}, {"fast", "b", 0.5, 25}});
  std::vector<Objective> obj = {{"est_ms_total", false}, {"fpsnr", true}};
  EXPECT_EQ(pareto_front(t, obj, {"gpu"}), (std::vector<size_t>{1, 2}));
  EXPECT_EQ(pareto_front(t, obj, {}), (std::vector<size_t>{2}));
}

TEST(Pareto, IsoBudgetPicksBestQualityWithinBudget) {
  auto t = points({{"g", "kfr", 1.0, 20},
                   {"g", "kfr", 2.0, 25},
                   {"g", "kfr", 3.0, 40},
                   {"g", "rmfr", 1.5, 22},
                   {"g", "rmfr", 2.5, 30}});
  IsoBudgetSpec s;
  s.column = "est_ms_total";
  s.budgets = {2.0, 2.5};
  s.quality = {"fpsnr"};
  s.group_by = {"gpu"};
  auto r = iso_budget_table(t, s, {});
  ASSERT_EQ(r.rows().size(), 4u);
  EXPECT_EQ(*r.rows()[0].text_of("label"), "kfr");
  EXPECT_EQ(r.rows()[0].get("fpsnr", 0), 25);
  EXPECT_EQ(r.rows()[1].get("fpsnr", 0), 22);  // rmfr at 2.0: only the 1.5 ms cell fits
  EXPECT_EQ(r.rows()[3].get("fpsnr", 0), 30);
  s.budgets = {0.5};
  auto none = iso_budget_table(t, s, {});
  EXPECT_EQ(*none.rows()[0].text_of("config_id"), "none_within_budget");
  EXPECT_TRUE(std::isnan(none.rows()[0].get("fpsnr", 0)));
}

// A frame-time budget column is decided on the cells' own fit rule (fit_threshold_ms /
// budget_ms, sim/cost/budget.h): a cell whose estimate is under the budget but whose p_fit
// misses the level is not within it.
TEST(Pareto, IsoBudgetOnFrameTimeUsesTheCellsFitRule) {
  auto t = points({{"g", "kfr", 1.0, 20}, {"g", "kfr", 1.8, 25}});
  ResultTable ruled;
  for (ResultRow r : t.rows()) {
    r.set("budget_ms", 11.1);
    r.set("fit_level", 0.8);
    r.set("fit_threshold_ms", 11.1 * 0.8);  // fits at 0.8 up to 80% of any budget
    ruled.add(r);
  }
  IsoBudgetSpec s;
  s.column = "est_ms_total";
  s.budgets = {2.0, 2.5};
  s.quality = {"fpsnr"};
  s.group_by = {"gpu"};
  auto r = iso_budget_table(ruled, s, {});
  ASSERT_EQ(r.rows().size(), 2u);
  EXPECT_EQ(r.rows()[0].get("fpsnr", 0), 20);  // 1.8 > 2.0 x 0.8: not within 2 ms
  EXPECT_DOUBLE_EQ(r.rows()[0].get("within_ms", 0), 1.6);
  EXPECT_EQ(r.rows()[0].get("fit_level", 0), 0.8);
  EXPECT_EQ(r.rows()[1].get("fpsnr", 0), 25);  // 1.8 <= 2.5 x 0.8
}

TEST(Search, FindsConstrainedOptimum) {
  // maximize -(x-0.3)^2 - (y-0.6)^2 subject to x + y <= 0.8: optimum (0.25, 0.55).
  std::vector<SearchDim> space = {{"x", 0, 1}, {"y", 0, 1}};
  Searcher s(space, true, 7, 6);
  int evals = 0;
  for (int it = 0; it < 40 && evals < 120; ++it) {
    auto pts = s.ask();
    if (pts.empty()) break;
    std::vector<SearchEval> ev;
    for (auto& p : pts) {
      double f = -(p[0] - 0.3) * (p[0] - 0.3) - (p[1] - 0.6) * (p[1] - 0.6);
      ev.push_back({p, f, std::max(0.0, p[0] + p[1] - 0.8)});
    }
    evals += int(ev.size());
    s.tell(ev);
  }
  ASSERT_TRUE(s.has_best());
  EXPECT_LE(s.best().violation, 0.0);
  EXPECT_NEAR(s.best().x[0], 0.25, 0.03);
  EXPECT_NEAR(s.best().x[1], 0.55, 0.03);
  EXPECT_LE(evals, 120);
}

TEST(Search, DeterministicQuantizedAndNeverRepeats) {
  std::vector<SearchDim> space = {{"fx", 0.05, 0.8, 0.05}, {"n", 1, 8, 0, false, true}};
  auto run = [&]() {
    Searcher s(space, false, 3, 4);
    std::vector<std::vector<double>> all;
    for (int it = 0; it < 30; ++it) {
      auto pts = s.ask();
      if (pts.empty()) break;
      std::vector<SearchEval> ev;
      for (auto& p : pts) {
        all.push_back(p);
        ev.push_back({p, std::fabs(p[0] - 0.4) + std::fabs(p[1] - 3), 0});
      }
      s.tell(ev);
    }
    return std::make_pair(all, s.best().x);
  };
  auto [a, best] = run();
  auto [b, best2] = run();
  EXPECT_EQ(a, b);
  EXPECT_EQ(best, (std::vector<double>{0.4, 3}));
  std::set<std::vector<double>> uniq(a.begin(), a.end());
  EXPECT_EQ(uniq.size(), a.size());
  for (auto& p : a) {
    EXPECT_NEAR(std::round(p[0] / 0.05) * 0.05, p[0], 1e-9);
    EXPECT_EQ(p[1], std::round(p[1]));
  }
}
