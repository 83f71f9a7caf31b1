// The memory budget (docs/architecture.md "Memory"): a sweep whose budget fits one cell at a
// time runs its cells in several passes over the frames and gives the numbers of one pass; the
// manifest records the passes and the peak resident memory; at render.spp 1 the cells of a group
// share one reference side, whose foveation-loss reference is the reference itself (aliased, not
// a second copy), and the estimate counts it once; the cells' per-frame workspaces are counted
// once per cell running at once.
#include <gtest/gtest.h>
#include <tbb/info.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "sim/core/files.h"
#include "sim/experiment/sweep_runner.h"
#include "tests/common/csv_without_times.h"

using namespace fovsim;
namespace fs = std::filesystem;

namespace {

std::string tmp(const std::string& name) {
  return (fs::temp_directory_path() /
          ("fovsim_membudget_" + name + "_" + std::to_string(::getpid())))
      .string();
}

// Three KFR cells over one reference group: tiny frames, FovVideoVDP against both references;
// with KFR's TAA (its default) or without.
LoadedConfig config(int spp, bool taa = true) {
  LoadedConfig c;
  c.file = "membudget.json";
  c.doc = Json{
      {"name", "membudget"},
      {"display", "htc_vive_pro_eye"},
      {"render", {{"scale", 0.05}, {"spp", spp}}},
      {"scene", {{"type", "atrium"}, {"complexity", 1}}},
      {"trace", {{"synthetic", {{"scenario", "walk-through"}, {"seed", 3}, {"duration", 0.1}}}}},
      {"frames", {{"count", 3}}},
      {"metrics", {{"flip", false}}},
      {"methods", Json::array({Json{{"method", "kfr"}, {"taa", taa}}})},
      {"outputs", {{"print_summary", false}, {"image_frames", Json::array({1})}}},
      {"sweep",
       {{"grid", Json::array({Json{{"methods[kfr].sigma", Json::array({1.4, 2.0, 2.6})}}})}}}};
  return c;
}

SweepReport sweep(const LoadedConfig& c, const std::string& out, double budget_gb) {
  SweepOptions o;
  o.out_dir = out;
  o.models_dir = std::string(FOVSIM_SOURCE_DIR) + "/models";
  o.memory_budget_gb = budget_gb;
  return run_sweep(expand_sweep(c), c, o);
}

std::vector<std::string> cell_dirs(const std::string& out) {
  std::vector<std::string> v;
  for (auto& e : fs::directory_iterator(out + "/runs"))
    if (e.is_directory()) v.push_back(e.path().filename().string());
  std::sort(v.begin(), v.end());
  return v;
}

}  // namespace

