// A counter the cost model needs for a pass the method declares, but the method did not fill,
// is a flag of the row and of the run (summary.json "flags"), never silence (docs/architecture.md
// "Cost model"). The flc method declares its own VPL passes (RSMs, importance, culling) on any
// scene; on a scene without indirect light it renders the direct light only and fills none of their
// counters.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "sim/core/files.h"
#include "sim/experiment/runner.h"

using namespace fovsim;

TEST(MissingCounters, RowColumnAndManifestFlag) {
  LoadedConfig c;
  c.file = "missing.json";
  c.doc = Json{{"name", "missing"},
               {"display", "htc_vive_pro_eye"},
               {"render", {{"scale", 0.04}, {"spp", 1}}},
               {"scene", {{"type", "atrium"}, {"complexity", 1}}},
               {"trace", {{"synthetic", {{"scenario", "fixate"}, {"seed", 2}, {"duration", 0.1}}}}},
               {"frames", {{"count", 2}}},
               {"methods", Json::array({Json{{"method", "full"}}, Json{{"method", "flc"}}})},
               {"outputs", {{"print_summary", false}}}};
  RunOptions o;
  o.out_dir = (std::filesystem::temp_directory_path() / "fovsim_missing_counters").string();
  o.models_dir = std::string(FOVSIM_SOURCE_DIR) + "/models";
  o.print_summary = false;
  RunResult r = run_experiment(c, o);
  int flc_rows = 0;
  for (auto& row : r.frames.rows()) {
    const std::string* label = row.text_of("label");
    ASSERT_NE(label, nullptr);
    const std::string* mc = row.text_of("missing_counters");
    if (*label == "full") {
      EXPECT_TRUE(mc == nullptr || mc->empty()) << *mc;
      continue;
    }
    ++flc_rows;
    ASSERT_NE(mc, nullptr);
    for (const char* n : {"rsm_texels", "importance_samples", "vpls_total", "contribution_evals"})
      EXPECT_NE(mc->find(n), std::string::npos) << n << " not in " << *mc;
  }
  EXPECT_EQ(flc_rows, 2);
  // The run's flags (summary.json "flags") name the configuration.
  const Json man = Json::parse(read_file(r.out_dir + "/summary.json"));
  bool flag = false, full_flag = false;
  for (auto& f : man["flags"]) {
    flag = flag || f.get<std::string>() == "flc:missing_counters";
    full_flag = full_flag || f.get<std::string>() == "full:missing_counters";
  }
  EXPECT_TRUE(flag) << man["flags"].dump();
  EXPECT_FALSE(full_flag);
}
