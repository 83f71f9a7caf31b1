// Every run-config table (top level, render, tonemap, frames, outputs, latency) reads its own
// declared defaults and ranges.
#include <gtest/gtest.h>

#include <algorithm>

#include "sim/cost/workload.h"
#include "sim/display/display_keys.h"
#include "sim/experiment/engine.h"
#include "sim/experiment/latency.h"
#include "sim/experiment/reference_cache.h"
#include "sim/experiment/run_config.h"
#include "sim/experiment/sweep_spec.h"
#include "tests/common/param_table_check.h"

using namespace fovsim;

TEST(RunConfigDecl, EveryTableReadsItsOwnDefaults) {
  table_check::expect_table_reads_own_defaults(run_shared_table(), "");
  RunCellKeys cell;
  cell.name = "stem";
  table_check::expect_table_reads_own_defaults(run_cell_table(), "", cell);
  table_check::expect_table_reads_own_defaults(display_table(), "display");
  table_check::expect_table_reads_own_defaults(render_block_table(), "render");
  table_check::expect_table_reads_own_defaults(tonemap_block_table(), "render.tonemap");
  table_check::expect_table_reads_own_defaults(frames_block_table(), "frames");
  table_check::expect_table_reads_own_defaults(outputs_block_table(), "outputs");
  table_check::expect_table_reads_own_defaults(latency_table(), "latency");
  table_check::expect_table_reads_own_defaults(latency_saccade_table(), "latency.saccade");
  table_check::expect_table_reads_own_defaults(latency_main_sequence_table(),
                                               "latency.main_sequence");
  table_check::expect_table_reads_own_defaults(cache_block_table(), "cache");
  table_check::expect_table_reads_own_defaults(sweep_table(), "sweep");
  table_check::expect_table_reads_own_defaults(iso_budget_table(), "sweep.iso_budget");
  table_check::expect_table_reads_own_defaults(search_table(), "sweep.search");
  table_check::expect_table_reads_own_defaults(workload_table(), "");
  table_check::expect_table_reads_own_defaults(pipeline_table(), "pipeline");
}

// A workload file read through its table writes back the same document (calibrate writes
// workloads with to_json and reads them with from_params).
TEST(RunConfigDecl, WorkloadRoundTrips) {
  Params p(Json{{"name", "w"}, {"overdraw", 2.5}, {"pipeline", {{"taa", true}}}}, "w.json", "");
  const Workload w = Workload::from_params(p);
  EXPECT_NO_THROW(p.finish());
  EXPECT_EQ(w.overdraw, 2.5);
  EXPECT_TRUE(w.pipeline.taa);
  Params q(w.to_json(), "w2.json", "");
  const Workload v = Workload::from_params(q);
  EXPECT_EQ(v.to_json(), w.to_json());
  EXPECT_EQ(w.to_json()["pipeline"]["depth_prepass"], true);
  EXPECT_EQ(w.to_json()["shading_flops"], 3000);
}

TEST(RunConfigDecl, DefaultsTheCallerSetsAreKept) {
  // name, tonemap.exposure, outputs.print_summary default to what the caller knows.
  Params p(Json::object(), "run.json", "");
  RunCellKeys k;
  k.name = "quickstart";
  run_cell_table().read_into(p, k);
  EXPECT_EQ(k.name, "quickstart");
  EXPECT_EQ(p.resolved()["name"], "quickstart");
  Params q(Json::object(), "run.json", "outputs");
  OutputsBlock o;
  o.print_summary = false;
  outputs_block_table().read_into(q, o);
  EXPECT_FALSE(o.print_summary);
}

TEST(RunConfigDecl, MarkdownHasEveryKey) {
  const std::string md = config_keys_markdown();
  for (const char* k : {"`seed`",
                        "`display`",
                        "`gpus`",
                        "`max_pixels`",
                        "`spp`",
                        "`curve`",
                        "`warmup`",
                        "`print_summary`",
                        "`band_edges_deg`",
                        "`jitter_ms`",
                        "`velocity_threshold_deg_s`",
                        "`slope_ms_per_deg`",
                        "`l2_mb`",
                        "`peak_luminance`",
                        "`fov_h_deg`",
                        "`max_samples`",
                        "`scenario`",
                        "`max_triangles`",
                        "`max_vpls`",
                        "`complexity`",
                        "`pattern`",
                        "`cell`",
                        "`max_texture_pixels`",
                        "`max_gb`"})
    EXPECT_NE(md.find(k), std::string::npos) << k;
}

// Cells of one reference group that differ only in the cost model's workload share the
// reference, and every cell reads its own workload (a key missing from per_cell_keys() was
// dropped from the second cell on, which then fell back to the generic workload).
TEST(RunConfigDecl, WorkloadIsReadPerCell) {
  const auto& keys = fovsim::per_cell_keys();
  EXPECT_NE(std::find(keys.begin(), keys.end(), "workload"), keys.end());
  fovsim::Json a = {{"workload", "kfr_bistro"}, {"render", {{"scale", 0.1}}}};
  fovsim::Json b = a;
  b["workload"] = "generic";
  EXPECT_EQ(fovsim::reference_key(a), fovsim::reference_key(b));
  b["render"]["scale"] = 0.2;
  EXPECT_NE(fovsim::reference_key(a), fovsim::reference_key(b));
}
