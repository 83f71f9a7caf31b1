// Cost inputs that overflow: every workload and profile number has a bounded range (from the
// tables that parse and document them), every input in range costs a finite frame, a value
// that is not finite on the way is an error naming the pass, and a profile that has no
// coefficients for a pass a method declares is an error naming the file, method and pass.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "sim/core/error.h"
#include "sim/core/param_table.h"
#include "sim/cost/cost_model.h"
#include "sim/cost/gpu_profile.h"
#include "sim/cost/passes.h"
#include "sim/cost/workload.h"

using namespace fovsim;

namespace {
const std::string kModels = std::string(FOVSIM_SOURCE_DIR) + "/models";

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

template <class T>
void expect_bounded_numbers(const ParamTable<T>& table, const std::string& name) {
  for (const auto& r : table.rows()) {
    if (r.doc_only || (r.kind != ParamKind::Number && r.kind != ParamKind::Integer)) continue;
    EXPECT_LT(r.range.hi, 1e300) << name << "." << r.key << ": no upper bound " << r.range.str();
    EXPECT_GT(r.range.lo, -1e300) << name << "." << r.key << ": no lower bound";
  }
}

Workload workload_at(bool high) {
  // Every number of the workload at one end of its declared range.
  Json j = Json::object();
  for (const auto& r : workload_table().rows())
    if (!r.doc_only && r.kind == ParamKind::Number) j[r.key] = high ? r.range.hi : r.range.lo;
  j["pipeline"] = {{"depth_prepass", true}, {"skybox", true},  {"ssao", true}, {"tonemap", true},
                   {"taa", true},           {"post_aa", true}, {"frame", true}};
  Params p(j, "extreme.json");
  Workload w = Workload::from_params(p);
  p.finish();
  return w;
}
}  // namespace

TEST(CostInputs, EveryWorkloadAndProfileNumberHasABoundedRange) {
  expect_bounded_numbers(workload_table(), "workload");
  expect_bounded_numbers(gpu_spec_table(), "spec");
  for (const Range& r : {kProfileRanges.overhead_ms, kProfileRanges.coefficient,
                         kProfileRanges.lo_factor, kProfileRanges.hi_factor, kProfileRanges.score,
                         kProfileRanges.residual_ms, kProfileRanges.rel_err})
    EXPECT_LT(r.hi, 1e300) << r.str();
  for (const ProfileKey& k : gpu_profile_keys()) {  // every number of the declared profile keys
    if (k.type == ProfileKeyType::Number || k.type == ProfileKeyType::Numbers) {
      EXPECT_LT(k.range.hi, 1e300) << k.path << " " << k.range.str();
    }
  }
  // The documented range is the checked one (configs/README.md "Workload" is generated).
  for (const ParamInfo& i : workload_table().info())
    if (std::string(i.name) == "lights") {
      EXPECT_STREQ(i.range, "[-1, 1e6]");
    }
}

TEST(CostInputs, OverflowingWorkloadValuesAreRefusedWhereTheyAreRead) {
  Json j = {{"lights", 1e300}};
  Params p(j, "w.json");
  EXPECT_EQ(error_of([&] { Workload::from_params(p); }),
            "w.json: lights: value 1e+300 is out of range [-1, 1e+06]");
  Json k = {{"shadow_map_res", 1e155}};
  Params q(k, "w.json");
  EXPECT_EQ(error_of([&] { Workload::from_params(q); }),
            "w.json: shadow_map_res: value 1e+155 is out of range [0, 65536]");
  Json m = {{"triangles", -0.5}};
  Params r(m, "w.json");
  EXPECT_NE(error_of([&] { Workload::from_params(r); }).find("-1 (from the scene)"),
            std::string::npos);
  Json prof = Params::parse_json_file(kModels + "/gpus/gtx1080.json");
  prof["passes"]["lighting"]["terms"]["shade_flops"] = 1e300;
  EXPECT_NE(error_of([&] {
              GpuProfile::from_json(prof, "g.json");
            }).find("g.json: passes.lighting.terms.shade_flops: value 1e+300 is out of range"),
            std::string::npos);
}

