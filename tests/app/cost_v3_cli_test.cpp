// Cost model v3 on the command line: `predict --config` charges the passes a run charges
// (quickstart, two frames), `budget --results` answers for the run with a probability, and a
// scene-less `--workload generic` is refused like a missing --workload.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <set>

#include "tests/app/app_util.h"

using namespace fovsim_test;

namespace {
std::set<std::string> passes_of(const nlohmann::json& e) {
  std::set<std::string> p;
  for (auto it = e.begin(); it != e.end(); ++it) {
    const std::string k = it.key();
    if (k.rfind("est_ms_", 0) != 0 || k == "est_ms_total") continue;
    if (k.size() > 3 &&
        (k.compare(k.size() - 3, 3, "_lo") == 0 || k.compare(k.size() - 3, 3, "_hi") == 0))
      continue;
    p.insert(k.substr(7));
  }
  return p;
}
}  // namespace

TEST(CostV3Cli, PredictConfigChargesTheRunsPasses) {
  std::string dir = temp_dir("cost_v3_config");
  auto r = run_cmd(
      fovsim_bin() +
      " run configs/quickstart.json frames.count=2 render.scale=0.25 outputs.image_frames=[] -q "
      "--no-plots --out " +
      dir + "/run");
  ASSERT_EQ(r.code, 0) << r.output;
  auto p = run_cmd(fovsim_bin() + " predict --config configs/quickstart.json --json");
  ASSERT_EQ(p.code, 0) << p.output;
  auto pj = nlohmann::json::parse(p.output);
  auto q = run_cmd(fovsim_bin() + " predict --results " + dir + "/run --gpu gtx1080 --json");
  ASSERT_EQ(q.code, 0) << q.output;
  auto rj = nlohmann::json::parse(q.output);
  ASSERT_EQ(pj.size(), rj.size());
  for (auto& e : pj) {
    EXPECT_TRUE(e["indirect"].get<bool>());
    bool found = false;
    for (auto& x : rj)
      if (x["config_id"] == e["label"]) {
        found = true;
        EXPECT_EQ(passes_of(e), passes_of(x)) << e["label"];
      }
    EXPECT_TRUE(found) << e["label"];
  }
  auto b = run_cmd(fovsim_bin() + " budget --results " + dir + "/run --gpu gtx1080 --json");
  ASSERT_EQ(b.code, 0) << b.output;
  auto bj = nlohmann::json::parse(b.output);
  ASSERT_EQ(bj.size(), rj.size());
  for (auto& e : bj) {
    EXPECT_GE(e["p_fit"].get<double>(), 0.0);
    EXPECT_LE(e["p_fit"].get<double>(), 1.0);
  }
}

TEST(CostV3Cli, GenericWorkloadRefusedAndBudgetGivesProbability) {
  auto g =
      run_cmd(fovsim_bin() + " budget --gpu gtx1080 --workload generic -m kfr:sigma=1.2 -m full");
  EXPECT_EQ(g.code, 2) << g.output;
  EXPECT_NE(g.output.find("--workload"), std::string::npos) << g.output;
  EXPECT_NE(g.output.find("generic"), std::string::npos) << g.output;
  auto b = run_cmd(fovsim_bin() +
                   " budget --gpu gtx1080,rtx4070 --workload kfr_bistro --display "
                   "desktop_1920x1080 --hz 60 -m kfr:sigma=1.2 --json");
  ASSERT_EQ(b.code, 0) << b.output;
  auto j = nlohmann::json::parse(b.output);
  ASSERT_EQ(j.size(), 2u);
  EXPECT_TRUE(j[0]["calibrated"].get<bool>());
  EXPECT_FALSE(j[1]["calibrated"].get<bool>());
  EXPECT_LT(j[0]["p_fit"].get<double>(), 0.8);
  ASSERT_FALSE(j[0]["changes"].empty());
  EXPECT_GE(j[0]["changes"][0]["p_fit"].get<double>(), 0.8);
  auto t = run_cmd(fovsim_bin() +
                   " budget --gpu rtx4070 --workload kfr_bistro --display desktop_1920x1080");
  ASSERT_EQ(t.code, 0) << t.output;
  EXPECT_NE(t.output.find("* rtx4070: calibrated = no"), std::string::npos) << t.output;
}

// `budget`'s verdict is the one budget decision (sim/cost/budget.h): p_fit against --p.
TEST(CostV3Cli, BudgetVerdictIsTheProbabilityAtTheLevel) {
  for (const char* level : {"0.5", "0.8", "0.95"}) {
    auto b = run_cmd(fovsim_bin() +
                     " budget --gpu gtx1080 --workload kfr_bistro --display desktop_1920x1080 "
                     "--hz 75 -m kfr:sigma=1.2 -m kfr:sigma=1.6 -m kfr:sigma=2.0 -m full --json "
                     "--p " +
                     level);
    ASSERT_EQ(b.code, 0) << b.output;
    const double L = std::stod(level);
    for (auto& e : nlohmann::json::parse(b.output)) {
      const double p = e["p_fit"].get<double>();
      const std::string v = e["verdict"].get<std::string>();
      EXPECT_EQ(e["fits"].get<bool>(), p >= L) << e["method"];
      EXPECT_EQ(v, p >= L ? "fits" : (p <= 1 - L ? "does not fit" : "uncertain")) << e["method"];
      EXPECT_EQ(e["fit_level"].get<double>(), L);
    }
  }
}
