// Sweep expansion: order and counts of every block kind, determinism of cell ids, and bad
// specs failing with the JSON path of the offending axis.
#include "sim/experiment/sweep_spec.h"

#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include "sim/core/error.h"
#include "sim/experiment/runner.h"
#include "sim/experiment/summary.h"

using namespace fovsim;

namespace {

LoadedConfig cfg_of(const std::string& sweep_json) {
  LoadedConfig c;
  c.file = "s.json";
  c.doc = Json::parse(R"({"name": "t", "render": {"scale": 0.1},
    "methods": [{"method": "full"}, {"method": "full", "label": "kfr"}],
    "sweep": )" + sweep_json +
                      "}");
  return c;
}

std::string err_of(const std::string& sweep_json) {
  try {
    auto p = expand_sweep(cfg_of(sweep_json));
    validate_cells(p);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

double num(const SweepCell& c, const std::string& path) {
  for (auto& a : c.assign)
    if (a.path == path) return a.value.get<double>();
  return NAN;
}

}  // namespace

TEST(SweepSpec, RangeValuesAreTidyAndInclusive) {
  auto v = axis_values(Json::parse(R"({"from": 1.2, "to": 2.4, "step": 0.2})"), "x");
  ASSERT_EQ(v.size(), 7u);
  EXPECT_EQ(v[1].dump(), "1.4");  // not 1.4000000000000001
  EXPECT_EQ(v[6].dump(), "2.4");
  auto c = axis_values(Json::parse(R"({"from": 0, "to": 1, "count": 5})"), "x");
  ASSERT_EQ(c.size(), 5u);
  EXPECT_EQ(c[0].dump(), "0");
  EXPECT_DOUBLE_EQ(c[3].get<double>(), 0.75);
  auto d = axis_values(Json::parse(R"({"from": 4, "to": 1, "step": -1})"), "x");
  EXPECT_EQ(d.size(), 4u);
}

TEST(SweepSpec, GridIsCartesianFirstAxisSlowest) {
  auto p = expand_sweep(
      cfg_of(R"({"grid": [{"methods[kfr].sigma": [1, 2, 3]}, {"render.scale": [0.1, 0.2]}]})"));
  ASSERT_EQ(p.cells.size(), 6u);
  std::vector<std::pair<double, double>> got;
  for (auto& c : p.cells) got.push_back({num(c, "methods[kfr].sigma"), num(c, "render.scale")});
  std::vector<std::pair<double, double>> want = {{1, .1}, {1, .2}, {2, .1},
                                                 {2, .2}, {3, .1}, {3, .2}};
  EXPECT_EQ(got, want);
  // The method-scoped path lands in the labelled entry.
  EXPECT_EQ(p.cells[4].doc["methods"][1]["sigma"], 3);
  EXPECT_FALSE(p.cells[4].doc["methods"][0].contains("sigma"));
  EXPECT_FALSE(p.cells[0].doc.contains("sweep"));
  EXPECT_EQ(p.axis_paths, (std::vector<std::string>{"methods[kfr].sigma", "render.scale"}));
}

TEST(SweepSpec, ZipAdvancesTogetherAndAxesMultiply) {
  auto p = expand_sweep(cfg_of(R"({"axes": [
      {"list": [{"render.scale": 0.1}, {"render.scale": 0.2, "seed": 7}]},
      {"zip": {"methods[0].fx": [0.1, 0.2, 0.3], "methods[0].fy": {"from": 0.5, "to": 0.7, "step": 0.1}}}]})"));
  ASSERT_EQ(p.cells.size(), 6u);
  for (auto& c : p.cells)
    EXPECT_NEAR(num(c, "methods[0].fy") - num(c, "methods[0].fx"), 0.4, 1e-12);
  EXPECT_EQ(p.cells[3].doc["seed"], 7);
  EXPECT_EQ(num(p.cells[3], "methods[0].fx"), 0.1);
  EXPECT_EQ(num(p.cells[2], "render.scale"), 0.1);
}

