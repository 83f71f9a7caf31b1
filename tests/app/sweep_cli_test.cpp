// fovsim sweep as a user runs it: expansion listing, resume after SIGKILL (no missing,
// duplicated or corrupt rows), shards + merge equal to the unsharded run, a changed config
// never mixed with old cells.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <set>
#include <thread>

#include "tests/app/app_util.h"

using namespace fovsim_test;
namespace fs = std::filesystem;

namespace {

std::string sweep_config(const std::string& sigmas) {
  return R"({
  "name": "sweep_cli_test",
  "display": "htc_vive_pro_eye",
  "render": {"scale": 0.05},
  "scene": {"type": "atrium", "complexity": 1},
  "trace": {"file": ")" +
         std::string(FOVSIM_SOURCE_DIR) + R"(/tests/golden/golden_trace.csv"},
  "frames": {"count": 3},
  "methods": [{"method": "kfr"}, {"method": "rmfr"}],
  "outputs": {"print_summary": false},
  "sweep": {"axes": [{"grid": {"methods[kfr].sigma": )" +
         sigmas + R"(}},
                     {"zip": {"methods[rmfr].fx": [0.2, 0.4], "methods[rmfr].fy": [0.3, 0.5]}}],
            "objectives": [{"minimize": "shaded_fraction"}, {"maximize": "fpsnr"}]}
})";
}

// summary.csv without wall-clock columns (ref_ms, sim_ms), which differ between runs.
std::vector<std::string> deterministic_rows(const std::string& path) {
  Csv c = read_csv(path);
  std::vector<std::string> out;
  std::string h;
  for (auto& x : c.header)
    if (x != "ref_ms" && x != "sim_ms") h += x + ",";
  out.push_back(h);
  for (auto& r : c.rows) {
    std::string s;
    for (size_t i = 0; i < r.size() && i < c.header.size(); ++i)
      if (c.header[i] != "ref_ms" && c.header[i] != "sim_ms") s += r[i] + ",";
    out.push_back(s);
  }
  return out;
}

int count_complete(const std::string& out) {
  int n = 0;
  if (!fs::exists(out + "/runs")) return 0;
  for (auto& e : fs::directory_iterator(out + "/runs")) n += fs::exists(e.path() / "cell.json");
  return n;
}

}  // namespace

