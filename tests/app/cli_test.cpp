// Bad input gets one clear line naming what and where, exit code 2, and no results that
// look complete.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "tests/app/app_util.h"

using namespace fovsim_test;

namespace {

// A valid base config; each test breaks one thing.
std::string base_config(const std::string& dir) {
  return R"({
  "name": "cli_test",
  "display": "htc_vive_pro_eye",
  "render": {"scale": 0.05, "spp": 1},
  "scene": {"type": "atrium", "complexity": 1},
  "trace": {"file": ")" +
         std::string(FOVSIM_SOURCE_DIR) + R"(/tests/golden/golden_trace.csv"},
  "frames": {"count": 2},
  "methods": [{"method": "full"}],
  "outputs": {"print_summary": false}
})";
}

struct Case {
  std::string name, config, expect;
  std::vector<std::string> overrides = {};
};

CmdResult run_config(const std::string& dir, const std::string& cfg,
                     const std::vector<std::string>& ov = {}) {
  write_text(dir + "/c.json", cfg);
  std::string cmd = fovsim_bin() + " run " + dir + "/c.json --out " + dir + "/out";
  for (auto& o : ov) cmd += " '" + o + "'";
  return run_cmd(cmd);
}

int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

}  // namespace

TEST(Cli, HelpExplainsOptions) {
  auto r = run_cmd(fovsim_bin() + " --help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.output.find("run"), std::string::npos);
  auto rr = run_cmd(fovsim_bin() + " run --help");
  EXPECT_EQ(rr.code, 0);
  EXPECT_NE(rr.output.find("--out"), std::string::npos);
  EXPECT_NE(rr.output.find("key.path=value"), std::string::npos);
  EXPECT_NE(rr.output.find("--plots"), std::string::npos);  // default on; --no-plots skips
}

TEST(Cli, BadInputIsOneLineExit2) {
  std::string dir = temp_dir("cli");
  std::string good = base_config(dir);
  auto replace = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    auto p = s.find(from);
    EXPECT_NE(p, std::string::npos) << from;
    return s.replace(p, from.size(), to);
  };
  std::vector<Case> cases = {
      {"malformed", replace("\"frames\": {\"count\": 2},", "\"frames\": {\"count\": 2,,"),
       "c.json:7:25: malformed JSON"},
      {"unknown key",
       replace("\"render\": {\"scale\": 0.05, \"spp\": 1}",
               "\"render\": {\"scale\": 0.05, \"scael\": 1}"),
       "render.scael: unknown key"},
      {"wrong type", replace("{\"count\": 2}", "{\"count\": \"two\"}"),
       "frames.count: expected an integer"},
      {"out of range", replace("\"scale\": 0.05", "\"scale\": -1"),
       "render.scale: value -1 is out of range"},
      {"unknown method", replace("\"method\": \"full\"", "\"method\": \"fool\""),
       "unknown method \"fool\""},
      {"missing scene file",
       replace("{\"type\": \"atrium\", \"complexity\": 1}",
               "{\"type\": \"file\", \"path\": \"/nonexistent/x.gltf\"}"),
       "/nonexistent/x.gltf"},
      {"unreadable trace",
       replace("/tests/golden/golden_trace.csv", "/tests/golden/no_such_trace.csv"),
       "no_such_trace.csv"},
      {"override type", good, "methods[0].label"},
  };
  cases.back().overrides = {"methods[0].label=3"};
  for (auto& c : cases) {
    SCOPED_TRACE(c.name);
    auto r = run_config(dir, c.config, c.overrides);
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_EQ(count_lines(r.output), 1) << r.output;
    EXPECT_EQ(r.output.rfind("fovsim: error: ", 0), 0u) << r.output;
    EXPECT_NE(r.output.find(c.expect), std::string::npos) << r.output;
    // Nothing that looks like a complete result.
    EXPECT_FALSE(std::filesystem::exists(dir + "/out/frames.csv")) << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir + "/out/summary.csv"));
  }
}

