// The reference cache through the engine (sim/experiment/reference_cache.h): results with and
// without it are bit-identical (every column but the wall times), on a scene with indirect
// light (cached all-VPL indirect), with VPL visibility (no indirect cache) and without indirect
// light; a second run that changes only a method takes every frame from the cache; a damaged
// entry is ignored with a warning and recomputed; a changed render setting misses; bad `cache`
// keys are located errors.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "sim/core/error.h"
#include "sim/experiment/runner.h"
#include "tests/common/csv_without_times.h"

using namespace fovsim;
namespace fs = std::filesystem;

namespace {

std::string tmp(const std::string& name) {
  return (fs::temp_directory_path() /
          ("fovsim_refcache_" + name + "_" + std::to_string(::getpid())))
      .string();
}

LoadedConfig config(const Json& scene, int spp, const std::string& cache_dir, double kfr_sigma) {
  LoadedConfig c;
  c.file = "refcache.json";
  c.doc = Json{
      {"name", "refcache"},
      {"display", "htc_vive_pro_eye"},
      {"render", {{"scale", 0.05}, {"spp", spp}}},
      {"scene", scene},
      {"trace", {{"synthetic", {{"scenario", "walk-through"}, {"seed", 3}, {"duration", 0.1}}}}},
      {"frames", {{"count", 3}}},
      {"methods",
       Json::array({Json{{"method", "full"}}, Json{{"method", "kfr"}, {"sigma", kfr_sigma}},
                    Json{{"method", "twfr"}},  // asks for motion vectors
                    Json{{"method", "fvrs"}}})},
      {"outputs", {{"print_summary", false}}},
      {"cache", {{"dir", cache_dir}}}};
  return c;
}

RunResult run(const LoadedConfig& c, bool use_cache, const std::string& out) {
  RunOptions o;
  o.out_dir = out;
  o.models_dir = std::string(FOVSIM_SOURCE_DIR) + "/models";
  o.print_summary = false;
  o.use_cache = use_cache;
  return run_experiment(c, o);
}

using test::csv_without_times;

Json manifest(const std::string& out) {
  return Params::parse_json_file(out + "/manifest.json");
}

std::vector<fs::path> entries(const std::string& dir) {
  std::vector<fs::path> v;
  for (auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file() && e.path().extension() == ".fce") v.push_back(e.path());
  std::sort(v.begin(), v.end());
  return v;
}

}  // namespace

TEST(ReferenceCache, ResultsBitIdenticalWithAndWithoutIt) {
  struct Case {
    const char* name;
    Json scene;
    int spp;
  };
  const std::vector<Case> cases = {
      {"indirect_spp4",
       Json{{"type", "atrium"}, {"complexity", 1}, {"indirect", true}, {"vpl", {{"rsm_size", 8}}}},
       4},
      {"vpl_visibility",
       Json{{"type", "cornell"}, {"vpl", {{"rsm_size", 4}, {"shadow_rays", true}}}}, 1},
      {"direct_only", Json{{"type", "atrium"}, {"complexity", 1}}, 1},
  };
  for (const Case& cs : cases) {
    SCOPED_TRACE(cs.name);
    const std::string dir = tmp(std::string("cache_") + cs.name);
    fs::remove_all(dir);
    // The truth: no cache.
    RunResult plain = run(config(cs.scene, cs.spp, dir, 1.8), false, tmp("plain"));
    EXPECT_FALSE(manifest(tmp("plain"))["reference_cache"]["used"].get<bool>());
    EXPECT_FALSE(fs::exists(dir));
    // First run with the cache: every frame computed and written.
    RunResult first = run(config(cs.scene, cs.spp, dir, 1.8), true, tmp("first"));
    Json m1 = manifest(tmp("first"))["reference_cache"];
    EXPECT_EQ(m1["frames_from_cache"].get<int>(), 0);
    EXPECT_EQ(m1["frames_computed"].get<int>(), 3);
    EXPECT_EQ(m1["writes"].get<int>(), 3);
    EXPECT_EQ(csv_without_times(first.frames.to_csv()), csv_without_times(plain.frames.to_csv()));
    // Second run, a method parameter changed: every reference from the cache.
    RunResult second = run(config(cs.scene, cs.spp, dir, 2.4), true, tmp("second"));
    RunResult second_plain = run(config(cs.scene, cs.spp, dir, 2.4), false, tmp("second_plain"));
    Json m2 = manifest(tmp("second"))["reference_cache"];
    EXPECT_EQ(m2["frames_from_cache"].get<int>(), 3);
    EXPECT_EQ(m2["frames_computed"].get<int>(), 0);
    EXPECT_EQ(m2["ignored"].get<int>(), 0);
    EXPECT_EQ(csv_without_times(second.frames.to_csv()),
              csv_without_times(second_plain.frames.to_csv()));
    EXPECT_EQ(csv_without_times(second.summary.to_csv()),
              csv_without_times(second_plain.summary.to_csv()));
    EXPECT_TRUE(second.warnings.empty());
    fs::remove_all(dir);
  }
  for (const char* o : {"plain", "first", "second", "second_plain"}) fs::remove_all(tmp(o));
}

