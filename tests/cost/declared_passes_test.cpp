// Declared counters and passes (docs/architecture.md "Cost model"): every counter a method or
// strategy fills is in the one list (sim/core/counter_list.h) and reads back by its column name;
// the passes the cost model charges are the ones the method and its lighting strategy declare
// (CostPasses), never inferred from which counters are present; a declared pass whose counter
// was not filled is named in missing_counters; the frame's shared RSMs are charged from the
// declaration.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "sim/core/counter_list.h"
#include "sim/core/error.h"
#include "sim/cost/analytic.h"
#include "sim/cost/cost_model.h"
#include "sim/cost/passes.h"
#include "sim/cost/workload.h"
#include "sim/foveation/factory.h"
#include "sim/foveation/frame.h"

using namespace fovsim;

namespace {

bool has(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

const PassWork* pass_of(const std::vector<PassWork>& ps, const std::string& name) {
  for (auto& p : ps)
    if (p.pass == name) return &p;
  return nullptr;
}

double term_of(const PassWork* p, const std::string& term) {
  if (!p) return NAN;
  for (auto& t : p->terms)
    if (t.name == term) return t.value;
  return NAN;
}

Display small_display(int size = 32) {
  Display d;
  d.width = d.height = size;
  d.fov_h_deg = d.fov_v_deg = 60;
  return d;
}

// Every counter of `c` is declared: its column name reads back to the same key, it has a doc
// line, and an indexed family is only ever written with an index.
void expect_declared(const Counters& c, const std::string& who) {
  for (const auto& e : c.entries()) {
    const std::string name = e.key.name();
    auto k = find_counter(name);
    ASSERT_TRUE(k.has_value()) << who << ": " << name;
    EXPECT_TRUE(*k == e.key) << who << ": " << name;
    EXPECT_GT(std::string(counter_info(e.key.id).doc).size(), 0u) << who << ": " << name;
    EXPECT_EQ(counter_indexed(e.key.id), e.key.index >= 0) << who << ": " << name;
  }
}

}  // namespace

TEST(CounterList, NamesReadBackToTheirIds) {
  for (int i = 0; i < kCounterCount; ++i) {
    const Counter id = Counter(i);
    if (counter_indexed(id)) continue;
    auto k = find_counter(counter_name(id));
    ASSERT_TRUE(k.has_value()) << counter_name(id);
    EXPECT_TRUE(*k == CounterKey{id}) << counter_name(id);
  }
  auto mip = find_counter("holes_mip7");
  ASSERT_TRUE(mip.has_value());
  EXPECT_TRUE(*mip == (CounterKey{Counter::holes_mip, 7}));
  EXPECT_EQ(mip->name(), "holes_mip7");
  for (const char* bad : {"shaded_sampels", "holes_mip", "holes_mipx", "psnr", "est_ms_total", ""})
    EXPECT_FALSE(find_counter(bad).has_value()) << bad;
  Counters c;
  EXPECT_FALSE(c.set_named("shaded_sampels", 1));
  EXPECT_TRUE(c.items().empty());
  EXPECT_TRUE(c.set_named("holes_mip2", 5));
  EXPECT_EQ(c.get(CounterKey{Counter::holes_mip, 2}), 5);
}

TEST(CounterList, ScalesAsDeclared) {
  EXPECT_EQ(display_scale(Counter::shaded_samples, 4.0), 4.0);
  EXPECT_EQ(display_scale(Counter::holes_mip, 4.0), 4.0);
  EXPECT_EQ(display_scale(Counter::prims_submitted, 4.0), 1.0);
  EXPECT_EQ(display_scale(Counter::rsm_texels, 4.0), 1.0);
  EXPECT_EQ(display_scale(Counter::importance_samples, 4.0), 1.0);
}

// Every counter every method and lighting strategy fills, rendered (two frames, so temporal
// methods run their second-frame path) and analytic, is in the list.
TEST(CounterList, EveryCounterAMethodFillsIsDeclared) {
  Params sp(Json{{"type", "cornell"}, {"vpl", {{"rsm_size", 6}}}});
  Scene scene = make_scene(sp, "");
  Renderer renderer(scene, RenderSettings{});
  const Display display = small_display();
  TraceSample s;
  s.head_pos = glm::dvec3(0, 1, 2.2);
  s.gaze_dir = glm::normalize(glm::dvec3(-0.3, 0.0, -1.0));
  renderer.set_time(0);
  FrameData fd;
  prepare_frame(renderer, display, s, 0, kShadingChannels, nullptr, fd);
  expect_declared(fd.counters, "frame");
  for (const auto& e : method_table()) {
    for (const char* lighting : {"all_vpls", "flc", "fir"}) {
      Json pj = Json::object();
      if (std::string(e.name) != "flc") pj["lighting"] = Json{{"method", lighting}};
      Params p(pj, "cfg.json", "methods[0]");
      auto m = make_method(e.name, p);
      for (int frame = 0; frame < 2; ++frame) {
        FrameContext ctx = fd.context(scene, renderer, display, false);
        ctx.frame = frame;
        FrameOutput out;
        render_with_lighting(*m, ctx, out);
        expect_declared(out.counters, std::string(e.name) + "+" + lighting);
      }
      if (std::string(e.name) == "flc") break;
    }
    Workload w;
    for (bool indirect : {false, true})
      expect_declared(analytic_counters(e.name, Json::object(), w, display, "params", indirect),
                      std::string(e.name) + " analytic");
  }
}

TEST(DeclaredPasses, MethodsAndStrategiesDeclareTheirPasses) {
  const CostPasses all = declared_passes("kfr");
  EXPECT_TRUE(all.inverse_map);
  EXPECT_FALSE(all.full_resolution || all.reprojection || all.forward_shading);
  EXPECT_TRUE(all.frame_rsm);
  EXPECT_FALSE(all.importance || all.culling || all.own_vpls);
  const CostPasses flc = declared_passes("kfr", "flc");
  EXPECT_TRUE(flc.frame_rsm && flc.importance && flc.culling);
  const CostPasses fir = declared_passes("full", "fir");
  EXPECT_TRUE(fir.full_resolution);
  EXPECT_FALSE(fir.inverse_map);
  EXPECT_TRUE(fir.frame_rsm && fir.culling);
  EXPECT_FALSE(fir.importance);
  // The flc method brings its own strategy (a lighting name is ignored) and builds VPLs anywhere.
  for (const char* l : {"", "flc", "all_vpls"}) {
    const CostPasses m = declared_passes("flc", l);
    EXPECT_TRUE(m.direct_at_every_pixel);
    EXPECT_TRUE(m.own_vpls && m.importance && m.culling && m.frame_rsm) << l;
  }
  EXPECT_TRUE(declared_passes("rmfr_auto").inverse_map);
  const CostPasses twfr = declared_passes("twfr");
  EXPECT_TRUE(twfr.reprojection && twfr.redraws_marked_pixels && twfr.culls_primitives);
  EXPECT_TRUE(declared_passes("fvrs").forward_shading);
  EXPECT_FALSE(declared_passes("fvrs").inverse_map);
  EXPECT_THROW(declared_passes("kfr_typo"), Error);
}

// The pipeline follows the declaration: a counter without a declared pass adds no pass, a
// declared pass without its counter is charged 0 and named in missing_counters.
TEST(DeclaredPasses, PassesComeFromTheDeclarationNotTheCounters) {
  Workload w;
  CostInputs in;
  in.method = "kfr";
  in.features.indirect = true;
  in.display = small_display(100);
  Counters c;
  c.set(Counter::shaded_samples, 2500);
  c.set(Counter::fullres_pixels, 10000);
  c.set(Counter::filter_taps, 40000);
  c.set(Counter::rsm_texels, 64);
  c.set(Counter::vpls_total, 64);
  c.set(Counter::shaded_sample_vpls, 2500 * 64.0);
  c.set(Counter::importance_samples, 256);  // present, but all_vpls declares no importance pass
  in.counters = &c;
  in.passes = declared_passes("kfr", "all_vpls");
  std::vector<std::string> missing;
  auto ps = assemble_passes(in, w, &missing);
  EXPECT_EQ(pass_of(ps, "importance"), nullptr);
  EXPECT_EQ(pass_of(ps, "light_culling"), nullptr);
  EXPECT_NE(pass_of(ps, "rsm"), nullptr);
  EXPECT_NE(pass_of(ps, "pass2"), nullptr);
  EXPECT_TRUE(missing.empty());

  // A strategy that declares importance + culling, and a method that did not fill them.
  Counters c2;
  c2.set(Counter::shaded_samples, 2500);
  c2.set(Counter::fullres_pixels, 10000);
  c2.set(Counter::filter_taps, 40000);
  c2.set(Counter::rsm_texels, 64);
  c2.set(Counter::shaded_sample_vpls, 2500 * 64.0);
  in.counters = &c2;
  in.passes = declared_passes("kfr", "flc");
  missing.clear();
  ps = assemble_passes(in, w, &missing);
  ASSERT_NE(pass_of(ps, "importance"), nullptr);
  ASSERT_NE(pass_of(ps, "contribution"), nullptr);
  EXPECT_EQ(term_of(pass_of(ps, "importance"), "samples"), 0.0);
  EXPECT_TRUE(has(missing, "importance_samples"));
  EXPECT_TRUE(has(missing, "vpls_total"));
  EXPECT_TRUE(has(missing, "contribution_evals"));
}

// The frame's RSMs are shared work: a method that declares them is charged the frame's texels
// and its row shows them; one that does not declare them has no rsm pass.
TEST(DeclaredPasses, SharedRsmChargedFromTheDeclaration) {
  Workload w;
  CostInputs in;
  in.method = "full";
  in.features.indirect = true;
  in.display = small_display(100);
  Counters own, frame;
  own.set(Counter::shaded_samples, 10000);
  own.set(Counter::shaded_sample_vpls, 10000 * 50.0);
  frame.set(Counter::rsm_texels, 1234);
  in.counters = &own;
  in.shared = &frame;
  in.passes = declared_passes("full");
  std::vector<std::string> missing;
  auto ps = assemble_passes(in, w, &missing);
  EXPECT_EQ(term_of(pass_of(ps, "rsm"), "texels"), 1234.0);
  EXPECT_FALSE(has(missing, "rsm_texels"));
  const Counters shown = shared_counters(in);
  ASSERT_EQ(shown.items().size(), 1u);
  EXPECT_EQ(shown.get(Counter::rsm_texels), 1234.0);

  // Without the shared work and without its own count: the rsm pass is charged its fallback
  // and named missing.
  in.shared = nullptr;
  missing.clear();
  ps = assemble_passes(in, w, &missing);
  EXPECT_NE(pass_of(ps, "rsm"), nullptr);
  EXPECT_TRUE(has(missing, "rsm_texels"));

  // A pipeline that declares no RSM use has no rsm pass and shows no shared counter.
  CostPasses none = declared_passes("full");
  none.frame_rsm = false;
  in.passes = none;
  in.shared = &frame;
  ps = assemble_passes(in, w);
  EXPECT_EQ(pass_of(ps, "rsm"), nullptr);
  EXPECT_TRUE(shared_counters(in).items().empty());
}