TEST(SweepCli, ExpandListsCellsInOrder) {
  std::string dir = temp_dir("sweep_expand");
  write_text(dir + "/s.json", sweep_config("[1.4, 2.0, 2.6]"));
  auto r = run_cmd(fovsim_bin() + " sweep expand " + dir + "/s.json");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("0 0000-"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("5 0005-"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("methods[kfr].sigma=2.6 methods[rmfr].fx=0.4 methods[rmfr].fy=0.5"),
            std::string::npos);
  EXPECT_NE(r.output.find("6 cells"), std::string::npos);
  auto again = run_cmd(fovsim_bin() + " sweep expand " + dir + "/s.json");
  EXPECT_EQ(again.output, r.output);
  // A typo in an axis fails with its JSON path.
  std::string bad = sweep_config("[1.4]");
  bad.replace(bad.find("methods[kfr].sigma"), 18, "methods[kfr].sigam");
  write_text(dir + "/bad.json", bad);
  auto b = run_cmd(fovsim_bin() + " sweep " + dir + "/bad.json");
  EXPECT_EQ(b.code, 2);
  EXPECT_NE(
      b.output.find(
          "sweep.axes[0].grid.methods[kfr].sigam: unknown parameter \"sigam\" for method \"kfr\""),
      std::string::npos)
      << b.output;
}

TEST(SweepCli, ResumeAfterSigkillAndShardsMergeEqual) {
  std::string dir = temp_dir("sweep_resume");
  write_text(dir + "/s.json", sweep_config("[1.4, 2.0, 2.6]"));
  const int cells = 6;

  // Reference: one uninterrupted run.
  auto full =
      run_cmd(fovsim_bin() + " sweep " + dir + "/s.json --out " + dir + "/full --no-plots -q");
  ASSERT_EQ(full.code, 0) << full.output;
  auto want = deterministic_rows(dir + "/full/summary.csv");
  ASSERT_EQ(want.size(), size_t(1 + cells * 2));

  // Killed mid-sweep: one cell per reference pass so cells complete one by one.
  std::string out = dir + "/killed";
  std::string cmd = "cd '" FOVSIM_SOURCE_DIR "' && exec " + fovsim_bin() + " sweep " + dir +
                    "/s.json --out " + out + " --batch 1 -j 1 --no-plots -q";
  pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", cmd.c_str(), (char*)nullptr);
    _exit(127);
  }
  auto t0 = std::chrono::steady_clock::now();
  while (count_complete(out) < 2 &&
         std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  kill(pid, SIGKILL);
  int st = 0;
  waitpid(pid, &st, 0);
  int done_at_kill = count_complete(out);
  ASSERT_GE(done_at_kill, 2);
  if (done_at_kill == cells) GTEST_SKIP() << "the sweep finished before it could be killed";
  EXPECT_FALSE(fs::exists(out + "/summary.csv"));  // an incomplete sweep has no summary

  auto resumed = run_cmd(fovsim_bin() + " sweep " + dir + "/s.json --out " + out + " --no-plots");
  ASSERT_EQ(resumed.code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find(std::to_string(done_at_kill) + " already complete (skipped)"),
            std::string::npos)
      << resumed.output;
  auto got = deterministic_rows(out + "/summary.csv");
  EXPECT_EQ(got, want);  // no missing, duplicated or corrupt rows
  std::set<std::string> ids;
  for (size_t i = 1; i < got.size(); ++i)
    EXPECT_TRUE(ids.insert(got[i].substr(0, got[i].find(','))).second);

  // Shards in separate folders, merged: equal to the unsharded run.
  for (int s = 0; s < 2; ++s) {
    auto r = run_cmd(fovsim_bin() + " sweep " + dir + "/s.json --out " + dir + "/shard" +
                     std::to_string(s) + " --shard " + std::to_string(s) + "/2 --no-plots -q");
    ASSERT_EQ(r.code, 0) << r.output;
  }
  EXPECT_FALSE(fs::exists(dir + "/shard0/summary.csv"));
  auto partial = run_cmd(fovsim_bin() + " merge " + dir + "/shard0 --no-plots");
  EXPECT_EQ(partial.code, 2);
  EXPECT_NE(partial.output.find("3 of 6 cells are missing"), std::string::npos) << partial.output;
  auto m = run_cmd(fovsim_bin() + " merge " + dir + "/shard0 --from " + dir + "/shard1 --no-plots");
  ASSERT_EQ(m.code, 0) << m.output;
  EXPECT_EQ(deterministic_rows(dir + "/shard0/summary.csv"), want);
  EXPECT_TRUE(fs::exists(dir + "/shard0/pareto.csv"));
  // Cells of two builds never make one summary: merge refuses, naming the builds and cells;
  // a resumed sweep computes the other build's cell again and says so.
  ASSERT_FALSE(stamp_other_build(dir + "/shard0/runs", "cell.json").empty());
  auto mixed = run_cmd(fovsim_bin() + " merge " + dir + "/shard0 --no-plots");
  EXPECT_EQ(mixed.code, 2) << mixed.output;
  EXPECT_NE(mixed.output.find("computed by 2 different builds of fovsim (git_commit "),
            std::string::npos)
      << mixed.output;
  EXPECT_NE(mixed.output.find("older-"), std::string::npos) << mixed.output;
  auto redo =
      run_cmd(fovsim_bin() + " sweep " + dir + "/s.json --out " + dir + "/shard0 --no-plots");
  ASSERT_EQ(redo.code, 0) << redo.output;
  EXPECT_NE(redo.output.find("5 already complete (skipped), 1 run"), std::string::npos)
      << redo.output;
  EXPECT_NE(redo.output.find("note: 1 complete cell in " + dir +
                             "/shard0/runs came from another build of fovsim"),
            std::string::npos)
      << redo.output;
  EXPECT_EQ(deterministic_rows(dir + "/shard0/summary.csv"), want);

  // Slurm's array variables select the shard when --shard is absent.
  auto sl = run_cmd("SLURM_ARRAY_TASK_ID=1 SLURM_ARRAY_TASK_COUNT=3 " + fovsim_bin() + " sweep " +
                    dir + "/s.json --out " + dir + "/slurm --no-plots");
  EXPECT_NE(sl.output.find("shard 1/3 holds 2"), std::string::npos) << sl.output;

  // A changed config: the changed cells get new hashes and are recomputed, the others reused.
  write_text(dir + "/s.json", sweep_config("[1.4, 2.2, 2.6]"));
  auto ch = run_cmd(fovsim_bin() + " sweep " + dir + "/s.json --out " + dir + "/full --no-plots");
  ASSERT_EQ(ch.code, 0) << ch.output;
  EXPECT_NE(ch.output.find("4 already complete (skipped), 2 run"), std::string::npos) << ch.output;
  EXPECT_NE(ch.output.find("2 folders in"), std::string::npos) << ch.output;  // stale, ignored
  Csv c = read_csv(dir + "/full/summary.csv");
  EXPECT_EQ(c.rows.size(), size_t(cells * 2));
  int sc = c.col("sigma");
  ASSERT_GE(sc, 0);
  for (auto& r : c.rows)
    if (r[size_t(c.col("label"))] == "kfr") {
      EXPECT_NE(r[size_t(sc)], "2");
    }
}
