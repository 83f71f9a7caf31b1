// `fovsim run --target`: stops early, deterministic for a seed, and every
// recorded row equals the full run's row for that frame.
#include <gtest/gtest.h>

#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "tests/app/app_util.h"

using namespace fovsim_test;

namespace {

std::string config(const std::string& methods) {
  return R"({
  "name": "target_test",
  "display": "htc_vive_pro_eye",
  "render": {"scale": 0.04, "spp": 1},
  "scene": {"type": "atrium", "complexity": 1},
  "trace": {"synthetic": {"scenario": "walk-through", "seed": 2, "duration": 3.4}},
  "frames": {"count": 300},
  "methods": [)" +
         methods + R"(],
  "outputs": {"print_summary": false}
})";
}

// (config_id, frame) -> row without the wall-clock columns.
std::map<std::pair<std::string, std::string>, std::string> keyed_rows(const std::string& path) {
  Csv c = read_csv(path);
  std::map<std::pair<std::string, std::string>, std::string> out;
  for (auto& r : c.rows) {
    std::string s;
    for (size_t k = 0; k < c.header.size(); ++k)
      // FovVideoVDP scores a full run as video and shuffled --target units as still images
      // (docs/metrics.md "FovVideoVDP in a run"): its columns differ by design.
      if (c.header[k] != "sim_ms" && c.header[k] != "ref_ms" && c.header[k].rfind("fvvdp_", 0) != 0)
        s += r[k] + ",";
    out[{r[size_t(c.col("config_id"))], r[size_t(c.col("frame"))]}] = s;
  }
  return out;
}

nlohmann::json target_record(const std::string& dir) {
  return nlohmann::json::parse(read_text(dir + "/manifest.json")).at("target");
}

TEST(TargetCli, StopsEarlyWithTheFullRunsRowsAndIsDeterministic) {
  std::string dir = temp_dir("target");
  // rmfr without its TAA: no history, so --target may evaluate the frames in random units.
  write_text(dir + "/c.json", config(R"({"method": "full"}, {"method": "rmfr", "taa": false})"));
  const std::string run = fovsim_bin() + " run " + dir + "/c.json";
  const std::string tgt = " --target est_ms_total:5% --target ssim:0.5";
  auto full = run_cmd(run + " --out " + dir + "/full");
  auto a = run_cmd(run + tgt + " -j 1 --out " + dir + "/a");
  auto b = run_cmd(run + tgt + " -j 2 --out " + dir + "/b");
  auto other = run_cmd(run + tgt + " seed=7 --out " + dir + "/other");
  for (auto* r : {&full, &a, &b, &other}) ASSERT_EQ(r->code, 0) << r->output;

  nlohmann::json t = target_record(dir + "/a");
  EXPECT_EQ(nlohmann::json::parse(read_text(dir + "/a/manifest.json")).at("fvvdp").at("mode"),
            "image");
  EXPECT_EQ(nlohmann::json::parse(read_text(dir + "/full/manifest.json")).at("fvvdp").at("mode"),
            "video");
  EXPECT_TRUE(t.at("met").get<bool>());
  EXPECT_EQ(t.at("order"), "random_units");
  EXPECT_EQ(t.at("frames_available"), 300);
  // rmfr's and full's frame times are constant and SSIM is bounded by 1: the targets hold as
  // soon as they are checked, after the minimum of 20 units of 10 frames.
  EXPECT_EQ(t.at("frames_used"), 200);
  EXPECT_LE(t.at("warmup_frames").get<int>(), 20);
  EXPECT_TRUE(t.at("achieved").at("rmfr").at("ssim").at("met").get<bool>());
  EXPECT_LE(t.at("achieved").at("rmfr").at("ssim").at("ci95").get<double>(), 0.5);

  auto fr = keyed_rows(dir + "/full/frames.csv"), ar = keyed_rows(dir + "/a/frames.csv");
  ASSERT_EQ(ar.size(), 400u);  // 200 frames x 2 configs
  std::set<std::string> frames;
  for (auto& [k, row] : ar) {
    ASSERT_TRUE(fr.count(k)) << k.second;
    EXPECT_EQ(row, fr[k]) << "frame " << k.second << " of " << k.first
                          << " differs from the full run";
    frames.insert(k.second);
  }
  EXPECT_EQ(frames.size(), 200u);
  // Same seed: the same frames in the same order at any thread count; another seed: others.
  Csv ca = read_csv(dir + "/a/frames.csv"), cb = read_csv(dir + "/b/frames.csv");
  ASSERT_EQ(ca.rows.size(), cb.rows.size());
  for (size_t i = 0; i < ca.rows.size(); ++i)
    EXPECT_EQ(ca.rows[i][size_t(ca.col("frame"))], cb.rows[i][size_t(cb.col("frame"))]);
  EXPECT_EQ(read_text(dir + "/a/summary.csv").substr(0, 200),
            read_text(dir + "/b/summary.csv").substr(0, 200));
  std::set<std::string> other_frames;
  for (auto& [k, row] : keyed_rows(dir + "/other/frames.csv")) other_frames.insert(k.second);
  EXPECT_NE(other_frames, frames);
}

TEST(TargetCli, TemporalMethodKeepsTraceOrder) {
  std::string dir = temp_dir("target_twfr");
  write_text(dir + "/c.json", config(R"({"method": "twfr"})"));
  auto r = run_cmd(fovsim_bin() + " run " + dir + "/c.json --target est_ms_total:50% --out " + dir +
                   "/o");
  ASSERT_EQ(r.code, 0) << r.output;
  nlohmann::json t = target_record(dir + "/o");
  EXPECT_EQ(t.at("order"), "trace");
  EXPECT_EQ(t.at("warmup_frames"), 0);
  Csv c = read_csv(dir + "/o/frames.csv");
  ASSERT_EQ(int(c.rows.size()), t.at("frames_used").get<int>());
  for (size_t i = 0; i < c.rows.size(); ++i)
    EXPECT_EQ(c.rows[i][size_t(c.col("frame"))], std::to_string(i));
}

TEST(TargetCli, BadTargetIsOneLineExit2) {
  std::string dir = temp_dir("target_bad");
  write_text(dir + "/c.json", config(R"({"method": "full"})"));
  for (const char* spec :
       {"fpsnr", "fpsnr:-1dB", "fpsnr:1furlong", "sigma:1", "nosuchcol:1%", "psnr:150%"}) {
    auto r = run_cmd(fovsim_bin() + " run " + dir + "/c.json --target '" + spec + "' --out " + dir +
                     "/o");
    EXPECT_EQ(r.code, 2) << spec << ": " << r.output;
    EXPECT_NE(r.output.find("--target " + std::string(spec)), std::string::npos) << r.output;
  }
}

}  // namespace
