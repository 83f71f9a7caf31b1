// FPSNR, local ppd, region and band RMSEs.
#include <gtest/gtest.h>

#include <cmath>

#include "metrics_test_util.h"
#include "sim/core/error.h"
#include "sim/metrics/metrics.h"

using namespace fovsim;

static const double kFc0 = std::log(64.0) / 0.106;  // f_c(0) = e2 ln(1/CT0) / (alpha e2)

TEST(MetricsFpsnr, WeightIsCutoffFrequencyClippedAtNyquist) {
  EXPECT_NEAR(fpsnr_weight(0.0, 1000.0), kFc0, 1e-12);
  EXPECT_NEAR(fpsnr_weight(2.3, 1000.0), kFc0 / 2, 1e-12);  // e = e2 halves the cutoff
  EXPECT_NEAR(fpsnr_weight(20.0, 1000.0), 2.3 * std::log(64.0) / (0.106 * 22.3), 1e-12);
  EXPECT_DOUBLE_EQ(fpsnr_weight(0.0, 20.0), 10.0);  // clipped at ppd / 2
  EXPECT_DOUBLE_EQ(fpsnr_weight(60.0, 20.0), 2.3 * std::log(64.0) / (0.106 * 62.3));
}

TEST(MetricsFpsnr, LocalPpdMatchesCameraPpdAt) {
  Display d = Display::load("htc_vive_pro_eye", std::string(FOVSIM_SOURCE_DIR) + "/models");
  Camera cam = Camera::from_pose(d, glm::dvec3(0), glm::dquat(1, 0, 0, 0));
  for (double fx : {0.5, 0.1, 0.9, 0.0})
    for (double fy : {0.5, 0.02, 0.7}) {
      double px = fx * cam.width + 0.5, py = fy * cam.height + 0.5;
      EXPECT_NEAR(local_ppd(cam, px, py) / cam.ppd_at(px, py), 1.0, 1e-5) << fx << "," << fy;
    }
  EXPECT_GT(local_ppd(cam, 0.5, 0.5),
            local_ppd(cam, cam.width / 2.0, cam.height / 2.0));  // rectilinear
}

TEST(MetricsFpsnr, EqualsPsnrWhenWeightIsConstant) {
  // 10 deg FOV over 200 px: ppd ~ 20, Nyquist ~ 10 > f_c(20 deg) ~ 4.05 everywhere.
  Camera cam = testutil::camera(200, 120, 10, 6);
  std::vector<float> ecc(cam.width * size_t(cam.height), 20.f);
  Image a = testutil::pattern(200, 120, 3, 21), b = testutil::pattern(200, 120, 3, 22, 0.4);
  EXPECT_NEAR(fpsnr(a, b, ecc, cam), psnr(a, b), 1e-9);
  EXPECT_TRUE(std::isinf(fpsnr(a, a, ecc, cam)));
}

TEST(MetricsFpsnr, WeighsFovealErrorsMore) {
  // 400 px over 40 deg: ppd ~ 10, so the weight falls from the Nyquist clip (~5) at the
  // gaze to f_c(27 deg) ~ 3.1 in the corners.
  const int N = 400;
  Camera cam = testutil::camera(N, N, 40, 40);
  std::vector<float> ecc = eccentricity_map(cam, glm::dvec3(0, 0, -1));
  Image ref(N, N, 3, 0.5f), near = ref, far = ref;
  // Same number of wrong pixels, same error: once around the gaze, once in a corner.
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 20; ++x)
      for (int c = 0; c < 3; ++c) {
        near.at(N / 2 - 10 + x, N / 2 - 10 + y)[c] += 0.2f;
        far.at(x, y)[c] += 0.2f;
      }
  EXPECT_NEAR(psnr(near, ref), psnr(far, ref), 1e-9);
  EXPECT_LT(fpsnr(near, ref, ecc, cam), psnr(near, ref));
  EXPECT_GT(fpsnr(far, ref, ecc, cam), psnr(far, ref));
  EXPECT_GT(fpsnr(far, ref, ecc, cam) - fpsnr(near, ref, ecc, cam), 1.5);
}

