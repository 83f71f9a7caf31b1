// `fovsim run` makes plots through the one launcher (sim/experiment/plots.h): plots/index.html
// when /usr/bin/python3 has matplotlib, else one "plots skipped" line; --no-plots makes none.
#include <gtest/gtest.h>

#include "tests/app/app_util.h"

using namespace fovsim_test;
namespace fs = std::filesystem;

TEST(PlotsCli, RunMakesPlotsUnlessNoPlots) {
  std::string dir = temp_dir("plots_cli");
  write_text(dir + "/c.json", R"({
  "name": "plots_cli",
  "display": "htc_vive_pro_eye",
  "render": {"scale": 0.05},
  "scene": {"type": "atrium", "complexity": 1},
  "trace": {"file": ")" + std::string(FOVSIM_SOURCE_DIR) +
                                  R"(/tests/golden/golden_trace.csv"},
  "frames": {"count": 2},
  "methods": [{"method": "full"}, {"method": "kfr"}],
  "outputs": {"print_summary": false}
})");
  // test_app's main sets FOVSIM_NO_PLOTS; this test wants the default behaviour.
  auto r = run_cmd("env -u FOVSIM_NO_PLOTS " + fovsim_bin() + " run " + dir + "/c.json --out " +
                   dir + "/a");
  ASSERT_EQ(r.code, 0) << r.output;
  bool have_mpl = std::system("/usr/bin/python3 -c 'import matplotlib' >/dev/null 2>&1") == 0;
  if (have_mpl) {
    EXPECT_TRUE(fs::exists(dir + "/a/plots/index.html")) << r.output;
    EXPECT_TRUE(fs::exists(dir + "/a/plots/quality_timeline.png")) << r.output;
    EXPECT_NE(read_text(dir + "/a/plots/index.html").find("<table>"), std::string::npos);
  } else {
    EXPECT_NE(r.output.find("plots skipped: /usr/bin/python3"), std::string::npos) << r.output;
  }
  auto n = run_cmd("env -u FOVSIM_NO_PLOTS " + fovsim_bin() + " run " + dir + "/c.json --out " +
                   dir + "/b --no-plots");
  ASSERT_EQ(n.code, 0) << n.output;
  EXPECT_FALSE(fs::exists(dir + "/b/plots"));
  EXPECT_EQ(n.output.find("plot: wrote"), std::string::npos) << n.output;
  EXPECT_EQ(n.output.find("plots skipped"), std::string::npos) << n.output;
}
