// One lighting model per scene through the engine (sim/experiment/engine.cpp): on a scene with
// indirect light every row is measured against the same reference (direct + indirect from all
// VPLs), `full` is that reference (PSNR inf), FLC with a budget covering every VPL is too, and
// FLC's culled lighting is charged less than TBDS; without indirect light no lighting column
// or pass exists.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <string>

#include "sim/core/error.h"
#include "sim/experiment/runner.h"
#include "sim/experiment/sweep_spec.h"

using namespace fovsim;

namespace {

RunResult run(const Json& scene, const Json& methods, const std::string& name, int spp = 1) {
  LoadedConfig c;
  c.file = "lighting.json";
  c.doc = Json{{"name", name},
               {"display", "htc_vive_pro_eye"},
               {"render", {{"scale", 0.04}, {"spp", spp}}},
               {"scene", scene},
               {"trace", {{"synthetic", {{"scenario", "fixate"}, {"seed", 2}, {"duration", 0.1}}}}},
               {"frames", {{"count", 2}}},
               {"methods", methods},
               {"outputs", {{"print_summary", false}}}};
  RunOptions o;
  o.out_dir = (std::filesystem::temp_directory_path() / ("fovsim_lighting_" + name)).string();
  o.models_dir = std::string(FOVSIM_SOURCE_DIR) + "/models";
  o.print_summary = false;
  return run_experiment(c, o);
}

std::map<std::string, const ResultRow*> by_label(const RunResult& r) {
  std::map<std::string, const ResultRow*> m;
  for (auto& row : r.summary.rows()) m[*row.text_of("label")] = &row;
  return m;
}

}  // namespace

TEST(LightingRows, EveryRowAgainstTheSameReference) {
  const Json scene{{"type", "cornell"}, {"vpl", {{"rsm_size", 8}}}};
  const Json methods = Json::array(
      {Json{{"method", "full"}},
       // Without TAA: the image itself against the reference.
       Json{{"method", "flc"}, {"label", "flc_all"}, {"vpl_budget", 100000}, {"taa", false}},
       Json{{"method", "flc"}, {"vpl_budget", 8}},
       Json{{"method", "full"},
            {"label", "fir"},
            {"lighting", {{"method", "fir"}, {"vpl_budget", 8}}}},
       Json{{"method", "kfr"}, {"lighting", {{"method", "flc"}, {"vpl_budget", 8}}}}});
  RunResult r = run(scene, methods, "rows");
  auto m = by_label(r);
  ASSERT_EQ(m.size(), 5u);
  EXPECT_TRUE(std::isinf(m["full"]->get("psnr", 0)));
  EXPECT_TRUE(std::isinf(m["flc_all"]->get("psnr", 0)));  // all VPLs kept = the reference
  for (const char* l : {"flc", "fir", "kfr"}) {
    EXPECT_TRUE(std::isfinite(m[l]->get("psnr", NAN))) << l;
    EXPECT_LE(m[l]->get("vpls_kept", 1e9), 8.0) << l;
  }
  EXPECT_EQ(*m["full"]->text_of("lighting"), "all_vpls");
  EXPECT_EQ(*m["fir"]->text_of("lighting"), "fir");
  EXPECT_EQ(*m["kfr"]->text_of("lighting"), "flc");
  // Charged for what they shade: FLC (8 VPLs) below TBDS (all VPLs); both pay for the RSMs.
  EXPECT_LT(m["flc"]->get("est_ms_total", 0), m["full"]->get("est_ms_total", 0));
  EXPECT_GT(m["full"]->get("est_ms_rsm", 0), 0.0);
  EXPECT_GT(m["kfr"]->get("est_ms_rsm", 0), 0.0);
  EXPECT_GT(m["kfr"]->get("est_ms_light_culling", 0), 0.0);
}

// With a supersampled reference, `full` is one sample per pixel plus all VPLs: finite PSNR, and
// FLC keeping every VPL renders exactly the same image (its difference is aliasing only).
TEST(LightingRows, SupersampledReferenceFullAndFlcAllAgree) {
  const Json scene{{"type", "cornell"}, {"vpl", {{"rsm_size", 8}}}};
  const Json methods = Json::array(
      {Json{{"method", "full"}},
       Json{{"method", "flc"}, {"label", "flc_all"}, {"vpl_budget", 100000}, {"taa", false}}});
  RunResult r = run(scene, methods, "rows_spp4", 4);
  auto m = by_label(r);
  ASSERT_EQ(m.size(), 2u);
  const double full = m["full"]->get("psnr", NAN), all = m["flc_all"]->get("psnr", NAN);
  EXPECT_TRUE(std::isfinite(full));
  EXPECT_NEAR(full, all, 1e-9);
}

TEST(LightingRows, NoIndirectNoLightingColumnsOrPasses) {
  const Json scene{{"type", "atrium"}, {"complexity", 1}};
  const Json methods =
      Json::array({Json{{"method", "full"}},
                   Json{{"method", "kfr"}, {"lighting", {{"method", "flc"}, {"vpl_budget", 8}}}}});
  RunResult r = run(scene, methods, "noind");
  for (auto& row : r.frames.rows()) {
    EXPECT_EQ(row.text_of("lighting"), nullptr);
    for (const char* k : {"vpls_kept", "rsm_texels", "shaded_sample_vpls", "est_ms_rsm",
                          "est_ms_importance", "est_ms_light_culling", "vpl_budget"})
      EXPECT_TRUE(std::isnan(row.get(k, NAN))) << k;
  }
}

TEST(LightingRows, LightingKeysAreSweepAxes) {
  LoadedConfig c;
  c.file = "s.json";
  c.doc = Json::parse(R"({"name": "t", "scene": {"type": "cornell"},
    "methods": [{"method": "kfr", "lighting": {"method": "flc"}}],
    "sweep": {"grid": {"methods[kfr].lighting.vpl_budget": [16, 64]}}})");
  SweepPlan p = expand_sweep(c);
  ASSERT_EQ(p.cells.size(), 2u);
  EXPECT_NO_THROW(validate_cells(p));
  EXPECT_EQ(p.cells[1].doc["methods"][0]["lighting"]["vpl_budget"], 64);
  // A typo in a lighting axis is an error naming the path, never a silent default.
  c.doc["sweep"]["grid"] = Json{{"methods[kfr].lighting.vpl_budgte", Json::array({16})}};
  try {
    validate_cells(expand_sweep(c));
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("lighting.vpl_budgte"), std::string::npos) << e.what();
  }
}
