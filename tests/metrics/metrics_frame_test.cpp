// Temporal error, compute_metrics columns, config parsing, thread-count determinism.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

#include "metrics_test_util.h"
#include "sim/core/error.h"
#include "sim/metrics/flip_metric.h"
#include "sim/metrics/metrics.h"

using namespace fovsim;

static std::vector<float> half_ecc(int w, int h) {  // left half fovea (1 deg), right half 30 deg
  std::vector<float> e(size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) e[size_t(y) * w + x] = x < w / 2 ? 1.f : 30.f;
  return e;
}

TEST(MetricsTemporal, StaticErrorIsZeroFlickerIsItsAmplitude) {
  const int W = 32, H = 16;
  std::vector<float> ecc = half_ecc(W, H);
  Image ref = testutil::pattern(W, H, 3, 31, 0.0);
  for (float& v : ref.data) v = 0.25f + 0.5f * v;
  Image stat = ref;
  for (float& v : stat.data) v += 0.1f;
  TemporalState st;
  EXPECT_TRUE(std::isnan(temporal_error(stat, ref, ecc, 5.0, st)));  // first frame
  for (int t = 0; t < 3; ++t) EXPECT_NEAR(temporal_error(stat, ref, ecc, 5.0, st), 0.0, 1e-7);

  // Flicker +d / -d in every channel of the periphery: luma error changes by 2d per frame.
  st.reset();
  const float d = 0.05f;
  for (int t = 0; t < 4; ++t) {
    Image f = ref;
    for (int y = 0; y < H; ++y)
      for (int x = W / 2; x < W; ++x)
        for (int c = 0; c < 3; ++c) f.at(x, y)[c] += (t % 2 ? -d : d);
    double te = temporal_error(f, ref, ecc, 5.0, st);
    if (t == 0)
      EXPECT_TRUE(std::isnan(te));
    else
      EXPECT_NEAR(te, 2 * d, 1e-6);
  }
  // Flicker only inside the fovea is not counted.
  st.reset();
  for (int t = 0; t < 3; ++t) {
    Image f = ref;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W / 2; ++x) f.at(x, y)[0] += (t % 2 ? -d : d);
    double te = temporal_error(f, ref, ecc, 5.0, st);
    if (t > 0) {
      EXPECT_NEAR(te, 0.0, 1e-7);
    }
  }
  // A size change behaves like a reset.
  Image small(W / 2, H, 3, 0.5f);
  EXPECT_TRUE(
      std::isnan(temporal_error(small, small, std::vector<float>(small.pixels(), 30.f), 5.0, st)));
}

TEST(MetricsCompute, ColumnsInOrderAndConsistentWithStandaloneFunctions) {
  const int W = 48, H = 40;
  Camera cam = testutil::camera(W, H, 60, 50);
  std::vector<float> ecc = eccentricity_map(cam, glm::dvec3(0.1, 0, -1));
  Image ref = testutil::pattern(W, H, 3, 41), test = testutil::pattern(W, H, 3, 42, 0.3);
  MetricsConfig cfg;
  TemporalState st;
  MetricValues m = compute_metrics(cfg, test, ref, cam, ecc, &st);
  std::vector<std::string> names;
  for (auto& kv : m.items()) names.push_back(kv.first);
  std::vector<std::string> want{
      "psnr",           "ssim",          "fpsnr",          "rmse_fovea",     "rmse_periphery",
      "rmse_ecc_0_5",   "rmse_ecc_5_10", "rmse_ecc_10_20", "rmse_ecc_20_30", "rmse_ecc_30_60",
      "flip",           "flip_ecc_0_5",  "flip_ecc_5_10",  "flip_ecc_10_20", "flip_ecc_20_30",
      "flip_ecc_30_60", "temporal_error"};
  EXPECT_EQ(names, want);
  EXPECT_DOUBLE_EQ(m.get("psnr"), psnr(test, ref));
  EXPECT_DOUBLE_EQ(m.get("ssim"), ssim(test, ref));
  EXPECT_DOUBLE_EQ(m.get("fpsnr"), fpsnr(test, ref, ecc, cam));
  EXPECT_DOUBLE_EQ(m.get("flip"), flip(ref, test, flip_ppd(cam)));
  EXPECT_TRUE(std::isnan(m.get("temporal_error")));
  EXPECT_FALSE(std::isnan(compute_metrics(cfg, test, ref, cam, ecc, &st).get("temporal_error")));
  EXPECT_TRUE(std::isnan(compute_metrics(cfg, test, ref, cam, ecc, nullptr).get("temporal_error")));
  // Disabled metrics produce no column.
  cfg.set("ssim", false);
  cfg.set("fpsnr", false);
  cfg.set("regions", false);
  cfg.set("temporal", false);
  cfg.set("flip", false);
  MetricValues p = compute_metrics(cfg, test, ref, cam, {}, nullptr);
  ASSERT_EQ(p.items().size(), 1u);
  EXPECT_EQ(p.items()[0].first, "psnr");
}

