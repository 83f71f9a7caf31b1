#include "sim/experiment/cell_rows.h"

#include "sim/core/counters.h"
#include "sim/cost/cost_model.h"
#include "sim/experiment/cell.h"
#include "sim/foveation/factory.h"
#include "sim/foveation/lighting.h"

namespace fovsim {

void Cell::build_rows(const FrameIn& in, size_t mi, const Step& st, const FrameContext& ctx,
                      const MetricValues& metrics) {
  const Shared& sh = in.sh;
  const FrameData& fd = in.fd;
  const TraceSample& s = sh.trace.samples[size_t(in.fi)];
  MethodRun& m = methods[mi];
  const FrameOutput& fo = m.fo;
  for (auto& gpu : cost.gpus) {
    CostInputs ci;
    ci.method = st.cost_method;
    ci.counters = &fo.counters;
    ci.passes = declared_passes(*st.impl);             // its cost passes and shared work
    ci.shared = fd.has_vpls ? &fd.counters : nullptr;  // the frame's RSMs
    ci.features = in.features;
    ci.display = sh.display;
    ci.pixel_scale = sh.pixel_scale;
    ci.workload = &cost.workload;
    FrameCost fc = estimate_frame(gpu, ci);
    if (&gpu == &cost.gpus.front()) gaze->feedback(mi, fc.total_ms);
    ResultRow row;
    row.set_text("config_id", cost.gpus.size() > 1 ? m.label + "@" + gpu.name : m.label);
    row.set_text("method", m.method);
    row.set_text("label", m.label);
    row.set_text("gpu", gpu.name);
    for (auto& [pn, pv] : m.impl->param_columns()) row.set(pn, pv);
    for (auto& [pn, pv] : m.impl->text_param_columns()) row.set_text(pn, pv);
    if (fd.has_vpls && m.impl->lighting()) {  // lighting strategy columns (results/README.md)
      row.set_text("lighting", m.impl->lighting()->name());
      for (auto& [pn, pv] : m.impl->lighting()->param_columns()) row.set(pn, pv);
    }
    row.set("frame", in.fi);
    row.set("t", s.t);
    row.set("gaze_x", fd.gaze_px.x / sh.scale);  // pixels of the real display
    row.set("gaze_y", fd.gaze_px.y / sh.scale);
    row.set("gaze_valid", fd.gaze_valid ? 1 : 0);
    if (sh.tracking_column) row.set_text("tracking", gaze->tracked().state);  // docs/tracking.md
    latency.add_columns(row, *gaze, st.lat_ms, fd, ctx, sh.scale);            // results/README.md
    double shaded = fo.counters.get(Counter::shaded_samples);
    row.set("shaded_samples", shaded * display_scale(Counter::shaded_samples, sh.pixel_scale));
    row.set("shaded_fraction", shaded / double(sh.sim_display.width * sh.sim_display.height));
    row.set("prims_submitted",
            fo.counters.get(Counter::prims_submitted, double(in.features.triangles)));
    row.set("prims_culled", fo.counters.get(Counter::prims_culled, 0.0));
    for (auto& [cn, cv] : fo.counters.items())
      if (const auto k = find_counter(cn); !k || !reported_by_row_builder(k->id)) row.set(cn, cv);
    for (auto& [cn, cv] : shared_counters(ci).items()) row.set(cn, cv);  // the frame's RSMs
    // A counter the cost model needed and the method did not fill (its pass was charged 0 or
    // a fallback) is a flag of the row, never silence (results/README.md).
    if (!fc.missing_counters.empty()) {
      std::string mc;
      for (const auto& n : fc.missing_counters) mc += (mc.empty() ? "" : ";") + n;
      row.set_text("missing_counters", mc);
      flags_seen.insert(m.label + ":missing_counters");
    }
    row.set("est_ms_total", fc.total_ms);
    if (fc.interval_level > 0) {  // the profile's prediction interval (docs/cost_model.md)
      row.set("est_ms_total_lo", fc.total_lo_ms);
      row.set("est_ms_total_hi", fc.total_hi_ms);
    }
    for (auto& pc : fc.passes) {
      row.set("est_ms_" + pc.pass, pc.ms);
      if (fc.interval_level > 0) {  // per-pass interval (docs/cost_model.md)
        row.set("est_ms_" + pc.pass + "_lo", pc.lo_ms);
        row.set("est_ms_" + pc.pass + "_hi", pc.hi_ms);
      }
    }
    for (auto& [mn, mv] : metrics.items()) row.set(mn, mv);
    row.set("ref_ms", in.ref_ms);
    row.set("sim_ms", st.sim_ms);
    if (in.record) frames.add(std::move(row));
  }
}

}  // namespace fovsim
