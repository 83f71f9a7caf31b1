#include "sim/experiment/jod_fidelity.h"

#include <cmath>
#include <cstdio>

#include "sim/display/display.h"
#include "sim/experiment/sweep_spec.h"
#include "sim/experiment/table.h"
#include "sim/metrics/fvvdp.h"

namespace fovsim {

const std::vector<JodBiasRung>& jod_bias_rungs() {
  // docs/fidelity.md, "JOD at the display's resolution": `fovsim fidelity` on the perception
  // base (atrium, traces/sample_walk.csv, fove_2560x1440, render.spp 1, 10 frames) with six
  // methods, rungs render.scale 0.25 and 0.5 against the top rung render.scale 1; the largest
  // |difference of a method's mean| per metric.
  static const std::vector<JodBiasRung> r = {{0.25, 1.38, 1.38}, {0.5, 0.77, 0.77}};
  return r;
}

std::string jod_metric_of(const std::string& column) {
  for (const char* m : {"fvvdp_jod_fl", "fvvdp_jod"}) {
    const std::string s = m;
    if (column == s) return s;
    for (const char* suf : {"_lo", "_hi", "_ci95"})
      if (column == s + suf) return s;
  }
  return "";
}

double jod_display_ppd(const Display& d) {
  return FvvdpDisplay::from_display(d).ppd;
}

namespace {
std::string ppd_text(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}
}  // namespace

Json jod_fidelity_record(double scale, double display_ppd) {
  const bool native = std::fabs(scale - 1.0) < 1e-9;
  Json bias = nullptr;
  if (native) {
    bias = Json{{"fvvdp_jod", 0.0}, {"fvvdp_jod_fl", 0.0}};
  } else {
    for (const JodBiasRung& r : jod_bias_rungs())
      if (std::fabs(scale - r.scale) < 1e-9)
        bias = Json{{"fvvdp_jod", r.fvvdp_jod}, {"fvvdp_jod_fl", r.fvvdp_jod_fl}};
  }
  const bool needs_native = !native && !bias.is_object();
  Json j{{"render_scale", scale},
         {"ppd_display", display_ppd},
         {"ppd_simulated", display_ppd * scale},
         {"native", native},
         {"vs_render_scale", 1.0},
         {"bias", bias},
         {"needs_native", needs_native}};
  if (!native) {
    const std::string at = "render.scale " + format_number(scale) + " (" +
                           ppd_text(display_ppd * scale) + " of the display's " +
                           ppd_text(display_ppd) + " pixels per degree)";
    j["note"] = bias.is_object()
                    ? "JOD at " + at + " is biased by up to " +
                          format_number(bias["fvvdp_jod_fl"].get<double>()) +
                          " JOD (fvvdp_jod_fl) against native resolution (docs/fidelity.md); "
                          "a JOD threshold is judged with that margin"
                    : "JOD at " + at +
                          " has no measured bias against native resolution: a JOD threshold "
                          "decided here needs native resolution (render.scale=1)";
  }
  return j;
}

double jod_bias_of(const Json& rec, const std::string& column) {
  const std::string m = jod_metric_of(column);
  if (m.empty() || !rec.is_object() || !rec.contains("bias") || !rec["bias"].is_object())
    return NAN;
  const Json& b = rec["bias"];
  return b.contains(m) && b[m].is_number() ? b[m].get<double>() : double(NAN);
}

JodJudgement judge_jod(const SearchConstraint& c, const Json& rec) {
  JodJudgement j;
  if (jod_metric_of(c.column).empty() || !rec.is_object()) return j;
  const double b = jod_bias_of(rec, c.column);
  if (std::isfinite(b)) {
    j.margin = b;
  } else {
    j.needs_native = true;
  }
  return j;
}

std::string jod_verdict_sentence(const SearchConstraint& c, const JodJudgement& j,
                                 const Json& rec) {
  if (jod_metric_of(c.column).empty() || !rec.is_object() || rec.value("native", false)) return "";
  const double s = rec.value("render_scale", double(NAN));
  const std::string at = "render.scale " + format_number(s) + " (" +
                         ppd_text(rec.value("ppd_simulated", double(NAN))) + " of " +
                         ppd_text(rec.value("ppd_display", double(NAN))) + " px/deg)";
  if (j.needs_native)
    return "JOD constraint " + c.describe() + " decided at " + at +
           ", where no bias against native resolution is measured: the answer needs native "
           "resolution (render.scale=1)";
  return "JOD constraint " + c.describe() + " judged with the measured bias of " + at + ": " +
         c.column + " counts as its value -/+ " + format_number(j.margin) +
         " JOD, so a point is feasible only if it is at native resolution too (docs/fidelity.md)";
}

}  // namespace fovsim