TEST(SweepSpec, RandomAndLhsAreSeededAndInRange) {
  auto spec = [](const char* kind, int seed) {
    return std::string(R"({")") + kind + R"(": {"count": 10, "seed": )" + std::to_string(seed) +
           R"(, "axes": {"methods[0].a": {"from": 1, "to": 4}, "methods[0].b": {"from": 0.05, "to": 0.8, "log": true}}}})";
  };
  for (const char* kind : {"random", "lhs"}) {
    SCOPED_TRACE(kind);
    auto a = expand_sweep(cfg_of(spec(kind, 3))), b = expand_sweep(cfg_of(spec(kind, 3))),
         c = expand_sweep(cfg_of(spec(kind, 4)));
    ASSERT_EQ(a.cells.size(), 10u);
    EXPECT_EQ(a.hash, b.hash);
    EXPECT_NE(a.hash, c.hash);
    for (auto& cell : a.cells) {
      EXPECT_GE(num(cell, "methods[0].a"), 1);
      EXPECT_LE(num(cell, "methods[0].a"), 4);
      EXPECT_GE(num(cell, "methods[0].b"), 0.05);
      EXPECT_LE(num(cell, "methods[0].b"), 0.8);
    }
  }
  // LHS: each of the 10 strata of each axis holds exactly one sample.
  auto l = expand_sweep(cfg_of(spec("lhs", 3)));
  std::set<int> strata;
  for (auto& cell : l.cells) strata.insert(int((num(cell, "methods[0].a") - 1) / 3 * 10));
  EXPECT_EQ(strata.size(), 10u);
}

TEST(SweepSpec, CellIdsAreStableAndTrackContent) {
  auto a = expand_sweep(cfg_of(R"({"grid": {"methods[0].x": [1, 2, 3]}})"));
  auto b = expand_sweep(cfg_of(R"({"grid": {"methods[0].x": [1, 2, 3]}})"));
  auto c = expand_sweep(cfg_of(R"({"grid": {"methods[0].x": [1, 5, 3]}})"));
  ASSERT_EQ(a.cells.size(), 3u);
  for (size_t i = 0; i < 3; ++i) EXPECT_EQ(a.cells[i].id(), b.cells[i].id());
  EXPECT_EQ(a.cells[0].id(), c.cells[0].id());
  EXPECT_NE(a.cells[1].id(), c.cells[1].id());  // changed config -> new hash, never mixed
  EXPECT_EQ(a.cells[2].id().substr(0, 5), "0002-");
  std::set<std::string> ids;
  for (auto& x : a.cells) ids.insert(x.hash);
  EXPECT_EQ(ids.size(), 3u);
}

TEST(SweepSpec, NoSweepBlockIsOneCell) {
  LoadedConfig c;
  c.file = "r.json";
  c.doc = Json::parse(R"({"name": "r", "methods": [{"method": "full"}]})");
  auto p = expand_sweep(c);
  ASSERT_EQ(p.cells.size(), 1u);
  EXPECT_EQ(p.cells[0].doc, c.doc);
}

TEST(SweepSpec, BadSpecsNameTheJsonPath) {
  struct Case {
    const char* sweep;
    const char* expect;
  };
  std::vector<Case> cases = {
      {R"({"grid": {"methods[0].sigma": []}})", "s.json: sweep.grid.methods[0].sigma: empty axis"},
      {R"({"grid": {"methods[0].sigma": {"from": 2, "to": 1, "step": 0.5}}})",
       "sweep.grid.methods[0].sigma.step"},
      {R"({"zip": {"methods[0].fx": [1, 2, 3], "methods[0].fy": [1, 2]}})",
       "s.json: sweep.zip: zip axes must have equal lengths: \"methods[0].fx\" has 3 values, "
       "\"methods[0].fy\" has 2"},
      {R"({"grid": {"methods[0].sigmaa": [1, 2]}})",
       "s.json: sweep.grid.methods[0].sigmaa: unknown parameter \"sigmaa\" for method \"full\""},
      {R"({"axes": [{"grid": {"render.scale": [0.1]}}, {"grid": {"methods[kfr].alpha": [1]}}]})",
       "sweep.axes[1].grid.methods[kfr].alpha: unknown parameter \"alpha\" for method \"full\""},
      {R"({"grid": {"methods[rmfr].fx": [1]}})",
       "sweep.grid.methods[rmfr].fx: no entry of \"methods\" has label \"rmfr\""},
      {R"({"grid": {"methods[5].fx": [1]}})", "has no element [5]"},
      {R"({"grdi": {"render.scale": [1]}})", "sweep.grdi: unknown key"},
      {R"({"random": {"count": 3, "axes": {"render.scale": {"from": 1, "to": 1}}}})",
       "sweep.random.axes.render.scale: empty axis"},
      {R"({"lhs": {"count": 0, "axes": {"render.scale": {"from": 0, "to": 1}}}})",
       "sweep.lhs.count"},
      {R"({"grid": {"render.scale": {"from": 0, "to": 1}}})",
       "exactly one of \"step\" or \"count\""},
      {R"({"grid": {"render.scale": [1]}, "zip": {"seed": [1]}})", "several under \"axes\""},
      {R"({"list": [{"render.scale": 1}], "objectives": [{"minimise": "x"}]})",
       "sweep.objectives[0]"},
      {R"({"axes": [{"grid": {"render.scale": [1]}}, {"grid": {"render.scale": [2]}}]})",
       "set by two axes"},
      {R"({"grid": {"methods[0].method": ["nope"]}})", "unknown method \"nope\""},
  };
  for (auto& c : cases) {
    SCOPED_TRACE(c.sweep);
    std::string e = err_of(c.sweep);
    EXPECT_NE(e.find(c.expect), std::string::npos) << e;
  }
}

// subject_to: several columns, each with min and/or max (a JOD floor and the frame budget);
// the violation is the sum of how far each value lies outside its bounds.
TEST(SweepSpec, SearchConstraintsMinMaxAndViolation) {
  auto p = expand_sweep(cfg_of(R"({"search": {"space": {"methods[kfr].sigma": {"from": 1.2,
      "to": 3}}, "minimize": "est_ms_total", "subject_to": {"fvvdp_jod_fl": {"min": 9.5},
      "headroom_ms": {"min": 0}, "shaded_fraction": {"min": 0.1, "max": 0.3}}}})"));
  const SearchSpec& s = p.search;
  ASSERT_EQ(s.constraints.size(), 3u);  // in column-name order
  EXPECT_EQ(s.constraints[0].column, "fvvdp_jod_fl");
  EXPECT_EQ(s.constraints[0].describe(), "fvvdp_jod_fl >= 9.5");
  EXPECT_EQ(s.constraints[1].column, "headroom_ms");
  EXPECT_EQ(s.constraints[2].describe(), "0.1 <= shaded_fraction <= 0.3");
  EXPECT_EQ(s.violation({9.6, 0.5, 0.2}), 0.0);
  EXPECT_NEAR(s.violation({9.25, 0.5, 0.2}), 0.25, 1e-12);
  EXPECT_NEAR(s.violation({9.25, -2.0, 0.35}), 0.25 + 2.0 + 0.05, 1e-12);
  EXPECT_EQ(s.violation({9.6, NAN, 0.2}), INFINITY);
  EXPECT_NE(err_of(R"({"search": {"space": {"a": {"from": 0, "to": 1}}, "maximize": "q",
                 "subject_to": {"fvvdp_jod": {"min": 9, "max": 8}}}})")
                .find("sweep.search.subject_to.fvvdp_jod: min 9 is above max 8"),
            std::string::npos);
  EXPECT_NE(err_of(R"({"search": {"space": {"a": {"from": 0, "to": 1}}, "maximize": "q",
                 "subject_to": {"fvvdp_jod": {"above": 9}}}})")
                .find("sweep.search.subject_to.fvvdp_jod: expected"),
            std::string::npos);
}

