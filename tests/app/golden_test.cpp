// Regression: a short trace through the `full` method compared with a committed golden
// frames.csv. Tolerances: numeric columns match within |a-b| <= 1e-6 + 1e-4*|b| (renders are
// deterministic; the slack absorbs compiler/libm differences), text columns exactly, and the
// column set exactly. Wall-time columns (sim_ms, ref_ms) are ignored.
// Refresh after an intended change: build/test_app --gtest_filter='Golden*' --update-golden
#include <gtest/gtest.h>

#include <cmath>

#include "tests/app/app_util.h"

using namespace fovsim_test;
extern bool g_update_golden;

namespace {

void check_golden(const std::string& config, const std::string& golden) {
  std::string dir = temp_dir("golden");
  auto r = run_cmd(fovsim_bin() + " run " + config + " -q --out " + dir);
  ASSERT_EQ(r.code, 0) << r.output;
  std::string gpath = std::string(FOVSIM_SOURCE_DIR) + "/" + golden;
  if (g_update_golden) {
    std::filesystem::copy_file(dir + "/frames.csv", gpath,
                               std::filesystem::copy_options::overwrite_existing);
    GTEST_SKIP() << "golden updated: " << gpath;
  }
  ASSERT_TRUE(std::filesystem::exists(gpath))
      << "missing golden " << gpath << " (run with --update-golden)";
  Csv got = read_csv(dir + "/frames.csv"), want = read_csv(gpath);
  ASSERT_EQ(got.header, want.header)
      << "column set changed: a breaking change of results/README.md";
  ASSERT_EQ(got.rows.size(), want.rows.size());
  for (size_t i = 0; i < got.rows.size(); ++i)
    for (size_t k = 0; k < got.header.size(); ++k) {
      const std::string& col = got.header[k];
      if (col == "sim_ms" || col == "ref_ms") continue;
      const std::string &a = got.rows[i][k], &b = want.rows[i][k];
      char* end = nullptr;
      double va = std::strtod(a.c_str(), &end);
      bool numeric = end && *end == '\0' && !a.empty();
      if (!numeric) {
        EXPECT_EQ(a, b) << "row " << i << " column " << col;
        continue;
      }
      double vb = std::strtod(b.c_str(), nullptr);
      if (std::isnan(vb) || std::isinf(vb)) {
        EXPECT_EQ(a, b) << "row " << i << " column " << col;
      } else {
        EXPECT_LE(std::fabs(va - vb), 1e-6 + 1e-4 * std::fabs(vb))
            << "row " << i << " column " << col << ": " << a << " vs golden " << b;
      }
    }
}

}  // namespace

TEST(Golden, FullMethodShortTrace) {
  check_golden("tests/golden/full_small.json", "tests/golden/full_small.frames.csv");
}

TEST(Golden, EveryMethodShortTrace) {
  check_golden("tests/golden/methods_small.json", "tests/golden/methods_small.frames.csv");
}