TEST(CostInputs, EveryInputInRangeCostsAFiniteFrame) {
  // The largest workload, display and counters the ranges allow stay finite on every profile
  // and method: a new key without a bound, or a new product that overflows, fails here.
  for (bool high : {true, false}) {
    const Workload w = workload_at(high);
    Counters c;
    for (int i = 0; i < kCounterCount; ++i) {
      const Counter id = Counter(i);
      if (counter_indexed(id))
        for (int level = 0; level < 8; ++level) c.set(id, level, high ? 1e13 : 0);
      else
        c.set(id, high ? 1e13 : 0);
    }
    for (const std::string& gpu : GpuProfile::available(kModels)) {
      const GpuProfile g = GpuProfile::load(gpu, kModels);
      for (const std::string& m : cost_methods()) {
        CostInputs in;
        in.method = m;
        in.counters = &c;
        in.features.indirect = true;
        in.display.width = in.display.height = high ? 1 << 20 : 1;
        in.display.eyes = 2;
        in.workload = &w;
        FrameCost fc;
        EXPECT_EQ(error_of([&] { fc = estimate_frame(g, in); }), "") << gpu << " " << m;
        EXPECT_TRUE(std::isfinite(fc.total_ms) && std::isfinite(fc.total_hi_ms)) << gpu << m;
      }
    }
  }
}

TEST(CostInputs, ANonFiniteIntermediateIsAnErrorNamingThePass) {
  // Bypassing the table's ranges (a Workload built in code): the infinities are an error, not
  // dropped (lights 1e300 and shadow_map_res 1e155 used to make the frame cheaper).
  const GpuProfile g = GpuProfile::load("gtx1080", kModels);
  Counters c;
  c.set(Counter::shaded_samples, 1e6);
  CostInputs in;
  in.method = "full";
  in.counters = &c;
  in.display.width = 1440, in.display.height = 1600, in.display.eyes = 2;
  Workload w;
  w.lights = 1e300;
  in.workload = &w;
  EXPECT_NE(error_of([&] {
              estimate_frame(g, in);
            }).find("cost of method 'full': pass lighting, term shade_flops is inf"),
            std::string::npos);
  Workload s;
  s.shadowed_lights = 1, s.shadow_map_res = 1e155;
  in.workload = &s;
  EXPECT_NE(error_of([&] { estimate_frame(g, in); }).find("pass shadow, term shadow_texels is inf"),
            std::string::npos);
  GpuProfile big = g;  // a coefficient x term product that overflows
  big.passes["lighting"].terms["shade_flops"] = 1e300;
  Workload l;
  l.lights = 1e6, l.shading_flops = 1e9;
  in.workload = &l;
  const std::string e = error_of([&] { estimate_frame(big, in); });
  EXPECT_NE(e.find("method 'full', pass 'lighting': a term's time is inf"), std::string::npos) << e;
  EXPECT_EQ(e.find(big.file + ": "), 0u) << e;
}

TEST(CostInputs, AProfileWithoutADeclaredPassIsAnErrorNamingFileMethodAndPass) {
  Json j = Params::parse_json_file(kModels + "/gpus/gtx1080.json");
  j["passes"] = Json::object();
  const GpuProfile empty = GpuProfile::from_json(j, "empty.json");
  Counters c;
  for (const std::string& m : cost_methods()) {
    CostInputs in;
    in.method = m;
    in.counters = &c;
    in.display.width = 1440, in.display.height = 1600;
    const std::string e = error_of([&] { estimate_frame(empty, in); });
    EXPECT_EQ(e.find("empty.json: GPU profile 'gtx1080' has no coefficients for pass '"), 0u)
        << m << ": " << e;
    EXPECT_NE(e.find("which method '" + m + "' declares"), std::string::npos) << e;
  }
  // One pass missing: named, whichever method declares it.
  Json k = Params::parse_json_file(kModels + "/gpus/gtx1080.json");
  k["passes"].erase("pass2");
  const GpuProfile no_pass2 = GpuProfile::from_json(k, "no_pass2.json");
  CostInputs in;
  in.method = "kfr";
  in.counters = &c;
  in.display.width = 1440, in.display.height = 1600;
  EXPECT_NE(error_of([&] { estimate_frame(no_pass2, in); })
                .find("no_pass2.json: GPU profile 'gtx1080' has no coefficients for pass 'pass2', "
                      "which method 'kfr' declares"),
            std::string::npos);
  in.method = "full";  // full has no pass 2: costs as before
  EXPECT_EQ(error_of([&] { estimate_frame(no_pass2, in); }), "");
}
