// The per-frame metrics (sim/metrics/frame_metric.h) as declared: each one's toggle is a row
// of the `metrics` block's table documented in configs/README.md and docs/metrics.md, each
// column it writes has a registry declaration and is documented in docs/metrics.md and
// results/README.md, and compute_metrics writes exactly the declared columns, in order.
#include "sim/metrics/frame_metric.h"

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "metrics_test_util.h"
#include "sim/core/param_table.h"
#include "sim/metrics/registry.h"

using namespace fovsim;

namespace {

std::string slurp(const std::string& rel) {
  std::ifstream f(std::string(FOVSIM_SOURCE_DIR) + "/" + rel);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::vector<MetricToggle> toggles_of(const FrameMetric& m) {
  std::vector<MetricToggle> t{m.toggle};
  if (m.image) t.push_back(m.image_toggle);
  return t;
}

}  // namespace

TEST(FrameMetrics, EveryToggleAndColumnIsDeclaredAndDocumented) {
  const std::string config_doc = slurp("configs/README.md");
  const std::string metrics_doc = slurp("docs/metrics.md");
  const std::string results_doc = slurp("results/README.md");
  ASSERT_FALSE(config_doc.empty());
  std::set<std::string> rows;
  for (const auto& r : metrics_config_table().rows()) rows.insert(r.key);
  std::set<std::string> names;
  for (const FrameMetric& m : frame_metrics()) {
    EXPECT_TRUE(names.insert(m.name).second) << "two per-frame metrics named " << m.name;
    ASSERT_TRUE(m.compute) << m.name;
    ASSERT_TRUE(m.columns) << m.name;
    for (const MetricToggle& t : toggles_of(m)) {
      EXPECT_TRUE(rows.count(t.key)) << m.name << ": metrics." << t.key << " is not a row";
      EXPECT_NE(config_doc.find("| `" + std::string(t.key) + "` |"), std::string::npos)
          << m.name << ": metrics." << t.key << " not in configs/README.md (run `make docs`)";
      EXPECT_NE(metrics_doc.find("`" + std::string(t.key) + "`"), std::string::npos)
          << m.name << ": metrics." << t.key << " not in docs/metrics.md";
      EXPECT_GT(std::string(t.doc).size(), 0u) << m.name << ": " << t.key << " has no doc line";
    }
    const MetricsConfig cfg;
    const auto cols = m.columns(cfg);
    EXPECT_FALSE(cols.empty()) << m.name;
    for (const std::string& c : cols) {
      const MetricDecl* d = find_metric(c);
      ASSERT_NE(d, nullptr) << m.name << ": column " << c << " has no registry declaration";
      // A family's columns are documented by its prefix (`rmse_ecc_<a>_<b>`, `rmse_ecc_*`).
      const std::string shown = "`" + (d->family ? d->name : c);
      EXPECT_NE(metrics_doc.find(shown), std::string::npos) << c << " not in docs/metrics.md";
      EXPECT_NE(results_doc.find(shown), std::string::npos) << c << " not in results/README.md";
    }
  }
}

TEST(FrameMetrics, ComputeWritesTheDeclaredColumnsInOrder) {
  const int W = 32, H = 20;
  const Camera cam = testutil::camera(W, H, 60, 40);
  const Image ref = testutil::pattern(W, H, 3, 71), test = testutil::pattern(W, H, 3, 72, 0.3);
  std::vector<float> ecc(size_t(W) * H);
  for (size_t i = 0; i < ecc.size(); ++i) ecc[i] = float(i % W);  // 0 .. 31 degrees
  for (const bool regions : {true, false}) {
    MetricsConfig cfg;
    cfg.set("regions", regions);
    TemporalState st;
    const MetricValues v = compute_metrics(cfg, test, ref, cam, ecc, &st);
    std::vector<std::string> got;
    for (auto& kv : v.items()) got.push_back(kv.first);
    EXPECT_EQ(got, frame_metric_columns(cfg));
  }
}
