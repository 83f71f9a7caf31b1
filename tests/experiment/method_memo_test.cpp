// The method memo (sim/experiment/method_memo.h) through the engine: a second run that changes
// one method entry computes only that entry and gives byte-identical frames.csv, summary.csv,
// paired.csv (but for the wall times ref_ms and sim_ms) and images to a run without any cache,
// and the manifest names the memoised entries; a changed metric setting or trace window
// misses; a damaged entry is recomputed with a warning; --target and a run without the cache
// do not memoise.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "sim/core/files.h"
#include "sim/experiment/runner.h"
#include "tests/common/csv_without_times.h"

using namespace fovsim;
namespace fs = std::filesystem;

namespace {

std::string tmp(const std::string& name) {
  return (fs::temp_directory_path() / ("fovsim_memo_" + name + "_" + std::to_string(::getpid())))
      .string();
}

// Small: render.scale 0.1 (really 0.05 of the Vive Pro Eye), three frames after one warm-up
// frame, one saved frame with every image kind, indirect light, every metric incl. `_fl`.
LoadedConfig config(const std::string& cache_dir, double kfr_sigma) {
  LoadedConfig c;
  c.file = "memo.json";
  c.doc = Json{
      {"name", "memo"},
      {"display", "htc_vive_pro_eye"},
      {"render", {{"scale", 0.05}}},
      {"scene",
       {{"type", "atrium"}, {"complexity", 1}, {"indirect", true}, {"vpl", {{"rsm_size", 8}}}}},
      {"trace", {{"synthetic", {{"scenario", "walk-through"}, {"seed", 3}, {"duration", 0.1}}}}},
      {"frames", {{"count", 3}, {"warmup", 1}}},
      {"methods",
       Json::array({Json{{"method", "full"}}, Json{{"method", "kfr"}, {"sigma", kfr_sigma}},
                    Json{{"method", "twfr"}}, Json{{"method", "fvrs"}}})},
      {"outputs",
       {{"print_summary", false},
        {"image_frames", Json::array({2})},
        {"exr", true},
        {"error_images", true},
        {"debug_images", true}}},
      {"cache", {{"dir", cache_dir}}}};
  return c;
}

RunResult run(const LoadedConfig& c, bool use_cache, const std::string& out,
              std::vector<std::string> targets = {}) {
  RunOptions o;
  o.out_dir = out;
  o.models_dir = std::string(FOVSIM_SOURCE_DIR) + "/models";
  o.print_summary = false;
  o.use_cache = use_cache;
  o.targets = std::move(targets);
  return run_experiment(c, o);
}

// A CSV file without the wall-time columns (ref_ms, sim_ms and their intervals).
std::string without_times(const std::string& path) {
  return test::csv_without_times(read_file(path));
}

Json manifest(const std::string& out) {
  return Params::parse_json_file(out + "/manifest.json");
}

std::vector<std::string> memoised(const std::string& out) {
  std::vector<std::string> v;
  const Json m = manifest(out);  // kept: a loop over a temporary's member would dangle
  for (auto& x : m["memoised_methods"]) v.push_back(x.get<std::string>());
  return v;
}

// Every file under `dir` (relative name, bytes).
std::vector<std::pair<std::string, std::string>> files(const std::string& dir) {
  std::vector<std::pair<std::string, std::string>> v;
  for (auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file())
      v.emplace_back(fs::relative(e.path(), dir).string(), read_file(e.path().string()));
  std::sort(v.begin(), v.end());
  return v;
}

void expect_same_outputs(const std::string& a, const std::string& b) {
  for (const char* f : {"frames.csv", "summary.csv", "paired.csv"})
    EXPECT_EQ(without_times(a + "/" + f), without_times(b + "/" + f)) << f;
  const auto ia = files(a + "/images"), ib = files(b + "/images");
  ASSERT_EQ(ia.size(), ib.size());
  EXPECT_GT(ia.size(), 20u);  // reference, each method's png, exr, error, flip, heat, debug maps
  for (size_t i = 0; i < ia.size(); ++i) {
    EXPECT_EQ(ia[i].first, ib[i].first);
    EXPECT_TRUE(ia[i].second == ib[i].second) << ia[i].first << " differs";
  }
}

void remove_all(const std::string& dir, std::initializer_list<const char*> outs) {
  fs::remove_all(dir);
  for (const char* o : outs) fs::remove_all(tmp(o));
}

}  // namespace

