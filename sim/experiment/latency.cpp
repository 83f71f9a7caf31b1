#include "sim/experiment/latency.h"

#include <algorithm>
#include <cmath>

#include "sim/core/param_table.h"
#include "sim/core/rng.h"

namespace fovsim {

const ParamTable<LatencyConfig>& latency_table() {
  using C = LatencyConfig;
  const Range ms = Range::closed(0, 1000);
  static const auto t =
      ParamTable<C>()
          .number("tracker_ms", 0.0, ms, &C::tracker_ms)
          .doc("", "eye-tracker latency (sample to application)")
          .number("render_ms", 0.0, ms, &C::render_ms)
          .doc("",
               "render pipeline part (ignored when `render_from_estimate` has a previous "
               "frame)")
          .number("display_ms", 0.0, ms, &C::display_ms)
          .doc("", "display part (scan-out, panel response)")
          .text("jitter", "none", {"none", "normal", "uniform"}, &C::jitter)
          .doc("", "per-frame jitter added to L")
          .number("jitter_ms", 0.0, Range::closed(0, 500), &C::jitter_ms)
          .doc("", "`normal`: standard deviation; `uniform`: width of [0, jitter_ms)")
          .integer("seed", 1, Range::closed(0, 2e9), &C::seed)
          .doc("",
               "jitter seed (one stream per frame: same numbers at any thread count or frame "
               "order)")
          .boolean("render_from_estimate", false, &C::render_from_estimate)
          .doc("",
               "render part = the method's previous-frame `est_ms_total` (first GPU profile) "
               "rounded up to whole refresh periods: a frame that misses the budget is "
               "displayed a period later")
          .text("predictor", "none", {"none", "main_sequence"}, &C::predictor)
          .doc("", "landing-position predictor for saccades in flight at t - L")
          .number("predictor_min_deg", 1.0, Range::closed(0, 90), &C::predictor_min_deg)
          .doc("", "angle a saccade must have travelled before the predictor acts")
          .documented("saccade", "object", "", "", "", "saccade detector: `latency.saccade` below")
          .documented("main_sequence", "object", "", "", "",
                      "main-sequence model: `latency.main_sequence` below");
  return t;
}

const ParamTable<LatencyConfig>& latency_saccade_table() {
  using C = LatencyConfig;
  static const auto t =
      ParamTable<C>()
          .number("velocity_threshold_deg_s", 75.0, Range::above(0, 5000), &C::saccade_deg_s)
          .doc("",
               "eye-in-head speed above which a frame is `saccade` (detector on the true "
               "gaze)")
          .number("suppression_ms", 50.0, Range::closed(0, 1000), &C::suppression_ms)
          .doc("", "window after the last saccade sample labelled `suppression`");
  return t;
}

const ParamTable<LatencyConfig>& latency_main_sequence_table() {
  using C = LatencyConfig;
  static const auto t =
      ParamTable<C>()
          .number("vmax_deg_s", 600.0, Range::above(0, 5000), &C::ms_vmax_deg_s)
          .doc("Baloh et al. 1975", "V_peak = vmax (1 - e^(-A/c)), deg/s")
          .number("c_deg", 10.0, Range::above(0, 1000), &C::ms_c_deg)
          .doc("Baloh et al. 1975", "c of V_peak, deg")
          .number("intercept_ms", 21.0, Range::closed(0, 1000), &C::ms_intercept_ms)
          .doc("Carpenter 1988", "duration = intercept + slope A")
          .number("slope_ms_per_deg", 2.2, Range::above(0, 100), &C::ms_slope_ms_per_deg)
          .doc("Carpenter 1988", "slope of the duration");
  return t;
}

LatencyConfig LatencyConfig::from_params(Params& root) {
  LatencyConfig c;
  if (!root.has("latency")) return c;
  c.enabled = true;
  Params p = root.child("latency");
  latency_table().read_into(p, c);
  Params s = p.child("saccade");
  latency_saccade_table().read_into(s, c);
  Params m = p.child("main_sequence");
  latency_main_sequence_table().read_into(m, c);
  return c;
}

double LatencyConfig::total_ms(int frame, double render_part_ms) const {
  double l = tracker_ms + render_part_ms + display_ms;
  if (jitter != "none" && jitter_ms > 0) {
    Rng rng(seed, uint64_t(frame) + 1);  // one stream per frame
    l += jitter == "normal" ? jitter_ms * rng.normal() : jitter_ms * rng.uniform();
  }
  return std::max(0.0, l);  // a frame never shows gaze from the future
}

const char* phase_name(GazePhase p) {
  switch (p) {
    case GazePhase::Saccade:
      return "saccade";
    case GazePhase::Suppression:
      return "suppression";
    default:
      return "fixation";
  }
}

GazePhase gaze_phase(const Trace& truth, double t, double period, const LatencyConfig& c) {
  const double h = 0.5 * period;
  if (gaze_speed_deg_s(truth, t, h) > c.saccade_deg_s) return GazePhase::Saccade;
  const int n = int(std::floor(c.suppression_ms));
  for (int k = 1; k <= n; ++k)
    if (gaze_speed_deg_s(truth, t - 1e-3 * k, h) > c.saccade_deg_s) return GazePhase::Suppression;
  return GazePhase::Fixation;
}

namespace {

// Backward-difference speed: only samples the system already has at time t.
double speed_back(const Trace& tr, double t, double period) {
  TraceSample a = sample_at(tr, t - period), b = sample_at(tr, t);
  double dt = b.t - a.t;
  return dt > 0 ? angle_deg(glm::normalize(a.gaze_dir), glm::normalize(b.gaze_dir)) / dt : 0;
}

// Rotates unit `from` towards unit `toward` by `deg` degrees (great circle).
glm::dvec3 rotate_towards(const glm::dvec3& from, const glm::dvec3& toward, double deg) {
  glm::dvec3 axis = glm::cross(from, toward);
  double n = glm::length(axis);
  if (n < 1e-12) return from;
  axis /= n;
  double a = deg * 3.14159265358979323846 / 180.0;
  // Rodrigues' rotation (from is perpendicular to axis).
  return glm::normalize(from * std::cos(a) + glm::cross(axis, from) * std::sin(a));
}

}  // namespace

TraceSample estimated_gaze(const Trace& truth, double t, double latency_s, double period,
                           const LatencyConfig& c) {
  const double te = t - latency_s;
  TraceSample s = sample_at(truth, te);
  if (c.predictor != "main_sequence") return s;
  double v = speed_back(truth, te, period);
  if (!(v > c.saccade_deg_s)) return s;
  // Onset: walk back in half periods while the speed stays above threshold (at most 200 ms,
  // longer than any saccade of the main sequence up to 80 deg).
  const double step = 0.5 * period;
  double onset = te, vpeak = v, tpeak = te;
  for (int k = 1; k * step <= 0.2; ++k) {
    double tk = te - k * step;
    double vk = speed_back(truth, tk, period);
    if (!(vk > c.saccade_deg_s)) break;
    onset = tk;
    if (vk > vpeak) {
      vpeak = vk;
      tpeak = tk;
    }
  }
  onset -= period;  // the backward difference lags the true onset by up to one period
  glm::dvec3 g0 = glm::normalize(sample_at(truth, onset).gaze_dir), g1 = glm::normalize(s.gaze_dir);
  double travelled = angle_deg(g0, g1);
  if (travelled < c.predictor_min_deg) return s;
  // Amplitude (Bahill, Clark & Stark, "The main sequence, a tool for studying human eye
  // movements"): inverse of Vpeak = vmax (1 - exp(-A/c)); at least the angle travelled, and at
  // least what the elapsed duration implies (D = intercept + slope * A).
  double r = std::min(vpeak / c.ms_vmax_deg_s, 0.95);
  double a_v = -c.ms_c_deg * std::log(1.0 - r);
  double a_d = ((te - onset) * 1e3 - c.ms_intercept_ms) / c.ms_slope_ms_per_deg;
  double amp = std::max({a_v, a_d, travelled});
  // Past the peak (speed fallen below 90% of it), the near-symmetric velocity profile puts the
  // peak at half the amplitude; the backward difference lags the peak by half a period.
  if (v < 0.9 * vpeak && tpeak - 0.5 * period > onset) {
    double half = angle_deg(g0, glm::normalize(sample_at(truth, tpeak - 0.5 * period).gaze_dir));
    amp = std::max(2.0 * half, travelled);
  }
  s.gaze_dir = rotate_towards(g0, g1, amp);
  return s;
}

ResultTable summarize_phases(const ResultTable& frames, const ResultTable& summary,
                             const std::set<std::string>& metrics) {
  std::vector<std::string> names(metrics.begin(), metrics.end());
  names.push_back("gaze_error_deg");
  ResultTable out;
  for (const ResultRow& srow : summary.rows()) {
    ResultRow r;
    for (auto& kv : srow.text)
      if (kv.first != "phase") r.set_text(kv.first, kv.second);
    r.num = srow.num;
    const std::string* id = srow.text_of("config_id");
    for (const char* ph : {"saccade", "suppression", "fixation"}) {
      std::vector<const ResultRow*> rows;
      for (auto& fr : frames.rows()) {
        const std::string *fid = fr.text_of("config_id"), *fp = fr.text_of("phase");
        if (id && fid && *fid == *id && fp && *fp == ph) rows.push_back(&fr);
      }
      r.set(std::string("frames_") + ph, double(rows.size()));
      for (auto& n : names) {
        double sum = 0;
        size_t k = 0;
        for (auto* fr : rows) {
          double v = fr->get(n, NAN);
          if (std::isfinite(v)) {
            sum += v;
            ++k;
          }
        }
        r.set(n + "_" + ph, k ? sum / double(k) : NAN);
      }
    }
    out.add(std::move(r));
  }
  return out;
}

}  // namespace fovsim