TEST(MetricsFpsnr, NyquistClipDominatesAtLowPixelDensity) {
  // 100 px over 100 deg (ppd < 1.5): every weight is clipped to ppd/2, which grows towards
  // the edges of a rectilinear projection, so a corner error counts more than a central one.
  Camera cam = testutil::camera(100, 100, 100, 100);
  std::vector<float> ecc = eccentricity_map(cam, glm::dvec3(0, 0, -1));
  Image ref(100, 100, 1, 0.5f), near = ref, far = ref;
  near.at(50, 50)[0] += 0.2f;
  far.at(0, 0)[0] += 0.2f;
  EXPECT_GT(fpsnr(near, ref, ecc, cam), fpsnr(far, ref, ecc, cam));
}

TEST(MetricsFpsnr, TwoZoneExpectedValue) {
  Camera cam = testutil::camera(64, 32, 5, 2.5);  // ppd ~ 12.8: f_c(0) is clipped, f_c(30) is not
  std::vector<float> ecc(64 * 32);
  Image ref(64, 32, 1, 0.5f), test = ref;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) {
      bool fov = x < 32;
      ecc[size_t(y) * 64 + x] = fov ? 0.f : 30.f;
      test.at(x, y)[0] += fov ? 0.05f : 0.25f;
    }
  double sw = 0, swe = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) {
      double w = fpsnr_weight(ecc[size_t(y) * 64 + x], local_ppd(cam, x + 0.5, y + 0.5));
      double e = x < 32 ? 0.05 : 0.25;
      sw += w;
      swe += w * e * e;
    }
  EXPECT_LT(fpsnr_weight(0, local_ppd(cam, 16, 16)), kFc0);  // clipping is active in this case
  EXPECT_NEAR(fpsnr(test, ref, ecc, cam), 10 * std::log10(sw / swe), 1e-5);
}

TEST(MetricsFpsnr, RejectsMismatchedInputs) {
  Camera cam = testutil::camera(20, 20, 10, 10);
  Image a(20, 20, 3);
  EXPECT_THROW(fpsnr(a, a, std::vector<float>(399), cam), Error);
  EXPECT_THROW(fpsnr(a, a, std::vector<float>(400), testutil::camera(21, 20, 10, 10)), Error);
}

// Eccentricity = column index (degrees) so regions and bands are column ranges.
static std::vector<float> column_ecc(int w, int h) {
  std::vector<float> e(size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) e[size_t(y) * w + x] = float(x);
  return e;
}

TEST(MetricsRegions, FoveaPeripheryAndBands) {
  const int W = 40, H = 12;
  Camera cam = testutil::camera(W, H, 40, 12);
  std::vector<float> ecc = column_ecc(W, H);
  Image ref(W, H, 3, 0.5f), test = ref;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      for (int c = 0; c < 3; ++c) test.at(x, y)[c] += x < 5 ? 0.1f : (x < 10 ? 0.2f : 0.3f);
  MetricsConfig cfg;
  cfg.set("psnr", false);
  cfg.set("ssim", false);
  cfg.set("fpsnr", false);
  cfg.set("temporal", false);
  cfg.fovea_deg = 5;
  cfg.band_edges_deg = {0, 5, 10, 20, 50, 60};
  MetricValues m = compute_metrics(cfg, test, ref, cam, ecc, nullptr);
  EXPECT_NEAR(m.get("rmse_fovea"), 0.1, 1e-6);
  EXPECT_NEAR(m.get("rmse_periphery"), std::sqrt((5 * 0.04 + 30 * 0.09) / 35), 1e-6);
  EXPECT_NEAR(m.get("rmse_ecc_0_5"), 0.1, 1e-6);
  EXPECT_NEAR(m.get("rmse_ecc_5_10"), 0.2, 1e-6);
  EXPECT_NEAR(m.get("rmse_ecc_10_20"), 0.3, 1e-6);
  EXPECT_NEAR(m.get("rmse_ecc_20_50"), 0.3, 1e-6);   // columns 20..39
  EXPECT_TRUE(std::isnan(m.get("rmse_ecc_50_60")));  // no pixel there
  EXPECT_FALSE(m.has("psnr"));
  EXPECT_FALSE(m.has("temporal_error"));
  // Everything in the fovea: the periphery is empty (NaN), not 0.
  cfg.fovea_deg = 100;
  EXPECT_TRUE(std::isnan(compute_metrics(cfg, test, ref, cam, ecc, nullptr).get("rmse_periphery")));
}

TEST(MetricsRegions, BandColumnNames) {
  EXPECT_EQ(band_column(0, 5), "rmse_ecc_0_5");
  EXPECT_EQ(band_column(2.5, 10), "rmse_ecc_2p5_10");
  EXPECT_EQ(band_column(30, 60), "rmse_ecc_30_60");
}