TEST(Cli, TooShortTraceIsReported) {
  std::string dir = temp_dir("short");
  auto r = run_config(dir, base_config(dir), {"frames.count=500"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("frames.count: trace is too short"), std::string::npos) << r.output;
  auto ok =
      run_config(dir, base_config(dir), {"frames.count=500", "frames.on_short_trace=\"truncate\""});
  EXPECT_EQ(ok.code, 0) << ok.output;
}

TEST(Cli, RunWritesCompleteOutputs) {
  std::string dir = temp_dir("outputs");
  auto r = run_config(dir, base_config(dir), {"outputs.image_frames=[0]"});
  ASSERT_EQ(r.code, 0) << r.output;
  for (const char* f :
       {"manifest.json", "frames.csv", "summary.csv", "summary.json",
        "images/frame_0/reference.png", "images/frame_0/full.png", "images/frame_0/full_error.png"})
    EXPECT_TRUE(std::filesystem::exists(dir + "/out/" + f)) << f;
  std::string man = read_text(dir + "/out/manifest.json");
  EXPECT_NE(man.find("\"status\": \"complete\""), std::string::npos);
  EXPECT_NE(man.find("\"git_commit\""), std::string::npos);
  EXPECT_NE(man.find("\"resolved_config\""), std::string::npos);
  Csv c = read_csv(dir + "/out/frames.csv");
  for (const char* col : {"config_id", "method", "frame", "t", "gaze_x", "gaze_y", "shaded_samples",
                          "shaded_fraction", "prims_submitted", "prims_culled", "est_ms_total",
                          "psnr", "ssim", "fpsnr", "rmse_fovea", "rmse_periphery", "sim_ms"})
    EXPECT_GE(c.col(col), 0) << col;
  ASSERT_EQ(c.rows.size(), 2u);
  // The full method is the reference: shaded fraction 1, SSIM 1.
  EXPECT_DOUBLE_EQ(std::stod(c.rows[0][size_t(c.col("shaded_fraction"))]), 1.0);
  EXPECT_NEAR(std::stod(c.rows[0][size_t(c.col("ssim"))]), 1.0, 1e-12);
}

TEST(Cli, SameNumbersAtAnyThreadCount) {
  std::string dir = temp_dir("threads");
  write_text(dir + "/c.json", base_config(dir));
  auto a = run_cmd(fovsim_bin() + " run " + dir + "/c.json -j 1 --out " + dir + "/a");
  auto b = run_cmd(fovsim_bin() + " run " + dir + "/c.json -j 2 --out " + dir + "/b");
  ASSERT_EQ(a.code, 0) << a.output;
  ASSERT_EQ(b.code, 0) << b.output;
  Csv ca = read_csv(dir + "/a/frames.csv"), cb = read_csv(dir + "/b/frames.csv");
  ASSERT_EQ(ca.header, cb.header);
  ASSERT_EQ(ca.rows.size(), cb.rows.size());
  for (size_t r = 0; r < ca.rows.size(); ++r)
    for (size_t k = 0; k < ca.header.size(); ++k) {
      if (ca.header[k] == "sim_ms" || ca.header[k] == "ref_ms") continue;  // wall time
      EXPECT_EQ(ca.rows[r][k], cb.rows[r][k]) << ca.header[k];
    }
}

// The images of a frame are queued while the methods run and written together, in parallel
// (cell_images.h ImageJobs): every file is there, and byte for byte the same at any thread count.
TEST(Cli, ImagesAreTheSameFilesAtAnyThreadCount) {
  namespace fs = std::filesystem;
  std::string dir = temp_dir("threads_images");
  write_text(dir + "/c.json", base_config(dir));
  std::vector<std::string> runs;
  for (const char* j : {"1", "2"}) {
    const std::string out = dir + "/o" + j;
    auto r = run_cmd(
        fovsim_bin() + " run " + dir + "/c.json -j " + j + " --no-plots --out " + out +
        " 'outputs.image_frames=[0, 1]' outputs.debug_images=true " + "outputs.exr=true " +
        "'methods=[{\"method\": \"full\"}, {\"method\": \"kfr\"}, " + "{\"method\": \"fvrs\"}]'");
    ASSERT_EQ(r.code, 0) << r.output;
    runs.push_back(out);
  }
  std::vector<std::string> names;
  for (auto& e : fs::recursive_directory_iterator(runs[0] + "/images"))
    if (e.is_regular_file()) names.push_back(fs::relative(e.path(), runs[0]).string());
  std::sort(names.begin(), names.end());
  for (const char* f :
       {"images/frame_0/reference.png", "images/frame_0/reference.exr", "images/frame_1/kfr.png",
        "images/frame_1/kfr_error.png", "images/frame_1/kfr_flip.png", "images/frame_1/fvrs.exr"})
    EXPECT_TRUE(std::binary_search(names.begin(), names.end(), std::string(f))) << f;
  EXPECT_GT(names.size(), 20u);  // plus the methods' debug images
  for (auto& n : names) {
    ASSERT_TRUE(fs::exists(runs[1] + "/" + n)) << n;
    EXPECT_TRUE(read_text(runs[0] + "/" + n) == read_text(runs[1] + "/" + n)) << n;
  }
  size_t n1 = 0;
  for (auto& e : fs::recursive_directory_iterator(runs[1] + "/images")) n1 += e.is_regular_file();
  EXPECT_EQ(n1, names.size());
}

// `summary.csv` carries `<col>_ci95` (nan below 20 frames or for an inf mean) and
// paired.csv compares the configs on the same frames.
TEST(Cli, RunWritesIntervalsAndPairedDifferences) {
  std::string dir = temp_dir("intervals");
  std::string cfg = R"({
  "name": "ci_test",
  "display": "htc_vive_pro_eye",
  "render": {"scale": 0.04, "spp": 1},
  "scene": {"type": "atrium", "complexity": 1},
  "trace": {"synthetic": {"scenario": "walk-through", "seed": 2, "duration": 0.4}},
  "frames": {"count": 24},
  "methods": [{"method": "full"}, {"method": "rmfr"}],
  "outputs": {"print_summary": false}
})";
  auto r = run_config(dir, cfg);
  ASSERT_EQ(r.code, 0) << r.output;
  Csv s = read_csv(dir + "/out/summary.csv");
  ASSERT_EQ(s.rows.size(), 2u);
  for (const char* col : {"est_ms_total_ci95", "shaded_fraction_ci95", "psnr_ci95", "fpsnr_ci95"})
    ASSERT_GE(s.col(col), 0) << col;
  for (const char* col : {"ref_ms_ci95", "sim_ms_ci95", "frame_ci95"})
    EXPECT_LT(s.col(col), 0) << col;
  auto num = [&](size_t row, const char* col) {
    return std::stod(s.rows[row][size_t(s.col(col))]);
  };
  EXPECT_TRUE(std::isnan(num(0, "psnr_ci95")));  // full: psnr is inf on every frame
  EXPECT_DOUBLE_EQ(num(0, "shaded_fraction_ci95"), 0.0);
  EXPECT_TRUE(std::isfinite(num(1, "psnr_ci95")));
  EXPECT_GE(num(1, "est_ms_total_ci95"), 0.0);
  Csv p = read_csv(dir + "/out/paired.csv");
  ASSERT_GE(p.col("diff_ci95"), 0);
  // full - rmfr: est_ms_total, shaded_fraction, the headline metrics psnr, fpsnr, ssim, flip,
  // fvvdp_jod, the foveation-loss columns fpsnr_fl, fvvdp_jod_fl and the region errors
  // rmse_fovea(_fl), rmse_periphery(_fl) (the metric registry's paired list)
  ASSERT_EQ(p.rows.size(), 13u);
  for (auto& row : p.rows) {
    EXPECT_EQ(row[size_t(p.col("config_a"))], "full");
    if (row[size_t(p.col("metric"))] == "psnr") {  // inf for full on every frame: nothing paired
      EXPECT_EQ(row[size_t(p.col("frames"))], "0");
      EXPECT_EQ(row[size_t(p.col("differs"))], "nan");
      continue;
    }
    if (row[size_t(p.col("frames"))] == "0") continue;  // fpsnr may be inf for full as well
    // FovVideoVDP's columns leave out its 15 settle frames at 90 Hz (docs/intervals.md).
    const bool fvvdp = row[size_t(p.col("metric"))].rfind("fvvdp", 0) == 0;
    EXPECT_EQ(row[size_t(p.col("frames"))], fvvdp ? "9" : "24") << row[size_t(p.col("metric"))];
    double d = std::stod(row[size_t(p.col("diff"))]);
    double a = std::stod(row[size_t(p.col("mean_a"))]), b = std::stod(row[size_t(p.col("mean_b"))]);
    EXPECT_NEAR(d, a - b, 1e-6 * (1 + std::fabs(a)));
  }
  std::string js = read_text(dir + "/out/summary.json");
  EXPECT_NE(js.find("\"fpsnr_ci95\""), std::string::npos);
}