TEST(MemoryBudget, SeveralPassesGiveTheNumbersOfOne) {
  const std::string dir = tmp("passes");
  const LoadedConfig c = config(1);
  const SweepReport one = sweep(c, dir + "/one", 1e6);
  const SweepReport three = sweep(c, dir + "/three", 1e-6);  // fits no cell: one per pass
  EXPECT_EQ(one.reference_passes, 1);
  EXPECT_EQ(three.reference_passes, 3);
  EXPECT_GT(three.peak_rss_bytes, 0u);
  const auto cells = cell_dirs(dir + "/one");
  ASSERT_EQ(cells.size(), 3u);
  ASSERT_EQ(cell_dirs(dir + "/three"), cells);
  for (size_t i = 0; i < cells.size(); ++i) {
    const std::string a = dir + "/one/runs/" + cells[i], b = dir + "/three/runs/" + cells[i];
    for (const char* f : {"frames.csv", "summary.csv", "paired.csv"})
      EXPECT_EQ(test::csv_without_times(read_file(a + "/" + f)),
                test::csv_without_times(read_file(b + "/" + f)))
          << cells[i] << "/" << f;
    // The saved frame's heat maps (FovVideoVDP against both references) are the same files.
    EXPECT_EQ(read_file(a + "/images/frame_1/kfr_fvvdp.png"),
              read_file(b + "/images/frame_1/kfr_fvvdp.png"));
    EXPECT_EQ(read_file(a + "/images/frame_1/kfr_fvvdp_fl.png"),
              read_file(b + "/images/frame_1/kfr_fvvdp_fl.png"));
    const Json ma = Params::parse_json_file(a + "/manifest.json");
    const Json mb = Params::parse_json_file(b + "/manifest.json");
    EXPECT_EQ(ma["memory"]["passes"], 1);
    EXPECT_EQ(ma["memory"]["pass"], 1);
    EXPECT_EQ(ma["memory"]["cells_in_pass"], 3);
    EXPECT_EQ(mb["memory"]["passes"], 3);
    EXPECT_EQ(mb["memory"]["pass"], int(i) + 1);
    EXPECT_EQ(mb["memory"]["cells_in_pass"], 1);
    EXPECT_EQ(mb["memory"]["budget_from"], "--memory-budget");
    EXPECT_GT(mb["memory"]["peak_rss_bytes"].get<double>(), 0);
    EXPECT_GT(mb["memory"]["estimate_bytes"]["cell"].get<double>(), 0);
    // Workspaces are lent per frame to the cells running at once: one for a pass of one cell,
    // as many as threads (at most the cells) for the pass of three.
    const double ws1 = mb["memory"]["estimate_bytes"]["workspaces"].get<double>();
    EXPECT_GT(ws1, 0);
    EXPECT_DOUBLE_EQ(ma["memory"]["estimate_bytes"]["workspaces"].get<double>(),
                     ws1 * double(std::min(3, int(tbb::info::default_concurrency()))));
  }
  // The config's run.memory_gb when no --memory-budget is given.
  LoadedConfig k = c;
  k.doc["run"] = Json{{"memory_gb", 1e-6}};
  const SweepReport key = sweep(k, dir + "/key", 0);
  EXPECT_EQ(key.reference_passes, 3);
  // (The key changes the cells' hashes, so their folders: compared in index order.)
  const auto key_cells = cell_dirs(dir + "/key");
  ASSERT_EQ(key_cells.size(), cells.size());
  for (size_t i = 0; i < cells.size(); ++i) {
    const std::string a = dir + "/one/runs/" + cells[i], b = dir + "/key/runs/" + key_cells[i];
    EXPECT_EQ(Params::parse_json_file(b + "/manifest.json")["memory"]["budget_from"],
              "run.memory_gb");
    EXPECT_EQ(test::csv_without_times(read_file(a + "/frames.csv")),
              test::csv_without_times(read_file(b + "/frames.csv")));
  }
  fs::remove_all(dir);
}

TEST(MemoryBudget, AtOneSampleTheReferenceIsNotDuplicated) {
  const std::string dir = tmp("alias");
  sweep(config(1, false), dir + "/spp1", 1e6);
  sweep(config(4, false), dir + "/spp4", 1e6);
  // With TAA `full` + TAA is the foveation-loss reference, not the reference itself.
  sweep(config(1, true), dir + "/spp1_taa", 1e6);
  for (const char* spp : {"spp1", "spp4", "spp1_taa"}) {
    const bool one = std::string(spp) == "spp1";
    for (auto& cell : cell_dirs(dir + "/" + spp)) {
      const Json m = Params::parse_json_file(dir + "/" + spp + "/runs/" + cell + "/manifest.json");
      const Json& mem = m["memory"];
      // Three cells with one `metrics` block: one reference side for all of them.
      EXPECT_EQ(mem["reference_sides"], 1) << spp;
      EXPECT_EQ(mem["foveation_loss_reference"], one ? "the reference" : "full at 1 spp") << spp;
      const Json& est = mem["estimate_bytes"];
      // The side holds one reference stream at 1 spp, two otherwise (and full's images).
      const double side = est["reference_side"].get<double>();
      const double stream = est["sequence_reference"].get<double>();
      EXPECT_GT(stream, 0);
      if (one)
        EXPECT_LT(side, 2 * stream) << spp;
      else
        EXPECT_GT(side, 2 * stream) << spp;
    }
  }
  fs::remove_all(dir);
}