// sweep.search.p_fit: the budget decision at a stated level, as the constraint p_fit >= level
// and the cells' budget.p_fit; given once.
TEST(SweepSpec, SearchFitLevelIsAConstraintAndTheCellsLevel) {
  auto p = expand_sweep(cfg_of(R"({"search": {"space": {"methods[kfr].sigma": {"from": 1.2,
      "to": 3}}, "maximize": "fvvdp_jod_fl", "p_fit": 0.8,
      "subject_to": {"shaded_fraction": {"max": 0.5}}}})"));
  ASSERT_EQ(p.search.constraints.size(), 2u);
  EXPECT_EQ(p.search.constraints[1].describe(), "p_fit >= 0.8");
  EXPECT_EQ(p.search.violation({0.4, 0.85}), 0.0);  // 0.85 is feasible at 0.8
  EXPECT_GT(p.search.violation({0.4, 0.5}), 0.0);   // 0.5 is not
  EXPECT_EQ(p.base["budget"]["p_fit"], 0.8);
  for (auto& c : p.cells) EXPECT_EQ(c.doc["budget"]["p_fit"], 0.8);
  EXPECT_NE(err_of(R"({"search": {"space": {"a": {"from": 0, "to": 1}}, "maximize": "q",
                 "p_fit": 0.3}})")
                .find("sweep.search.p_fit: value 0.3 is out of range [0.5, 0.99]"),
            std::string::npos)
      << err_of(R"({"search": {"space": {"a": {"from": 0, "to": 1}}, "maximize": "q",
                 "p_fit": 0.3}})");
  EXPECT_NE(err_of(R"({"search": {"space": {"a": {"from": 0, "to": 1}}, "maximize": "q",
                 "p_fit": 0.8, "subject_to": {"p_fit": {"min": 0.9}}}})")
                .find("give the level once"),
            std::string::npos);
}

