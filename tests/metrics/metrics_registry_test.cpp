// The metric registry (sim/metrics/registry.h): one declaration per metric.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "sim/metrics/fvvdp.h"
#include "sim/metrics/registry.h"

using namespace fovsim;

TEST(MetricRegistry, FindsNamesFamiliesAndPooledColumns) {
  ASSERT_NE(find_metric("psnr"), nullptr);
  EXPECT_EQ(find_metric("psnr")->unit, "dB");
  ASSERT_NE(find_metric("rmse_ecc_0_5"), nullptr);
  EXPECT_EQ(find_metric("rmse_ecc_0_5")->name, "rmse_ecc_");
  EXPECT_EQ(find_metric("rmse_ecc_"), nullptr);  // a family prefix alone is no column
  ASSERT_NE(find_metric("flip_ecc_5_10"), nullptr);
  EXPECT_EQ(find_metric("flip_ecc_5_10")->better, Better::lower);
  ASSERT_NE(find_metric("fvvdp_q"), nullptr);
  EXPECT_EQ(find_metric("fvvdp_q")->name, "fvvdp_jod");
  EXPECT_EQ(find_metric("est_ms_total"), nullptr);
  EXPECT_EQ(find_metric("shaded_fraction"), nullptr);
}

TEST(MetricRegistry, FoveationLossColumns) {
  ASSERT_NE(find_metric("psnr_fl"), nullptr);
  EXPECT_EQ(find_metric("psnr_fl")->name, "psnr");
  EXPECT_EQ(find_metric("rmse_ecc_0_5_fl")->name, "rmse_ecc_");
  EXPECT_EQ(find_metric("fvvdp_q_fl")->name, "fvvdp_jod");
  EXPECT_TRUE(is_foveation_loss_column("fvvdp_jod_fl"));
  EXPECT_FALSE(is_foveation_loss_column("fvvdp_jod"));
  EXPECT_FALSE(is_foveation_loss_column("est_ms_fl"));
  EXPECT_FALSE(higher_is_better("fvvdp_q_fl"));
  EXPECT_TRUE(higher_is_better("fvvdp_jod_fl"));
  EXPECT_FALSE(higher_is_better("flip_fl"));
  EXPECT_EQ(headline_metric_names(true),
            (std::vector<std::string>{"psnr", "fpsnr", "ssim", "flip", "fvvdp_jod", "fpsnr_fl",
                                      "fvvdp_jod_fl"}));
}

TEST(MetricRegistry, Directions) {
  EXPECT_TRUE(higher_is_better("psnr"));
  EXPECT_TRUE(higher_is_better("fvvdp_jod"));
  EXPECT_FALSE(higher_is_better("fvvdp_q"));  // larger Q, lower JOD
  EXPECT_FALSE(higher_is_better("flip"));
  EXPECT_FALSE(higher_is_better("temporal_error"));
  EXPECT_FALSE(higher_is_better("est_ms_total"));
}

TEST(MetricRegistry, NamesAreUniqueAndDeclarationsComplete) {
  std::set<std::string> names;
  for (auto& d : metric_registry()) {
    EXPECT_TRUE(names.insert(d.name).second) << d.name;
    EXPECT_FALSE(d.unit.empty()) << d.name;
    EXPECT_FALSE(d.label.empty()) << d.name;
    EXPECT_FALSE(d.doc.empty()) << d.name;
    if (d.pooling == Pooling::sequence) {
      EXPECT_FALSE(d.pooled_column.empty()) << d.name;
      EXPECT_NE(d.from_mean, nullptr) << d.name;
    }
  }
  const auto h = headline_metric_names();
  EXPECT_EQ(h, (std::vector<std::string>{"psnr", "fpsnr", "ssim", "flip", "fvvdp_jod"}));
  const auto p = paired_metric_names();
  EXPECT_EQ(std::vector<std::string>(p.end() - 4, p.end()),
            (std::vector<std::string>{"rmse_fovea", "rmse_fovea_fl", "rmse_periphery",
                                      "rmse_periphery_fl"}));
}

TEST(MetricRegistry, JsonCarriesEveryField) {
  Json j = metric_registry_json();
  ASSERT_EQ(j.size(), metric_registry().size());
  for (auto& m : j)
    for (const char* k : {"name", "family", "unit", "label", "better", "pooling", "pooled_column",
                          "headline", "paired", "convergence_tol", "precision", "cite", "doc"})
      EXPECT_TRUE(m.contains(k)) << k;
  EXPECT_EQ(j[4]["name"], "fvvdp_jod");
  EXPECT_EQ(j[4]["pooling"], "sequence");
  EXPECT_EQ(j[4]["pooled_column"], "fvvdp_q");
}

TEST(MetricRegistry, JodRegression) {
  // Mantiuk et al. 2021 §11 (FovVideoVDP v1.2): Q = 0 is exactly 10; case C8 of the spec's
  // sanity table: Q = 3795.3 -> 7.8812.
  EXPECT_EQ(fvvdp_jod_from_q(0.0), 10.0);
  EXPECT_NEAR(fvvdp_jod_from_q(3795.3), 7.8812, 1e-4);
}
