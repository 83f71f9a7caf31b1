// The reference cache from the command line (configs/README.md "cache"): `fovsim run` uses it by
// default (here in a temporary FOVSIM_CACHE_DIR), a second run takes every reference from it
// with the same frames.csv, `--no-cache` and FOVSIM_NO_CACHE leave it alone, a sweep's shards
// reuse each other's frames, and a bad `cache` key is one located line with exit code 2.
#include <gtest/gtest.h>

#include <filesystem>

#include "app_util.h"
#include "sim/core/params.h"  // Json

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

// `fovsim cache info` names the folder, its size and entries per kind and the cap; `prune
// --max-gb` shrinks it (least recently used first); a bad --max-gb is one line naming the flag
// and its range, exit code 2, the cache untouched. A run that adds more than cache.note_mb says
// so on stderr.
TEST(CacheCli, InfoPruneAndGrowthNote) {
  const std::string dir = temp_dir("cache_info");
  write_text(dir + "/c.json", kConfig);
  const std::string env = "env -u FOVSIM_NO_CACHE FOVSIM_CACHE_DIR=" + dir + "/cache ";
  auto a = run_cmd(env + fovsim_bin() + " run " + dir + "/c.json -q --no-plots -o " + dir +
                   "/a cache.note_mb=0");
  ASSERT_EQ(a.code, 0) << a.output;
  EXPECT_NE(a.output.find("note: reference cache " + dir + "/cache: this run wrote "),
            std::string::npos)
      << a.output;
  EXPECT_NE(a.output.find("`fovsim cache info`"), std::string::npos) << a.output;
  // The default cache.note_mb (100 MB): these few KB are not worth a line.
  auto b = run_cmd(env + fovsim_bin() + " run " + dir + "/c.json -q --no-plots -o " + dir +
                   "/b methods[1].sigma=2.4");
  ASSERT_EQ(b.code, 0) << b.output;
  EXPECT_EQ(b.output.find("note: reference cache"), std::string::npos) << b.output;
  EXPECT_NE(read_text(dir + "/b/manifest.json").find("\"max_gb_auto\": true"), std::string::npos);

  auto info = run_cmd(env + fovsim_bin() + " cache info");
  ASSERT_EQ(info.code, 0) << info.output;
  EXPECT_NE(info.output.find("cache folder: " + dir + "/cache\n"), std::string::npos)
      << info.output;
  EXPECT_NE(info.output.find("references: 3, "), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("methods: "), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("cap: "), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("free disk space: "), std::string::npos) << info.output;
  auto js = run_cmd(fovsim_bin() + " cache info --json --dir " + dir + "/cache");
  ASSERT_EQ(js.code, 0) << js.output;
  const fovsim::Json j = fovsim::Json::parse(js.output);
  const uint64_t before = j["bytes"].get<uint64_t>();
  EXPECT_GT(before, 0u);
  EXPECT_GE(j["entries"].get<int>(), 3);
  EXPECT_LE(j["default_max_gb"].get<double>(), 20.0);

  // Bad values: one line naming the flag and the range, exit 2, nothing removed.
  for (const char* bad : {"-1", "abc", "nan"}) {
    auto r = run_cmd(fovsim_bin() + " cache prune --dir " + dir + "/cache --max-gb " + bad);
    EXPECT_EQ(r.code, 2) << bad << ": " << r.output;
    EXPECT_NE(r.output.find("--max-gb"), std::string::npos) << r.output;
  }
  auto r0 = run_cmd(fovsim_bin() + " cache prune --dir " + dir + "/cache --max-gb -1");
  EXPECT_NE(r0.output.find("[0, 1e+06]"), std::string::npos) << r0.output;
  auto same = fovsim::Json::parse(
      run_cmd(fovsim_bin() + " cache info --json --dir " + dir + "/cache").output);
  EXPECT_EQ(same["bytes"].get<uint64_t>(), before);

  // Prune to a size below what it holds: fewer bytes, at most the size asked for.
  const double half_gb = double(before) / 2 / (1024.0 * 1024.0 * 1024.0);
  auto p = run_cmd(fovsim_bin() + " cache prune --dir " + dir + "/cache --max-gb " +
                   std::to_string(half_gb));
  ASSERT_EQ(p.code, 0) << p.output;
  EXPECT_NE(p.output.find("pruned " + dir + "/cache to at most"), std::string::npos) << p.output;
  auto after = fovsim::Json::parse(
      run_cmd(fovsim_bin() + " cache info --json --dir " + dir + "/cache").output);
  EXPECT_LT(after["bytes"].get<uint64_t>(), before);
  EXPECT_LE(double(after["bytes"].get<uint64_t>()), double(before) / 2 + 1);
  auto p0 = run_cmd(fovsim_bin() + " cache prune --dir " + dir + "/cache --max-gb 0");
  ASSERT_EQ(p0.code, 0) << p0.output;
  EXPECT_NE(p0.output.find("it holds 0 B in 0 entries"), std::string::npos) << p0.output;
  // No folder at all: an error naming what to give.
  auto none =
      run_cmd("env -u FOVSIM_CACHE_DIR -u XDG_CACHE_HOME -u HOME " + fovsim_bin() + " cache info");
  EXPECT_EQ(none.code, 2) << none.output;
  EXPECT_NE(none.output.find("give --dir"), std::string::npos) << none.output;
  auto sub = run_cmd(fovsim_bin() + " cache");
  EXPECT_NE(sub.code, 0);
  fs::remove_all(dir);
}