// Columns named by objectives, pareto, iso_budget and search are checked when the sweep is
// parsed, before any cell runs: every column a run writes (the golden frames.csv of every
// method, and the summary's suffixes) is accepted, a name no cell can produce is refused with
// its JSON path and the names there are.
TEST(SweepSpec, PlanColumnsAreKnownBeforeAnyCellRuns) {
  std::ifstream f(std::string(FOVSIM_SOURCE_DIR) + "/tests/golden/methods_small.frames.csv");
  std::string header;
  std::getline(f, header);
  std::vector<std::string> cols;
  for (size_t a = 0, b; a <= header.size(); a = b + 1) {
    b = header.find(',', a);
    if (b == std::string::npos) b = header.size();
    cols.push_back(header.substr(a, b - a));
  }
  ASSERT_GT(cols.size(), 100u);
  const std::set<std::string> text{"config_id", "method", "label", "gpu", "lighting", "kernel"};
  for (auto& c : cols) {
    if (text.count(c)) {
      EXPECT_EQ(err_of(R"({"grid": {"render.scale": [0.1]}, "objectives": [{"minimize": "psnr"}],
                          "pareto": {"group_by": [")" +
                       c + R"("]}})"),
                "(no error)")
          << c;
      continue;
    }
    for (const std::string suffix : {"", "_ci95"})
      EXPECT_EQ(err_of(R"({"grid": {"render.scale": [0.1]}, "objectives": [{"minimize": ")" + c +
                       suffix + R"("}]})"),
                "(no error)")
          << c << suffix;
  }
  for (const std::string c :
       {"frames", "est_ms_total_p95", "headroom_ms", "fits_budget", "fvvdp_jod_lo", "psnr_saccade",
        "frames_lost", "shaded_fraction_held_ci95", "render.scale", "startup_frames", "p_fit",
        "fit_level", "fit_threshold_ms"})
    EXPECT_EQ(err_of(R"({"grid": {"render.scale": [0.1]}, "objectives": [{"maximize": ")" + c +
                     R"("}]})"),
              "(no error)")
        << c;
  // Every column summarize writes (a new one must join the vocabulary, plan_columns.cpp).
  ResultTable fr;
  for (int i = 0; i < 4; ++i) {
    ResultRow r;
    r.set_text("config_id", "a");
    r.set_text("gpu", "g");
    r.set("frame", i);
    r.set("est_ms_total", 5 + i);
    r.set("psnr", 30 + i);
    fr.add(r);
  }
  for (auto& c : summarize(fr, 11.1).numeric_columns())
    EXPECT_EQ(err_of(R"({"grid": {"render.scale": [0.1]}, "objectives": [{"maximize": ")" + c +
                     R"("}]})"),
              "(no error)")
        << c;
  const std::string e = err_of(R"({"grid": {"render.scale": [0.1]},
      "objectives": [{"minimize": "est_ms_total"}, {"maximize": "fpsnr_x"}]})");
  EXPECT_NE(e.find("s.json: sweep.objectives[1]: no numeric column \"fpsnr_x\" can be in a "
                   "cell's summary (did you mean \"fpsnr\"?); checked before any cell runs "
                   "(columns: "),
            std::string::npos)
      << e;
  EXPECT_NE(e.find(", est_ms_total, "), std::string::npos) << e;
  EXPECT_NE(err_of(R"({"grid": {"render.scale": [0.1]}, "objectives": [{"minimize": "psnr"}],
                      "pareto": {"group_by": ["gpu", "scene_typo"]}})")
                .find("sweep.pareto.group_by: no column \"scene_typo\" can be in a cell's summary"),
            std::string::npos);
  EXPECT_NE(err_of(R"({"grid": {"render.scale": [0.1]},
                      "iso_budget": {"column": "shaded", "budgets": [0.5]}})")
                .find("sweep.iso_budget.column: no numeric column \"shaded\""),
            std::string::npos);
  EXPECT_NE(err_of(R"({"grid": {"render.scale": [0.1]}, "objectives": [{"minimize": "label"}]})")
                .find("sweep.objectives[0]: no numeric column \"label\""),
            std::string::npos);
  EXPECT_NE(err_of(R"({"search": {"space": {"render.scale": {"from": 0.1, "to": 0.2}},
                      "maximize": "psnr", "subject_to": {"ms": {"max": 11}}}})")
                .find("sweep.search.subject_to.ms: no numeric column \"ms\""),
            std::string::npos);
}