// The test image's FLIP preparation handed from one compute_metrics to another (the engine's
// second reference, metrics.foveation_loss): the same numbers as preparing it again; a
// preparation at another ppd is an internal error; the identical-images shortcut leaves no
// valid preparation behind.
TEST(MetricsCompute, GivenTestFlipPreparationGivesTheSameNumbers) {
  const int W = 40, H = 24;
  std::vector<float> ecc = half_ecc(W, H);
  Camera cam = testutil::camera(W, H, 60, 40);
  Image ref = testutil::pattern(W, H, 3, 61), ref2 = testutil::pattern(W, H, 3, 62),
        test = testutil::pattern(W, H, 3, 63, 0.4);
  MetricsConfig cfg;
  cfg.set("ssim", false);
  cfg.set("temporal", false);
  MetricsScratch a, b;
  compute_metrics(cfg, test, ref, cam, ecc, nullptr, &a);
  ASSERT_TRUE(flip_scratch(a)->test_valid);
  const MetricValues given = compute_metrics(cfg, test, ref2, cam, ecc, nullptr, &b, &a);
  EXPECT_FALSE(flip_scratch(b)->test_valid);
  MetricsScratch c;
  const MetricValues own = compute_metrics(cfg, test, ref2, cam, ecc, nullptr, &c);
  ASSERT_EQ(given.items().size(), own.items().size());
  for (size_t k = 0; k < own.items().size(); ++k) {
    EXPECT_EQ(given.items()[k].first, own.items()[k].first);
    const double g = given.items()[k].second, o = own.items()[k].second;
    if (std::isnan(o))
      EXPECT_TRUE(std::isnan(g)) << own.items()[k].first;  // an empty band
    else
      EXPECT_EQ(g, o) << own.items()[k].first;
  }
  MetricsScratch other;
  compute_metrics(cfg, test, ref, cam, ecc, nullptr, &other);
  const_cast<FlipScratch*>(flip_scratch(other))->test.ppd *= 2;
  EXPECT_THROW(compute_metrics(cfg, test, ref2, cam, ecc, nullptr, &b, &other), InternalError);
  compute_metrics(cfg, ref, ref, cam, ecc, nullptr, &a);  // identical: no preparation
  EXPECT_FALSE(flip_scratch(a)->test_valid);
}

TEST(MetricsCompute, FlipBandsAreMeansOfTheMapOverTheirPixels) {
  const int W = 40, H = 24;
  std::vector<float> ecc = half_ecc(W, H);  // left half 1 deg, right half 30 deg
  Camera cam = testutil::camera(W, H, 60, 40);
  Image ref = testutil::pattern(W, H, 3, 51), test = testutil::pattern(W, H, 3, 52, 0.4);
  MetricsConfig cfg;
  cfg.set("ssim", false);
  cfg.set("fpsnr", false);
  cfg.set("temporal", false);
  MetricsScratch sc;
  MetricValues m = compute_metrics(cfg, test, ref, cam, ecc, nullptr, &sc);
  const Image& map = flip_scratch(sc)->map;
  ASSERT_EQ(map.width, W);
  ASSERT_EQ(map.height, H);
  double left = 0, right = 0, all = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      (x < W / 2 ? left : right) += map.at(x, y)[0];
      all += map.at(x, y)[0];
    }
  const double half = double(W / 2) * H;
  EXPECT_NEAR(m.get("flip"), all / (W * H), 1e-6);  // the map is float
  EXPECT_NEAR(m.get("flip_ecc_0_5"), left / half, 1e-12);
  EXPECT_NEAR(m.get("flip_ecc_30_60"), right / half, 1e-12);
  EXPECT_TRUE(std::isnan(m.get("flip_ecc_5_10")));  // empty band
  EXPECT_GT(m.get("flip_ecc_0_5"), 0.0);
  // The ppd comes from the camera: a wider FOV on the same pixels is fewer pixels per degree.
  EXPECT_LT(flip_ppd(testutil::camera(W, H, 90, 60)), flip_ppd(cam));
  EXPECT_NEAR(flip_ppd(cam), local_ppd(cam, W / 2.0, H / 2.0), 1e-12);
  // Without regions: the mean only.
  cfg.set("regions", false);
  MetricValues n = compute_metrics(cfg, test, ref, cam, ecc, nullptr);
  ASSERT_EQ(n.items().size(), 2u);  // psnr, flip
  EXPECT_EQ(n.get("flip"), m.get("flip"));
  // The scratch's prepared reference is reused, and replaced when the reference changes.
  Image test2 = testutil::pattern(W, H, 3, 53, 0.4), ref2 = testutil::pattern(W, H, 3, 54);
  EXPECT_EQ(compute_metrics(cfg, test2, ref, cam, ecc, nullptr, &sc).get("flip"),
            flip(ref, test2, flip_ppd(cam)));
  EXPECT_EQ(compute_metrics(cfg, test2, ref2, cam, ecc, nullptr, &sc).get("flip"),
            flip(ref2, test2, flip_ppd(cam)));
  EXPECT_EQ(compute_metrics(cfg, test, ref, cam, ecc, nullptr, &sc).get("flip"), m.get("flip"));
}

