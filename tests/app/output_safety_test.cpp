// Output safety: `fovsim run` and `fovsim merge` killed by SIGKILL at
// seeded random moments never leave a file that looks complete but is not (every output goes
// through files.h write_atomic: temporary name, check, rename), and never lose a finished
// cell; the command run again afterwards completes with the same results. The kill delays
// are drawn from [0, 1.2 x the uninterrupted wall time], so they land before, during and after
// the writes; what is asserted never depends on where they land.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>
#include <thread>

#include "sim/core/files.h"
#include "tests/app/app_util.h"

using namespace fovsim_test;
namespace fs = std::filesystem;

namespace {

const std::string kTrace = std::string(FOVSIM_SOURCE_DIR) + "/tests/golden/golden_trace.csv";

// Problems of the files under `dir` that carry a final name: a PNG without its signature or
// IEND chunk, a CSV that is empty, unterminated or ragged, JSON that does not parse, HTML
// without its end. Temporaries (and everything inside a temporary folder) are skipped.
std::vector<std::string> incomplete_files(const std::string& dir) {
  std::vector<std::string> bad;
  if (!fs::exists(dir)) return bad;
  for (auto it = fs::recursive_directory_iterator(dir); it != fs::recursive_directory_iterator();
       ++it) {
    std::string name = it->path().filename().string();
    if (fovsim::is_temporary_name(name)) {
      if (it->is_directory()) it.disable_recursion_pending();
      continue;
    }
    if (!it->is_regular_file()) continue;
    std::string p = it->path().string(), ext = it->path().extension().string();
    std::string s = read_text(p);
    if (ext == ".png") {
      if (s.size() < 20 || s.compare(0, 4, "\x89PNG") != 0 ||
          s.compare(s.size() - 8, 4, "IEND") != 0)
        bad.push_back(p + ": truncated PNG");
    } else if (ext == ".csv") {
      if (s.empty() || s.back() != '\n') {
        bad.push_back(p + ": empty or unterminated CSV");
        continue;
      }
      std::istringstream in(s);
      std::string line;
      std::getline(in, line);
      size_t n = split_csv_line(line).size();
      long ln = 1;
      while (std::getline(in, line)) {
        ++ln;
        if (split_csv_line(line).size() != n)
          bad.push_back(p + ":" + std::to_string(ln) + ": ragged CSV row");
      }
    } else if (ext == ".json") {
      if (!nlohmann::json::accept(s)) bad.push_back(p + ": JSON does not parse");
    } else if (ext == ".html") {
      if (s.find("</html>") == std::string::npos) bad.push_back(p + ": HTML without its end");
    }
  }
  return bad;
}

nlohmann::json read_json(const std::string& p) {
  return nlohmann::json::parse(read_text(p), nullptr, false);
}

pid_t spawn(const std::string& cmd) {
  std::string full = "cd '" FOVSIM_SOURCE_DIR "' && exec " + cmd + " >/dev/null 2>&1";
  pid_t pid = fork();
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", full.c_str(), (char*)nullptr);
    _exit(127);
  }
  return pid;
}

double run_timed(const std::string& cmd) {
  auto t0 = std::chrono::steady_clock::now();
  pid_t pid = spawn(cmd);
  int st = 0;
  waitpid(pid, &st, 0);
  EXPECT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0) << cmd;
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Starts `cmd`, kills it with SIGKILL after `delay_s` (if still running), reaps it. Returns
// true when the kill interrupted it (reported, never asserted: it depends on timing).
bool kill_after(const std::string& cmd, double delay_s) {
  pid_t pid = spawn(cmd);
  std::this_thread::sleep_for(std::chrono::duration<double>(delay_s));
  kill(pid, SIGKILL);
  int st = 0;
  waitpid(pid, &st, 0);
  return WIFSIGNALED(st);
}

std::vector<double> seeded_delays(int n, double span_s, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, span_s);
  std::vector<double> d;
  for (int i = 0; i < n; ++i) d.push_back(u(rng));
  return d;
}

// A finished sweep cell: runs/<id>/cell.json says complete.
std::set<std::string> complete_cells(const std::string& out) {
  std::set<std::string> ids;
  if (!fs::exists(out + "/runs")) return ids;
  for (auto& e : fs::directory_iterator(out + "/runs")) {
    if (fovsim::is_temporary_name(e.path().filename().string())) continue;
    auto j = read_json((e.path() / "cell.json").string());
    if (j.is_object() && j.value("status", "") == "complete")
      ids.insert(e.path().filename().string());
  }
  return ids;
}

// summary.csv rows without wall-clock columns.
std::vector<std::string> deterministic_rows(const std::string& path) {
  Csv c = read_csv(path);
  std::vector<std::string> out;
  for (auto& r : c.rows) {
    std::string s;
    for (size_t i = 0; i < r.size() && i < c.header.size(); ++i)
      if (c.header[i].find("_ms") == std::string::npos || c.header[i].rfind("est_ms", 0) == 0)
        s += r[i] + ",";
    out.push_back(s);
  }
  return out;
}

}  // namespace