// sweep.search.methods: a method axis, one space per method entry; per_method() gives one
// search per entry (its space, its label, its own seed).
TEST(SweepSpec, SearchMethodAxisGivesOneSearchPerMethod) {
  auto p = expand_sweep(cfg_of(R"({"search": {"methods": {
      "full": {"space": {"render.scale": {"from": 0.05, "to": 0.1}}},
      "kfr": {"space": {"methods[kfr].sigma": {"from": 1.2, "to": 3}}}},
      "maximize": "fpsnr", "evaluations": 4}})"));
  ASSERT_TRUE(p.search.enabled());
  EXPECT_TRUE(p.search.space.empty());
  const std::vector<SearchSpec> ms = p.search.per_method();
  ASSERT_EQ(ms.size(), 2u);
  EXPECT_EQ(ms[0].select_label, "full");
  EXPECT_EQ(ms[1].select_label, "kfr");
  EXPECT_EQ(ms[1].space.at(0).path, "methods[kfr].sigma");
  EXPECT_NE(ms[0].seed, ms[1].seed);
  EXPECT_EQ(ms[1].evaluations, 4);
  EXPECT_EQ(p.search.per_method().size(), 2u);
  EXPECT_NE(err_of(R"({"search": {"methods": {"kfr": {"space": {"methods[kfr].sigma":
                 {"from": 1.2, "to": 3}}}}, "maximize": "fpsnr"}})")
                .find("sweep.search.methods: expected"),
            std::string::npos);  // one method needs no axis
  EXPECT_NE(err_of(R"({"search": {"methods": {"kfr": {"space": {}}, "full": {"space": {}}},
                 "space": {"a": {"from": 0, "to": 1}}, "maximize": "fpsnr"}})")
                .find("give either \"methods\""),
            std::string::npos);
  const std::string e = err_of(R"({"search": {"methods": {
      "full": {"space": {"render.scale": {"from": 0.05, "to": 0.1}}},
      "rmfr": {"space": {"render.scale": {"from": 0.05, "to": 0.1}}}}, "maximize": "fpsnr"}})");
  EXPECT_NE(e.find("sweep.search.methods.rmfr"), std::string::npos) << e;  // no such entry
}