TEST(MethodMemo, SecondRunComputesOnlyTheChangedMethodByteIdentically) {
  const std::string dir = tmp("cache");
  fs::remove_all(dir);
  run(config(dir, 1.8), true, tmp("first"));
  EXPECT_TRUE(memoised(tmp("first")).empty());
  EXPECT_TRUE(manifest(tmp("first"))["method_memo"]["used"].get<bool>());
  EXPECT_EQ(manifest(tmp("first"))["method_memo"]["writes"].get<int>(), 4);
  RunResult second = run(config(dir, 2.4), true, tmp("second"));
  run(config(dir, 2.4), false, tmp("plain"));
  // The config's methods but the changed kfr (a subset).
  EXPECT_EQ(memoised(tmp("second")), (std::vector<std::string>{"full", "twfr", "fvrs"}));
  const Json mm = manifest(tmp("second"))["method_memo"];
  EXPECT_EQ(mm["hits"].get<int>(), 3);
  EXPECT_EQ(mm["writes"].get<int>(), 1);  // kfr with sigma 2.4
  EXPECT_TRUE(second.warnings.empty());
  expect_same_outputs(tmp("second"), tmp("plain"));
  // A third run finds all four.
  run(config(dir, 2.4), true, tmp("third"));
  EXPECT_EQ(memoised(tmp("third")).size(), 4u);
  expect_same_outputs(tmp("third"), tmp("plain"));
  // Without the cache (--no-cache) nothing is memoised.
  EXPECT_FALSE(manifest(tmp("plain"))["method_memo"]["used"].get<bool>());
  EXPECT_TRUE(memoised(tmp("plain")).empty());
  remove_all(dir, {"first", "second", "plain", "third"});
}

TEST(MethodMemo, WhatTheMethodsDependOnIsInTheKey) {
  const std::string dir = tmp("key");
  fs::remove_all(dir);
  run(config(dir, 1.8), true, tmp("k0"));
  auto n_memoised = [&](const LoadedConfig& c) {
    run(c, true, tmp("k1"));
    return memoised(tmp("k1")).size();
  };
  EXPECT_EQ(n_memoised(config(dir, 1.8)), 4u);
  LoadedConfig c = config(dir, 1.8);
  c.doc["metrics"] = Json{{"fovea_deg", 4.0}};  // a metric setting
  EXPECT_EQ(n_memoised(c), 0u);
  c = config(dir, 1.8);
  c.doc["frames"]["count"] = 2;  // the trace window
  EXPECT_EQ(n_memoised(c), 0u);
  c = config(dir, 1.8);
  c.doc["frames"]["warmup"] = 0;  // the warm-up frames
  EXPECT_EQ(n_memoised(c), 0u);
  c = config(dir, 1.8);
  c.doc["render"]["tonemap"] = Json{{"exposure", 1.5}};  // what the methods' images look like
  EXPECT_EQ(n_memoised(c), 0u);
  c = config(dir, 1.8);
  c.doc["gpus"] = Json::array({"rtx2070"});  // only the cost model: rows built anew
  EXPECT_EQ(n_memoised(c), 4u);
  c = config(dir, 1.8);
  c.doc["cache"]["enabled"] = false;
  EXPECT_EQ(n_memoised(c), 0u);
  EXPECT_FALSE(manifest(tmp("k1"))["method_memo"]["used"].get<bool>());
  remove_all(dir, {"k0", "k1"});
}

TEST(MethodMemo, DamagedEntryIsRecomputedWithAWarning) {
  const std::string dir = tmp("damaged");
  fs::remove_all(dir);
  run(config(dir, 1.8), true, tmp("d_first"));
  run(config(dir, 1.8), false, tmp("d_plain"));
  std::vector<fs::path> entries;
  for (auto& e : fs::recursive_directory_iterator(dir + "/methods"))
    if (e.is_regular_file() && e.path().extension() == ".fce") entries.push_back(e.path());
  ASSERT_EQ(entries.size(), 4u);
  for (auto& p : entries) {  // flip one byte in the middle of each (the checksum fails)
    std::string b = read_file(p.string());
    b[b.size() / 2] = char(b[b.size() / 2] ^ 0x5a);
    write_file_atomic(p.string(), b);
  }
  RunResult again = run(config(dir, 1.8), true, tmp("d_again"));
  EXPECT_TRUE(memoised(tmp("d_again")).empty());
  EXPECT_EQ(manifest(tmp("d_again"))["method_memo"]["ignored"].get<int>(), 4);
  EXPECT_EQ(manifest(tmp("d_again"))["method_memo"]["writes"].get<int>(), 4);
  ASSERT_FALSE(again.warnings.empty());
  EXPECT_NE(again.warnings[0].find("method memo: cache entry"), std::string::npos)
      << again.warnings[0];
  expect_same_outputs(tmp("d_again"), tmp("d_plain"));
  run(config(dir, 1.8), true, tmp("d_third"));  // repaired
  EXPECT_EQ(memoised(tmp("d_third")).size(), 4u);
  remove_all(dir, {"d_first", "d_plain", "d_again", "d_third"});
}

TEST(MethodMemo, TargetRunsDoNotMemoise) {
  const std::string dir = tmp("target");
  fs::remove_all(dir);
  run(config(dir, 1.8), true, tmp("t0"));
  run(config(dir, 1.8), true, tmp("t1"), {"est_ms_total:50%"});
  EXPECT_FALSE(manifest(tmp("t1"))["method_memo"]["used"].get<bool>());
  EXPECT_TRUE(memoised(tmp("t1")).empty());
  remove_all(dir, {"t0", "t1"});
}
