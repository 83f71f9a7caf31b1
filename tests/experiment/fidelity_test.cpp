// `fovsim fidelity`: the ladder on a tiny config, the analytic rung against a
// rendered run, rung parsing, and the ranking target of --target.
#include "sim/experiment/fidelity.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <set>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/experiment/intervals.h"
#include "sim/experiment/runner.h"

using namespace fovsim;

namespace {

LoadedConfig tiny(const std::string& scene = R"({"type": "atrium", "complexity": 1})",
                  int frames = 24) {
  LoadedConfig c;
  c.file = "tiny.json";
  c.doc = Json::parse(R"({"name": "fid", "display": "htc_vive_pro_eye",
    "render": {"scale": 0.04},
    "scene": )" + scene +
                      R"(,
    "trace": {"synthetic": {"scenario": "walk-through", "seed": 3, "duration": 1}},
    "frames": {"count": )" +
                      std::to_string(frames) +
                      R"(},
    "methods": [{"method": "full"}, {"method": "kfr", "sigma": 2.0, "alpha": 4},
                {"method": "rmfr"}, {"method": "fvrs"}],
    "outputs": {"print_summary": false}})");
  return c;
}

std::string tmp(const std::string& name) {
  auto d = std::filesystem::temp_directory_path() /
           ("fovsim_fidelity_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  return d.string();
}

std::string err_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST(Fidelity, LadderHasARowPerRungMethodAndOutputAndTopErrorZero) {
  FidelityOptions o;
  o.out_dir = tmp("ladder");
  o.rungs = "analytic;scale=0.02;stride=2";
  o.top = "scale=0.04";
  o.progress = false;
  FidelityResult r = run_fidelity(tiny(), o);
  // rung -> config -> outputs
  std::map<std::string, std::map<std::string, std::set<std::string>>> seen;
  for (auto& row : r.table.rows()) {
    const std::string& rung = *row.text_of("rung");
    seen[rung][*row.text_of("config_id")].insert(*row.text_of("output"));
    if (rung == "scale=0.04") {  // the top rung against itself
      EXPECT_EQ(row.get("err", NAN), 0.0) << *row.text_of("output");
      EXPECT_EQ(row.get("ranking_same", NAN), 1.0);
      EXPECT_EQ(row.get("wall_ratio", NAN), 1.0);
    }
  }
  for (const char* rung : {"analytic", "scale=0.02", "stride=2", "scale=0.04"}) {
    ASSERT_EQ(seen[rung].size(), 4u) << rung;  // full, kfr, rmfr, fvrs
    for (auto& [id, outs] : seen[rung]) {
      EXPECT_TRUE(outs.count("est_ms_total")) << rung << " " << id;
      EXPECT_TRUE(outs.count("shaded_fraction")) << rung << " " << id;
      if (std::string(rung) != "analytic") {
        for (const char* m : {"est_ms_total_p95", "psnr", "fpsnr", "ssim", "flip"})
          EXPECT_TRUE(outs.count(m)) << rung << " " << id << " " << m;
      }
    }
  }
  // Rendered rungs differ from the truth somewhere; the stride rung ran half the frames.
  bool any = false;
  for (auto& row : r.table.rows())
    if (*row.text_of("rung") == "scale=0.02" && std::fabs(row.get("err", 0)) > 0) any = true;
  EXPECT_TRUE(any);
  for (auto& row : r.table.rows())
    if (*row.text_of("rung") == "stride=2") {
      EXPECT_EQ(row.get("frames", NAN), 12.0);
    }
  // Every rung has a ranking verdict per output; outputs: files and code version.
  for (auto& j : r.json["rungs"]) {
    EXPECT_TRUE(j.contains("ranking_same_all_outputs")) << j.dump();
    EXPECT_TRUE(j["wall_s"].get<double>() >= 0);
  }
  EXPECT_TRUE(r.json.contains("resolved_config") && r.json["resolved_config"].is_object());
  EXPECT_EQ(r.json["resolved_config"]["render"]["scale"], 0.04);
  EXPECT_TRUE(r.json.contains("version") && r.json.contains("git_commit"));
  EXPECT_TRUE(file_exists(o.out_dir + "/fidelity.csv"));
  EXPECT_TRUE(file_exists(o.out_dir + "/fidelity.json"));
  EXPECT_NE(r.markdown.find("| analytic |"), std::string::npos) << r.markdown;
}

TEST(Fidelity, RankingFlagComparesOrders) {
  auto summary = [](double a, double b, double c) {
    ResultTable t;
    for (auto [id, v] : {std::pair{"a", a}, {"b", b}, {"c", c}}) {
      ResultRow r;
      r.set_text("config_id", id);
      r.set_text("gpu", "g");
      r.set("psnr", v);
      t.add(r);
    }
    return t;
  };
  EXPECT_TRUE(same_ranking(summary(30, 20, 10), summary(31, 22, 9), "psnr"));
  EXPECT_FALSE(same_ranking(summary(30, 20, 10), summary(30, 9, 10), "psnr"));
  // A config without a finite value (PSNR of `full`, or no metric at all) is not ranked.
  EXPECT_TRUE(same_ranking(summary(INFINITY, 20, 10), summary(NAN, 22, 9), "psnr"));
}

TEST(Fidelity, BadRungsAreOneLocatedLine) {
  EXPECT_EQ(err_of([] { parse_rungs("analytic;scale=0", "scale=0.5"); }),
            "--rungs scale=0: scale must be a number in (0, 4], got \"0\"");
  EXPECT_EQ(err_of([] { parse_rungs("analytic;stride=1.5", "scale=0.5"); }),
            "--rungs stride=1.5: stride must be an integer in (0, 1000000], got \"1.5\"");
  EXPECT_EQ(err_of([] { parse_rungs("analytic;;scale=0.25", "scale=0.5"); }),
            "--rungs \"\": empty rung (rungs are separated by ';', e.g. "
            "analytic;scale=0.25;stride=2)");
  EXPECT_EQ(err_of([] { parse_rungs("resolution=3", "scale=0.5"); }),
            "--rungs resolution=3: unknown knob \"resolution\" (scale, stride, spp, or a config "
            "key.path such as render.scale)");
  EXPECT_EQ(err_of([] { parse_rungs("fast", "scale=0.5"); }),
            "--rungs fast: expected analytic, scale=X, stride=N, spp=N or key.path=value, got "
            "\"fast\"");
  EXPECT_EQ(err_of([] { parse_rungs("scale=0.25", "analytic"); }),
            "--top analytic: the top rung (the truth) must render");
  EXPECT_EQ(err_of([] { parse_rungs("scale=0.25;scale=0.25", "scale=0.5"); }),
            "--rungs scale=0.25: rung given twice");
  auto ok = parse_rungs("analytic; scale=0.25,stride=2 ;render.spp=4", "scale=0.5");
  ASSERT_EQ(ok.size(), 4u);
  EXPECT_TRUE(ok[0].analytic);
  EXPECT_EQ(ok[1].stride, 2);
  EXPECT_EQ(ok[1].overrides, std::vector<std::string>{"render.scale=0.25"});
  EXPECT_TRUE(ok[3].top);
  // spp rungs: skipped with a reason when this build has no render.spp.
  auto spp = parse_rungs("spp=1", "scale=0.5");
  EXPECT_EQ(spp[0].skipped.empty(), render_spp_known());
}

// `predict`'s analytic counters and frame times against a rendered run of the
// same config, on every built-in scene. RMFR's shaded fraction is exact up to rounding, KFR's an
// upper bound; the baselines' analytic fractions assume the gaze at the screen centre.
TEST(Fidelity, AnalyticAgreesWithRenderedRunOnBuiltInScenes) {
  for (const char* scene : {R"({"type": "atrium", "complexity": 1})", R"({"type": "cornell"})",
                            R"({"type": "patterns", "pattern": "stripes"})"}) {
    LoadedConfig c = tiny(scene, 20);
    c.doc["render"]["scale"] = 0.05;
    RunOptions ro;
    ro.out_dir = tmp("analytic");
    ro.print_summary = false;
    RunResult run = run_experiment(c, ro);
    ResultTable a = analytic_summary(c, "");
    ASSERT_EQ(a.rows().size(), 4u) << scene;
    ResultTable cmp = compare_to_truth("analytic", a, run.summary, {});
    int n = 0;
    const bool indirect = std::string(scene).find("cornell") != std::string::npos;
    for (auto& row : cmp.rows()) {
      const std::string& m = *row.text_of("method");
      const std::string& o = *row.text_of("output");
      double rel = row.get("err_rel", NAN);
      if (o == "est_ms_total") {
        ++n;
        EXPECT_TRUE(std::isfinite(rel)) << scene << " " << m;
        if (m == "full" && !indirect) {
          EXPECT_LT(std::fabs(rel), 0.02) << scene;  // same counters
        } else if (m == "full") {
          // Indirect light: analytic assumes every RSM texel is a VPL and every pixel a hit,
          // an upper bound on the rendered VPL shading (Cornell box: 4096 texels -> 3602 VPLs,
          // 79% hits; docs/fidelity.md).
          EXPECT_GT(rel, 0.0) << scene;
          EXPECT_LT(rel, 1.0) << scene;
        }
      }
      if (o == "shaded_fraction" && (m == "rmfr" || m == "full")) {
        EXPECT_LT(std::fabs(row.get("err", NAN)), 0.02) << scene << " " << m;
      }
      // KFR's analytic count is its whole (W/sigma) x (H/sigma) LP-buffer; the rendered run
      // shades only LP texels that map onto the screen: an upper bound (docs/fidelity.md).
      if (o == "shaded_fraction" && m == "kfr") {
        EXPECT_GE(row.get("value", NAN), row.get("top", NAN)) << scene;
        EXPECT_LT(row.get("err", NAN), 0.1) << scene;
      }
    }
    EXPECT_EQ(n, 4) << scene;
  }
}

TEST(RankingTarget, ParsesAndSettlesOnlyWhenNeighboursSeparate) {
  IntervalTarget t = parse_target("ranking");
  EXPECT_TRUE(t.ranking);
  EXPECT_EQ(t.column, kDefaultRankingColumn);
  EXPECT_EQ(parse_target("ranking:psnr").column, "psnr");
  EXPECT_EQ(err_of([] { parse_target("ranking:frame"); }),
            "--target ranking:frame: column \"frame\" has no interval, so it cannot be ranked");
  // Three configs over 40 frames: a >> b (separated), b vs c equal means up to noise.
  auto frames = [](double gap_bc) {
    ResultTable f;
    for (int i = 0; i < 40; ++i)
      for (auto [id, v] : {std::pair{"a", 30.0}, {"b", 20.0}, {"c", 20.0 - gap_bc}}) {
        ResultRow r;
        r.set_text("config_id", id);
        r.set_text("gpu", "g");
        r.set("frame", i);
        r.set("psnr",
              v + ((i * 7919) % 13) * 0.1 + (std::string(id) == "b" ? (i % 2) * 0.5 - 0.25 : 0));
        f.add(r);
      }
    return f;
  };
  Json ach;
  EXPECT_TRUE(targets_met({parse_target("ranking:psnr")}, frames(3.0), &ach));
  EXPECT_EQ(ach["ranking:psnr"]["order"]["g"], Json::array({"a", "b", "c"}));
  EXPECT_FALSE(targets_met({parse_target("ranking:psnr")}, frames(0.0), &ach));
  EXPECT_FALSE(ach["ranking:psnr"]["pairs"][1]["settled"].get<bool>());
}

// A sweep config: every rung runs the whole sweep; rows per cell, methods ranked within a cell.
TEST(Fidelity, SweepConfigGivesRowsPerCell) {
  LoadedConfig c = tiny(R"({"type": "atrium", "complexity": 1})", 6);
  c.doc["sweep"] = Json::parse(R"({"grid": {"methods[kfr].sigma": [1.5, 2.5]}})");
  FidelityOptions o;
  o.out_dir = tmp("sweep");
  o.rungs = "analytic;stride=2";
  o.top = "scale=0.03";
  o.progress = false;
  FidelityResult r = run_fidelity(c, o);
  std::map<std::string, std::set<std::string>> ids;
  for (auto& row : r.table.rows()) {
    ids[*row.text_of("rung")].insert(*row.text_of("config_id"));
    if (*row.text_of("rung") == "scale=0.03") {
      EXPECT_EQ(row.get("err", NAN), 0.0);
    }
  }
  for (const char* rung : {"analytic", "stride=2", "scale=0.03"}) {
    EXPECT_EQ(ids[rung].size(), 8u) << rung;  // 2 cells x 4 methods
    EXPECT_TRUE(ids[rung].count("0/kfr") && ids[rung].count("1/kfr")) << rung;
  }
  EXPECT_TRUE(file_exists(o.out_dir + "/rungs/2-scale_0.03/summary.csv"));
}