TEST(MetricsConfigTest, DefaultsAndOverrides) {
  Params empty(Json::object(), "run.json", "metrics");
  MetricsConfig d = MetricsConfig::from_params(empty);
  for (const char* k : {"psnr", "ssim", "fpsnr", "regions", "temporal", "flip", "flip_images"})
    EXPECT_TRUE(d.on(k)) << k;
  EXPECT_EQ(d.fovea_deg, 5.0);
  EXPECT_EQ(d.band_edges_deg, (std::vector<double>{0, 5, 10, 20, 30, 60}));
  Params p(Json::parse(R"({"ssim": false, "fovea_deg": 2.5, "band_edges_deg": [0, 2.5, 90]})"),
           "run.json", "metrics");
  MetricsConfig c = MetricsConfig::from_params(p);
  p.finish();
  EXPECT_FALSE(c.on("ssim"));
  EXPECT_TRUE(c.on("psnr"));
  EXPECT_EQ(c.fovea_deg, 2.5);
  EXPECT_EQ(c.band_edges_deg, (std::vector<double>{0, 2.5, 90}));
  Params none(Json::parse(R"({"band_edges_deg": []})"));
  EXPECT_TRUE(MetricsConfig::from_params(none).band_edges_deg.empty());
}

static std::string error_of(const char* json) {
  Params p(Json::parse(json), "run.json", "metrics");
  try {
    MetricsConfig::from_params(p);
    p.finish();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(MetricsConfigTest, InvalidValuesNameTheKey) {
  EXPECT_NE(error_of(R"({"band_edges_deg": [0, 10, 10]})").find("metrics.band_edges_deg[2]"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"band_edges_deg": [0, 10, 5]})").find("strictly increasing"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"band_edges_deg": [5]})").find("at least 2 edges"), std::string::npos);
  EXPECT_NE(error_of(R"({"band_edges_deg": [0, 200]})").find("band_edges_deg[1]"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"fovea_deg": 0})").find("metrics.fovea_deg"), std::string::npos);
  EXPECT_NE(error_of(R"({"ssim": "yes"})").find("metrics.ssim"), std::string::npos);
  EXPECT_NE(error_of(R"({"flip": 1})").find("metrics.flip"), std::string::npos);
  EXPECT_NE(error_of(R"({"psnrr": true})").find("psnrr"),
            std::string::npos);  // typo caught by finish()
  EXPECT_EQ(error_of(R"({"fovea_deg": 3})"), "");
}

TEST(MetricsDeterminism, IdenticalAtOneAndManyThreads) {
  const int W = 257, H = 203;  // odd sizes, several SSIM blocks
  Camera cam = testutil::camera(W, H, 90, 80);
  std::vector<float> ecc = eccentricity_map(cam, glm::dvec3(-0.2, 0.1, -1));
  Image ref = testutil::pattern(W, H, 3, 51), t0 = testutil::pattern(W, H, 3, 52, 0.3),
        t1 = testutil::pattern(W, H, 3, 53, 0.3);
  auto run = [&](int threads) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
    MetricsConfig cfg;
    TemporalState st;
    compute_metrics(cfg, t0, ref, cam, ecc, &st);
    return compute_metrics(cfg, t1, ref, cam, ecc, &st);
  };
  MetricValues a = run(1), b = run(2), c = run(8);
  ASSERT_EQ(a.items().size(), b.items().size());
  for (size_t i = 0; i < a.items().size(); ++i) {
    EXPECT_FALSE(std::isnan(a.items()[i].second)) << a.items()[i].first;
    // Bitwise equality, not a tolerance.
    EXPECT_EQ(a.items()[i].second, b.items()[i].second) << a.items()[i].first;
    EXPECT_EQ(a.items()[i].second, c.items()[i].second) << a.items()[i].first;
  }
}
