// The `metrics` block reads its own declared defaults and ranges; the struct's defaults (what
// code that builds a MetricsConfig without a config gets) are the declared ones.
#include <gtest/gtest.h>

#include "sim/metrics/metrics.h"
#include "tests/common/param_table_check.h"

TEST(MetricsConfigDecl, TableReadsItsOwnDefaults) {
  fovsim::table_check::expect_table_reads_own_defaults(fovsim::metrics_config_table(), "metrics");
  const fovsim::MetricsConfig c;
  for (const auto& r : fovsim::metrics_config_table().rows()) EXPECT_EQ(r.get(c), r.def) << r.key;
}
