// Lighting passes in the cost model (sim/cost/passes.cpp): a scene with indirect light charges
// every method for its RSMs and the VPL shading of its samples, culling passes only for
// strategies that declare them, and a scene without indirect light has none of them.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "sim/cost/analytic.h"
#include "sim/cost/cost_model.h"
#include "sim/cost/gpu_profile.h"
#include "sim/cost/passes.h"
#include "sim/cost/workload.h"
#include "sim/foveation/factory.h"

using namespace fovsim;

namespace {
const std::string kModels = std::string(FOVSIM_SOURCE_DIR) + "/models";

CostInputs inputs(const std::string& method, const Counters* c, bool indirect) {
  CostInputs in;
  in.method = method;
  in.counters = c;
  in.features.triangles = 100000;
  in.features.lights = 3;
  in.features.shadowed_lights = 1;
  in.features.indirect = indirect;
  in.display.width = 1440;
  in.display.height = 1600;
  in.display.eyes = 2;
  return in;
}

bool has_pass(const std::vector<PassWork>& ps, const std::string& name) {
  return std::any_of(ps.begin(), ps.end(), [&](const PassWork& p) { return p.pass == name; });
}
bool has_term(const std::vector<PassWork>& ps, const std::string& term) {
  for (auto& p : ps)
    for (auto& t : p.terms)
      if (t.name == term) return true;
  return false;
}
}  // namespace

TEST(LightingCost, NoIndirectNoVplPasses) {
  Counters c;
  c.set(Counter::shaded_samples, 1440.0 * 1600 * 0.3);
  // A subset: one method of each cost family that builds no VPLs of its own (not flc).
  for (const char* m : {"full", "kfr", "twfr", "fvrs"}) {
    CostInputs in = inputs(m, &c, false);
    Workload w;
    auto ps = assemble_passes(in, w, nullptr);
    for (const char* p : {"rsm", "importance", "contribution", "light_culling"})
      EXPECT_FALSE(has_pass(ps, p)) << m << " " << p;
    EXPECT_FALSE(has_term(ps, "vpl_flops")) << m;
  }
}

TEST(LightingCost, EveryMethodPaysForTheLightingTheSceneNeeds) {
  const double P = 1440.0 * 1600;
  Counters all;  // TBDS: every pixel x every VPL
  all.set(Counter::shaded_samples, P);
  all.set(Counter::rsm_texels, 768);
  all.set(Counter::vpls_total, 768);
  all.set(Counter::vpls_kept, 768);
  all.set(Counter::shaded_sample_vpls, P * 768);
  Counters flc = all;  // culled to 128 VPLs
  flc.set(Counter::vpls_kept, 128);
  flc.set(Counter::shaded_sample_vpls, P * 128);
  flc.set(Counter::importance_samples, 256);
  flc.set(Counter::contribution_evals, 768.0 * 256);
  const GpuProfile g = GpuProfile::load("gtx1080", kModels);
  Workload w;
  auto ps_all = assemble_passes(inputs("full", &all, true), w, nullptr);
  EXPECT_TRUE(has_pass(ps_all, "rsm"));
  EXPECT_TRUE(has_term(ps_all, "vpl_flops"));
  EXPECT_FALSE(has_pass(ps_all, "light_culling"));  // all_vpls culls nothing
  // The importance and culling passes are what the flc strategy declares (declare_passes).
  CostInputs in_flc = inputs("full", &flc, true);
  in_flc.passes = declared_passes("full", "flc");
  auto ps_flc = assemble_passes(in_flc, w, nullptr);
  EXPECT_TRUE(has_pass(ps_flc, "importance"));
  EXPECT_TRUE(has_pass(ps_flc, "light_culling"));
  const double t_all = estimate_frame(g, inputs("full", &all, true)).total_ms;
  const double t_flc = estimate_frame(g, in_flc).total_ms;
  const double t_direct = estimate_frame(g, inputs("full", &all, false)).total_ms;
  EXPECT_LT(t_flc, t_all);     // FLC cheaper than TBDS (FLC paper Fig. 6)
  EXPECT_GT(t_flc, t_direct);  // but indirect light is not free
}

// FLC's contribution pass (Yang et al. 2021 §5) counts its BLSO lookups analytically: 2 N' per
// VPL-sample pair (eq. 11: two local-space estimates of N' positions, eq. 13), none without
// BLSO; the pass's FP32 work is 80 per pair plus 120 per lookup.
TEST(LightingCost, FlcContributionCountsBlsoLookups) {
  const Workload w = Workload::load("flc_sponza", kModels);
  Display d;
  d.width = d.height = 1024;
  d.eyes = 1;
  const Counters blso = analytic_counters("flc", Json::object(), w, d, "test");
  const double pairs = blso.get(Counter::contribution_evals);
  ASSERT_GT(pairs, 0.0);
  EXPECT_DOUBLE_EQ(blso.get(Counter::blso_lookups), pairs * 2 * 4);  // N' = blso_samples = 4
  const Counters n8 = analytic_counters("flc", Json{{"blso_samples", 8}}, w, d, "test");
  EXPECT_DOUBLE_EQ(n8.get(Counter::blso_lookups), pairs * 2 * 8);
  const Counters none = analytic_counters("flc", Json{{"visibility", "none"}}, w, d, "test");
  EXPECT_EQ(none.get(Counter::blso_lookups), 0.0);
  CostInputs in;
  in.method = "flc";
  in.counters = &n8;
  in.display = d;
  in.passes = declared_passes("flc");
  for (const PassWork& p : assemble_passes(in, w))
    if (p.pass == "contribution") {
      ASSERT_EQ(p.terms.size(), 1u);
      EXPECT_EQ(p.terms[0].name, "flops");
      EXPECT_DOUBLE_EQ(p.terms[0].value,
                       pairs * kEq14FlopsPerPair + pairs * 16 * kBlsoFlopsPerLookup);
    }
}
