// `fovsim predict --results DIR` re-costs a run's measured counters: for the run's own GPU and
// display it reproduces the run's est_ms_total exactly; a bigger display costs more.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "tests/app/app_util.h"

using namespace fovsim_test;

TEST(PredictResults, ReproducesRunAndScalesWithDisplay) {
  std::string dir = temp_dir("predict_results");
  auto r = run_cmd(fovsim_bin() + " run tests/golden/methods_small.json -q --out " + dir + "/run");
  ASSERT_EQ(r.code, 0) << r.output;
  auto p = run_cmd(fovsim_bin() + " predict --results " + dir + "/run --gpu gtx1080 --json");
  ASSERT_EQ(p.code, 0) << p.output;
  auto j = nlohmann::json::parse(p.output);
  Csv s = read_csv(dir + "/run/summary.csv");
  int c_id = s.col("config_id"), c_ms = s.col("est_ms_total");
  ASSERT_GE(c_ms, 0);
  ASSERT_EQ(j.size(), s.rows.size());
  for (auto& row : s.rows) {
    bool found = false;
    for (auto& e : j)
      if (e["config_id"] == row[size_t(c_id)]) {
        found = true;
        EXPECT_NEAR(e["est_ms_total"].get<double>(), std::stod(row[size_t(c_ms)]), 1e-6)
            << row[size_t(c_id)];
      }
    EXPECT_TRUE(found) << row[size_t(c_id)];
  }
  auto big = run_cmd(fovsim_bin() + " predict --results " + dir +
                     "/run --gpu gtx1080 --display uhd_3840x2160 --json");
  ASSERT_EQ(big.code, 0) << big.output;
  auto jb = nlohmann::json::parse(big.output);
  for (size_t i = 0; i < j.size(); ++i)
    EXPECT_GT(jb[i]["est_ms_total"].get<double>(), j[i]["est_ms_total"].get<double>());
  auto bad = run_cmd(fovsim_bin() + " predict --results " + dir + "/nope --gpu gtx1080");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.output.find("nope/manifest.json"), std::string::npos) << bad.output;
}
