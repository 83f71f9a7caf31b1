// Sweep specs fail with located errors (never a std::exception that would end as
// "internal error"), the cell product is capped before any cell is built, and shard
// variables from the environment are parsed strictly.
#include <gtest/gtest.h>

#include <cstdlib>
#include <functional>

#include "sim/core/error.h"
#include "sim/experiment/sweep_runner.h"
#include "sim/experiment/sweep_spec.h"

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

std::string err_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("NOT A fovsim::Error: ") + e.what();
  }
  return "(no error)";
}

std::string sweep_err(const std::string& sweep_json) {
  return err_of([&] { validate_cells(expand_sweep(cfg_of(sweep_json))); });
}

std::string thousand() {
  std::string s = "[";
  for (int i = 0; i < 1000; ++i) s += (i ? "," : "") + std::to_string(i);
  return s + "]";
}

struct ScopedEnv {
  std::string name;
  ScopedEnv(const char* n, const char* v) : name(n) { ::setenv(n, v, 1); }
  ~ScopedEnv() { ::unsetenv(name.c_str()); }
};

}  // namespace

TEST(SweepLimits, HugeIndexIsAMissingElement) {
  std::string e = sweep_err(R"({"grid": {"methods[99999999999999999999999].sigma": [1, 2]}})");
  EXPECT_EQ(e,
            "s.json: sweep.grid.methods[99999999999999999999999].sigma: \"methods\" has no element "
            "[99999999999999999999999] (it has 2)");
  e = sweep_err(R"({"grid": {"methods[4294967296].sigma": [1]}})");
  EXPECT_NE(e.find("has no element [4294967296]"), std::string::npos) << e;
}

TEST(SweepLimits, CellProductCappedBeforeExpansion) {
  // Three axes of 1000 values: 1e9 cells, refused at once (not after exhausting memory).
  std::string t = thousand();
  std::string e = sweep_err(R"({"grid": {"a": )" + t + R"(, "b": )" + t + R"(, "c": )" + t + "}}");
  EXPECT_EQ(e,
            "s.json: sweep.grid: expands to at least 1000000 cells, over the limit of 100000 (set "
            "sweep.max_cells, up "
            "to 10000000)");
  // Across blocks too.
  e = sweep_err(R"({"axes": [{"grid": {"a": )" + t +
                R"(}}, {"list": [{"b": 1}, {"b": 2}]}, {"zip": {"c": )" + t + "}}]}");
  EXPECT_NE(e.find("s.json: sweep: expands to 2000000 cells, over the limit of 100000"),
            std::string::npos)
      << e;
  e = sweep_err(R"({"random": {"count": 200000, "axes": {"a": {"from": 0, "to": 1}}}})");
  EXPECT_NE(e.find("sweep.random.count: expands to 200000 cells"), std::string::npos) << e;
  e = sweep_err(
      R"({"zip": {"a": {"from": 0, "to": 199999, "step": 1}, "b": {"from": 0, "to": 199999, "step": 1}}})");
  EXPECT_NE(e.find("sweep.zip: expands to 200000 cells, over the limit of 100000"),
            std::string::npos)
      << e;
  // The limit is overridable (within [1, 1e7]) and applies as set.
  auto plan = expand_sweep(cfg_of(R"({"max_cells": 3, "grid": {"a": [1, 2, 3]}})"));
  EXPECT_EQ(plan.cells.size(), 3u);
  e = sweep_err(R"({"max_cells": 2, "grid": {"a": [1, 2, 3]}})");
  EXPECT_NE(e.find("expands to 3 cells, over the limit of 2"), std::string::npos) << e;
  e = sweep_err(R"({"max_cells": 1e300, "grid": {"a": [1]}})");
  EXPECT_EQ(e, "s.json: sweep.max_cells: value 1e+300 is out of range [1, 1e+07]");
}

TEST(SweepLimits, BadTypesAreLocatedErrors) {
  for (
      auto [spec, expect] : std::vector<std::pair<std::string, std::string>>{
          {R"({"grid": {"a": [1]}, "iso_budget": {"column": "x", "budgets": [1], "group_by": [1]}})",
           "sweep.iso_budget.group_by: expected column names"},
          {R"({"grid": {"a": [1]}, "iso_budget": {"column": "x", "budgets": [1], "group_by": "gpu"}})",
           "sweep.iso_budget.group_by: expected an array"},
          {R"({"grid": {"a": [1]}, "pareto": [1]})", "sweep.pareto: expected an object"},
          {R"({"search": {"space": {"a": {"from": 0, "to": 1}}, "maximize": "q", "evaluations": 1e300}})",
           "sweep.search.evaluations: value 1e+300 is out of range [1, 1e+05]"},
          {R"({"search": {"space": {"a": {"from": 0, "to": 1}}, "maximize": "q", "seed": -1}})",
           "sweep.search.seed: value -1 is out of range [0, 9007199254740992]"},
          {R"({"random": {"count": 2, "seed": 1e300, "axes": {"a": {"from": 0, "to": 1}}}})",
           "sweep.random.seed: expected an integer in [0, 2^53]"},
      }) {
    std::string e = sweep_err(spec);
    EXPECT_NE(e.find(expect), std::string::npos) << spec << " -> " << e;
    EXPECT_EQ(e.find("NOT A fovsim::Error"), std::string::npos) << e;
  }
}

TEST(SweepLimits, SlurmVariablesParsedStrictly) {
  int i = -1, n = -1;
  ::unsetenv("SLURM_ARRAY_TASK_ID");
  ::unsetenv("SLURM_ARRAY_TASK_COUNT");
  ::unsetenv("SLURM_ARRAY_TASK_MIN");
  EXPECT_FALSE(shard_from_env(i, n));
  {
    ScopedEnv id("SLURM_ARRAY_TASK_ID", "abc"), cnt("SLURM_ARRAY_TASK_COUNT", "4");
    EXPECT_EQ(err_of([&] { shard_from_env(i, n); }),
              "environment SLURM_ARRAY_TASK_ID=\"abc\": expected an integer in [0, 1000000000]");
  }
  {
    ScopedEnv id("SLURM_ARRAY_TASK_ID", "1"), cnt("SLURM_ARRAY_TASK_COUNT", "4x");
    EXPECT_NE(err_of([&] { shard_from_env(i, n); }).find("SLURM_ARRAY_TASK_COUNT=\"4x\""),
              std::string::npos);
  }
  {
    ScopedEnv id("SLURM_ARRAY_TASK_ID", "6"), cnt("SLURM_ARRAY_TASK_COUNT", "4"),
        mn("SLURM_ARRAY_TASK_MIN", "5");
    EXPECT_TRUE(shard_from_env(i, n));
    EXPECT_EQ(i, 1);
    EXPECT_EQ(n, 4);
  }
  {
    ScopedEnv id("SLURM_ARRAY_TASK_ID", "9"), cnt("SLURM_ARRAY_TASK_COUNT", "4");
    EXPECT_NE(err_of([&] { shard_from_env(i, n); }).find("must be contiguous"), std::string::npos);
  }
}
