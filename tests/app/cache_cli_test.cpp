// The reference cache from the command line (configs/README.md "cache"): `fovsim run` uses it by
// default (here in a temporary FOVSIM_CACHE_DIR), a second run takes every reference from it
// with the same frames.csv, `--no-cache` and FOVSIM_NO_CACHE leave it alone, a sweep's shards
// reuse each other's frames, and a bad `cache` key is one located line with exit code 2.
#include <gtest/gtest.h>

#include <filesystem>

#include "app_util.h"

using namespace fovsim_test;
namespace fs = std::filesystem;

namespace {

const char* kConfig = R"({
  "name": "cache_cli",
  "display": "htc_vive_pro_eye",
  "render": {"scale": 0.05, "spp": 4},
  "scene": {"type": "atrium", "complexity": 1, "indirect": true, "vpl": {"rsm_size": 8}},
  "trace": {"synthetic": {"scenario": "walk-through", "seed": 5, "duration": 0.1}},
  "frames": {"count": 3},
  "methods": [{"method": "full"}, {"method": "kfr", "sigma": 1.8}],
  "outputs": {"print_summary": false}
})";

// The frames.csv without its wall-time columns.
std::string frames_without_times(const std::string& dir) {
  Csv c = read_csv(dir + "/frames.csv");
  std::string s;
  for (auto& r : c.rows) {
    for (size_t k = 0; k < c.header.size(); ++k)
      if (c.header[k] != "sim_ms" && c.header[k] != "ref_ms") s += r[k] + ",";
    s += "\n";
  }
  return s;
}

std::string cache_record(const std::string& dir) {
  std::string m = read_text(dir + "/manifest.json");
  auto p = m.find("\"reference_cache\"");
  return p == std::string::npos ? "" : m.substr(p, m.find('}', p) - p);
}

}  // namespace

TEST(CacheCli, SecondRunReadsEveryReferenceAndMatches) {
  const std::string dir = temp_dir("cache_cli");
  write_text(dir + "/c.json", kConfig);
  // FOVSIM_NO_CACHE is set for the test binary (tests/app/main.cpp): unset for these commands.
  const std::string env = "env -u FOVSIM_NO_CACHE FOVSIM_CACHE_DIR=" + dir + "/cache ";
  auto a = run_cmd(env + fovsim_bin() + " run " + dir + "/c.json -q --no-plots -o " + dir + "/a");
  ASSERT_EQ(a.code, 0) << a.output;
  EXPECT_NE(cache_record(dir + "/a").find("\"frames_computed\": 3"), std::string::npos)
      << cache_record(dir + "/a");
  EXPECT_TRUE(fs::exists(dir + "/cache/references"));
  auto b = run_cmd(env + fovsim_bin() + " run " + dir + "/c.json -q --no-plots -o " + dir +
                   "/b methods[1].sigma=2.4");
  ASSERT_EQ(b.code, 0) << b.output;
  EXPECT_NE(cache_record(dir + "/b").find("\"frames_from_cache\": 3"), std::string::npos)
      << cache_record(dir + "/b");
  auto c = run_cmd(env + fovsim_bin() + " run " + dir + "/c.json -q --no-plots --no-cache -o " +
                   dir + "/c methods[1].sigma=2.4");
  ASSERT_EQ(c.code, 0) << c.output;
  EXPECT_NE(cache_record(dir + "/c").find("\"used\": false"), std::string::npos);
  EXPECT_EQ(frames_without_times(dir + "/b"), frames_without_times(dir + "/c"));
  // FOVSIM_NO_CACHE=1 (what this test binary sets) turns it off too.
  auto d = run_cmd("FOVSIM_NO_CACHE=1 FOVSIM_CACHE_DIR=" + dir + "/cache2 " + fovsim_bin() +
                   " run " + dir + "/c.json -q --no-plots -o " + dir + "/d");
  ASSERT_EQ(d.code, 0) << d.output;
  EXPECT_FALSE(fs::exists(dir + "/cache2"));
  // No folder at all (no HOME): a warning, the run goes on without the cache.
  auto e =
      run_cmd("cd " + dir + " && env -u FOVSIM_NO_CACHE -u FOVSIM_CACHE_DIR -u XDG_CACHE_HOME " +
              "-u HOME " + fovsim_bin() + " run " + dir + "/c.json -q --no-plots -o " + dir + "/e");
  ASSERT_EQ(e.code, 0) << e.output;
  EXPECT_NE(e.output.find("warning: reference cache: no folder"), std::string::npos) << e.output;
  EXPECT_FALSE(fs::exists(dir + "/references"));
  fs::remove_all(dir);
}