TEST(ReferenceCache, DamagedEntryIsIgnoredWithAWarningAndRecomputed) {
  const Json scene{
      {"type", "atrium"}, {"complexity", 1}, {"indirect", true}, {"vpl", {{"rsm_size", 8}}}};
  const std::string dir = tmp("damaged");
  fs::remove_all(dir);
  RunResult plain = run(config(scene, 1, dir, 1.8), false, tmp("d_plain"));
  run(config(scene, 1, dir, 1.8), true, tmp("d_first"));
  auto files = entries(dir + "/references");  // the method memo's entries are in "methods"
  ASSERT_EQ(files.size(), 3u);
  fs::resize_file(files[0], fs::file_size(files[0]) / 2);  // a copy cut short
  RunResult again = run(config(scene, 1, dir, 1.8), true, tmp("d_again"));
  Json m = manifest(tmp("d_again"))["reference_cache"];
  EXPECT_EQ(m["frames_from_cache"].get<int>(), 2);
  EXPECT_EQ(m["frames_computed"].get<int>(), 1);
  EXPECT_EQ(m["ignored"].get<int>(), 1);
  EXPECT_EQ(m["writes"].get<int>(), 1);  // written again
  ASSERT_EQ(again.warnings.size(), 1u);
  EXPECT_NE(again.warnings[0].find("reference cache: cache entry " + files[0].string()),
            std::string::npos)
      << again.warnings[0];
  EXPECT_NE(again.warnings[0].find("truncated"), std::string::npos) << again.warnings[0];
  EXPECT_EQ(csv_without_times(again.frames.to_csv()), csv_without_times(plain.frames.to_csv()));
  // Repaired: the next run reads all three.
  run(config(scene, 1, dir, 1.8), true, tmp("d_third"));
  EXPECT_EQ(manifest(tmp("d_third"))["reference_cache"]["frames_from_cache"].get<int>(), 3);
  fs::remove_all(dir);
  for (const char* o : {"d_plain", "d_first", "d_again", "d_third"}) fs::remove_all(tmp(o));
}

TEST(ReferenceCache, WhatTheReferenceDependsOnIsInTheKey) {
  const Json scene{{"type", "atrium"}, {"complexity", 1}};
  const std::string dir = tmp("key");
  fs::remove_all(dir);
  run(config(scene, 1, dir, 1.8), true, tmp("k0"));
  auto from_cache = [&](LoadedConfig c) {
    run(c, true, tmp("k1"));
    return manifest(tmp("k1"))["reference_cache"]["frames_from_cache"].get<int>();
  };
  EXPECT_EQ(from_cache(config(scene, 1, dir, 1.8)), 3);
  EXPECT_EQ(from_cache(config(scene, 4, dir, 1.8)), 0);  // render.spp
  LoadedConfig c = config(scene, 1, dir, 1.8);
  c.doc["render"]["scale"] = 0.06;  // another camera
  EXPECT_EQ(from_cache(c), 0);
  c = config(Json{{"type", "atrium"}, {"complexity", 2}}, 1, dir, 1.8);  // another scene
  EXPECT_EQ(from_cache(c), 0);
  c = config(scene, 1, dir, 1.8);
  c.doc["trace"]["synthetic"]["seed"] = 4;  // other poses
  EXPECT_EQ(from_cache(c), 0);
  c = config(scene, 1, dir, 1.8);
  c.doc["frames"]["count"] = 2;  // a shorter run reuses the frames it shares
  EXPECT_EQ(from_cache(c), 2);
  c = config(scene, 1, dir, 1.8);
  c.doc["metrics"] = Json{{"fvvdp", false}};  // nothing the reference depends on
  c.doc["gpus"] = Json::array({"rtx2070"});
  EXPECT_EQ(from_cache(c), 3);
  c = config(scene, 1, dir, 1.8);
  c.doc["cache"]["enabled"] = false;
  run(c, true, tmp("k1"));
  EXPECT_FALSE(manifest(tmp("k1"))["reference_cache"]["used"].get<bool>());
  fs::remove_all(dir);
  fs::remove_all(tmp("k0"));
  fs::remove_all(tmp("k1"));
}

TEST(ReferenceCache, BadKeysAreLocatedErrors) {
  const Json scene{{"type", "atrium"}, {"complexity", 1}};
  auto message = [&](const Json& cache) {
    LoadedConfig c = config(scene, 1, tmp("bad"), 1.8);
    c.doc["cache"] = cache;
    try {
      run(c, true, tmp("bad_out"));
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(Json{{"max_gb", -1}}).find("refcache.json: cache.max_gb"), std::string::npos);
  EXPECT_NE(message(Json{{"note_mb", -1}}).find("refcache.json: cache.note_mb"), std::string::npos);
  EXPECT_NE(message(Json{{"max_gb", "10"}}).find("cache.max_gb"), std::string::npos);
  EXPECT_NE(message(Json{{"enabled", 1}}).find("cache.enabled"), std::string::npos);
  EXPECT_NE(message(Json{{"dirr", "x"}}).find("cache.dirr"), std::string::npos);
  EXPECT_FALSE(fs::exists(tmp("bad")));
  fs::remove_all(tmp("bad_out"));
}
