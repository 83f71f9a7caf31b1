// A paired difference smaller than the known bias of the run's fidelity is named in paired.csv
// (fidelity_bias, below_fidelity_bias), counted in the manifest and on the console
// (docs/intervals.md, docs/fidelity.md).
#include <gtest/gtest.h>

#include "tests/app/app_util.h"

using namespace fovsim_test;

TEST(FidelityBiasCli, PairedDifferencesBelowTheKnownBiasAreNamed) {
  const std::string dir = temp_dir("fidelity_bias");
  // render.scale 0.125 is a rung the fidelity ladder measured; kfr at sigma 1.8 and 1.9 differ
  // on every frame (intervals exclude 0) by far less than that rung's bias.
  write_text(dir + "/fb.json",
             R"({"name": "fb", "display": "htc_vive_pro_eye", "render": {"scale": 0.125, "spp": 1},
  "scene": {"type": "atrium", "complexity": 1},
  "trace": {"file": ")" FOVSIM_SOURCE_DIR R"(/traces/sample_walk.csv"}, "frames": {"count": 20},
  "methods": [{"method": "kfr", "sigma": 1.8}, {"method": "kfr", "sigma": 1.9, "label": "kfr19"}],
  "gpus": ["gtx1080"], "metrics": {"fvvdp": false, "flip": false}})");
  auto r = run_cmd(fovsim_bin() + " run " + dir + "/fb.json --no-plots --out " + dir + "/out");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("exclude 0 but are smaller than that bias"), std::string::npos)
      << r.output;
  const Csv p = read_csv(dir + "/out/paired.csv");
  const int km = p.col("metric"), kb = p.col("fidelity_bias"), kw = p.col("below_fidelity_bias"),
            kd = p.col("differs");
  ASSERT_GE(kb, 0);
  ASSERT_GE(kw, 0);
  int named = 0;
  for (auto& row : p.rows) {
    const std::string& m = row[size_t(km)];
    if (m == "psnr") EXPECT_EQ(row[size_t(kb)], "4.65");  // the ladder's PSNR bias at 0.125
    if (m == "ssim") EXPECT_EQ(row[size_t(kw)], "nan");   // no known bias for SSIM
    if (row[size_t(kw)] == "1" && row[size_t(kd)] == "1") ++named;
  }
  EXPECT_GE(named, 3);
  EXPECT_NE(read_text(dir + "/out/manifest.json")
                .find("\"paired_real_below_bias\": " + std::to_string(named)),
            std::string::npos);
}