TEST(OutputSafety, RunKilledAtRandomMomentsLeavesNoFalseCompleteFile) {
  std::string dir = temp_dir("safety_run");
  write_text(dir + "/c.json", R"({"name": "safety", "render": {"scale": 0.05},
  "scene": {"type": "atrium", "complexity": 1}, "trace": {"file": ")" +
                                  kTrace + R"("}, "frames": {"count": 3},
  "methods": [{"method": "full"}, {"method": "kfr"}],
  "outputs": {"print_summary": false, "image_frames": [0, 1, 2]}})");
  const std::string cmd = fovsim_bin() + " run " + dir + "/c.json --no-plots --out " + dir + "/o";
  const double t_full = run_timed(cmd);
  ASSERT_TRUE(incomplete_files(dir + "/o").empty());
  auto want = read_csv(dir + "/o/frames.csv").rows.size();
  ASSERT_EQ(want, 6u);  // 3 frames x 2 methods
  fs::remove_all(dir + "/o");

  // Killed again and again into the same folder (a rerun over a killed run, as users do).
  int interrupted = 0;
  for (double d : seeded_delays(5, 1.2 * t_full, 20)) {
    interrupted += kill_after(cmd, d);
    for (auto& b : incomplete_files(dir + "/o"))
      ADD_FAILURE() << "after a kill at " << d << " s: " << b;
    auto man = read_json(dir + "/o/manifest.json");
    if (man.is_object() && man.value("status", "") == "complete") {
      // A run that says it is complete has every result file.
      for (const char* f : {"frames.csv", "summary.csv", "paired.csv", "summary.json"})
        EXPECT_TRUE(fs::exists(dir + "/o/" + f)) << f << " missing after a kill at " << d << " s";
      EXPECT_EQ(read_csv(dir + "/o/frames.csv").rows.size(), want);
    }
  }
  std::printf("%d of 5 kills interrupted the run (uninterrupted: %.2f s)\n", interrupted, t_full);
  // Run to the end after the kills: complete, every row there.
  run_timed(cmd);
  EXPECT_EQ(read_json(dir + "/o/manifest.json").value("status", ""), "complete");
  EXPECT_EQ(read_csv(dir + "/o/frames.csv").rows.size(), want);
  EXPECT_TRUE(incomplete_files(dir + "/o").empty());
}

TEST(OutputSafety, MergeKilledAtRandomMomentsLosesNoFinishedCell) {
  std::string dir = temp_dir("safety_merge");
  write_text(dir + "/s.json", R"({"name": "safety_sweep", "render": {"scale": 0.05},
  "scene": {"type": "atrium", "complexity": 1}, "trace": {"file": ")" +
                                  kTrace + R"("}, "frames": {"count": 1},
  "methods": [{"method": "kfr"}], "outputs": {"print_summary": false, "image_frames": [0]},
  "sweep": {"axes": [{"grid": {"methods[kfr].sigma": [1.4, 2.2, 2.6]}},
                     {"grid": {"methods[kfr].alpha": [2, 4]}}]}})");
  for (int s = 0; s < 2; ++s)
    run_timed(fovsim_bin() + " sweep " + dir + "/s.json --no-plots -q --shard " +
              std::to_string(s) + "/2 --out " + dir + "/shard" + std::to_string(s));
  const auto own = complete_cells(dir + "/shard0");
  ASSERT_EQ(own.size(), 3u);
  ASSERT_EQ(complete_cells(dir + "/shard1").size(), 3u);

  // Reference: an uninterrupted merge into a copy of shard 0.
  auto merge_into = [&](const std::string& out) {
    return fovsim_bin() + " merge " + out + " --from " + dir + "/shard1 --no-plots";
  };
  fs::copy(dir + "/shard0", dir + "/ref", fs::copy_options::recursive);
  const double t_merge = run_timed(merge_into(dir + "/ref"));
  auto want = deterministic_rows(dir + "/ref/summary.csv");
  ASSERT_EQ(want.size(), 6u);

  int i = 0, interrupted = 0;
  for (double d : seeded_delays(4, 1.2 * t_merge, 21)) {
    std::string out = dir + "/m" + std::to_string(i++);
    fs::copy(dir + "/shard0", out, fs::copy_options::recursive);
    interrupted += kill_after(merge_into(out), d);
    for (auto& b : incomplete_files(out)) ADD_FAILURE() << "after a kill at " << d << " s: " << b;
    // Cells finished before the merge stay finished; copied cells are whole or absent.
    auto now = complete_cells(out);
    for (auto& id : own) EXPECT_TRUE(now.count(id)) << id << " lost after a kill at " << d << " s";
    if (fs::exists(out + "/summary.csv")) {
      EXPECT_EQ(now.size(), 6u);  // a sweep summary only exists over every cell
      EXPECT_EQ(deterministic_rows(out + "/summary.csv"), want);
    }
    // Merging again completes with the same rows.
    run_timed(merge_into(out));
    EXPECT_EQ(deterministic_rows(out + "/summary.csv"), want) << "killed at " << d << " s";
    EXPECT_TRUE(incomplete_files(out).empty());
  }
  std::printf("%d of 4 kills interrupted the merge (uninterrupted: %.2f s)\n", interrupted,
              t_merge);
}