TEST(CacheCli, SweepShardsShareTheCache) {
  const std::string dir = temp_dir("cache_sweep");
  std::string cfg = kConfig;
  cfg.insert(cfg.rfind('}'),
             R"(, "sweep": {"grid": {"methods[kfr].sigma": [1.6, 2.0, 2.4, 2.8]}})");
  write_text(dir + "/s.json", cfg);
  const std::string env = "env -u FOVSIM_NO_CACHE FOVSIM_CACHE_DIR=" + dir + "/cache ";
  auto s0 = run_cmd(env + fovsim_bin() + " sweep " + dir + "/s.json --no-plots --shard 0/2 -o " +
                    dir + "/o");
  ASSERT_EQ(s0.code, 0) << s0.output;
  EXPECT_EQ(s0.output.find("from the reference cache"), std::string::npos) << s0.output;
  auto s1 = run_cmd(env + fovsim_bin() + " sweep " + dir + "/s.json --no-plots --shard 1/2 -o " +
                    dir + "/o");
  ASSERT_EQ(s1.code, 0) << s1.output;
  EXPECT_NE(s1.output.find("(3 references, 3 from the reference cache)"), std::string::npos)
      << s1.output;
  fs::remove_all(dir);
}

// `fovsim fidelity`, `converge` and `search` read and write the same cache: a ladder run twice
// renders no reference the second time, and --no-cache leaves the folder alone.
TEST(CacheCli, FidelityConvergeAndSearchUseTheCache) {
  const std::string dir = temp_dir("cache_cmds");
  write_text(dir + "/c.json", kConfig);
  const std::string env = "env -u FOVSIM_NO_CACHE FOVSIM_CACHE_DIR=" + dir + "/cache ";
  const std::string fid =
      " fidelity " + dir + "/c.json --rungs 'spp=1' --top 'spp=4' -q --no-plots";
  auto f0 = run_cmd(env + fovsim_bin() + fid + " -o " + dir + "/f0");
  ASSERT_EQ(f0.code, 0) << f0.output;
  EXPECT_NE(cache_record(dir + "/f0/rungs/1-spp_4").find("\"frames_computed\": 3"),
            std::string::npos)
      << cache_record(dir + "/f0/rungs/1-spp_4");
  auto f1 = run_cmd(env + fovsim_bin() + fid + " -o " + dir + "/f1 methods[1].sigma=2.4");
  ASSERT_EQ(f1.code, 0) << f1.output;
  for (const char* r : {"/f1/rungs/0-spp_1", "/f1/rungs/1-spp_4"})
    EXPECT_NE(cache_record(dir + r).find("\"frames_from_cache\": 3"), std::string::npos)
        << r << ": " << cache_record(dir + r);
  // converge: its spp 1 and 4 levels are the ladder's rungs, already in the cache.
  auto c = run_cmd(env + fovsim_bin() + " converge " + dir + "/c.json --spp 1,4 -o " + dir + "/c");
  ASSERT_EQ(c.code, 0) << c.output;
  EXPECT_NE(cache_record(dir + "/c/spp_4").find("\"frames_from_cache\": 3"), std::string::npos)
      << cache_record(dir + "/c/spp_4");
  // --no-cache: another folder stays absent.
  const std::string env2 = "env -u FOVSIM_NO_CACHE FOVSIM_CACHE_DIR=" + dir + "/cache2 ";
  auto n = run_cmd(env2 + fovsim_bin() + fid + " --no-cache -o " + dir + "/n");
  ASSERT_EQ(n.code, 0) << n.output;
  auto nc = run_cmd(env2 + fovsim_bin() + " converge " + dir + "/c.json --spp 1,4 --no-cache -o " +
                    dir + "/nc");
  ASSERT_EQ(nc.code, 0) << nc.output;
  std::string sc = kConfig;
  sc.insert(sc.rfind('}'), R"(, "sweep": {"search": {"space": [{"methods[kfr].sigma": )"
                           R"({"from": 1.6, "to": 2.4, "step": 0.4}}], "maximize": "psnr", )"
                           R"("label": "kfr", "evaluations": 2, "batch": 2, "seed": 1}})");
  write_text(dir + "/s.json", sc);
  auto s =
      run_cmd(env2 + fovsim_bin() + " search " + dir + "/s.json -q --no-cache -o " + dir + "/s");
  ASSERT_EQ(s.code, 0) << s.output;
  EXPECT_FALSE(fs::exists(dir + "/cache2"));
  auto s2 = run_cmd(env + fovsim_bin() + " search " + dir + "/s.json -q -o " + dir + "/s2");
  ASSERT_EQ(s2.code, 0) << s2.output;
  int evals = 0;
  for (auto& e : fs::directory_iterator(dir + "/s2/search/evals")) {
    ++evals;
    EXPECT_NE(cache_record(e.path().string()).find("\"frames_from_cache\": 3"), std::string::npos)
        << e.path() << ": " << cache_record(e.path().string());
  }
  EXPECT_EQ(evals, 2);
  fs::remove_all(dir);
}

TEST(CacheCli, BadCacheKeyIsOneLocatedLine) {
  const std::string dir = temp_dir("cache_bad");
  write_text(dir + "/c.json", kConfig);
  auto r = run_cmd(fovsim_bin() + " run " + dir + "/c.json -q --no-plots -o " + dir +
                   "/o cache.max_gb=-1");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("override 'cache.max_gb=-1': cache.max_gb"), std::string::npos)
      << r.output;
  auto k =
      run_cmd(fovsim_bin() + " run " + dir + "/c.json -q --no-plots -o " + dir + "/o cache.size=1");
  EXPECT_EQ(k.code, 2) << k.output;
  EXPECT_NE(k.output.find("cache.size"), std::string::npos) << k.output;
  fs::remove_all(dir);
}
