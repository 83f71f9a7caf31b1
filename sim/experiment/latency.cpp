#include "sim/experiment/latency.h"

#include <algorithm>
#include <cmath>

#include "sim/core/rng.h"

namespace fovsim {

LatencyConfig LatencyConfig::from_params(Params& root) {
  LatencyConfig c;
  if (!root.has("latency")) return c;
  c.enabled = true;
  Params p = root.child("latency");
  const Range ms = Range::closed(0, 1000);
  c.tracker_ms = p.number("tracker_ms", 0.0, ms);
  c.render_ms = p.number("render_ms", 0.0, ms);
  c.display_ms = p.number("display_ms", 0.0, ms);
  c.jitter = p.string("jitter", "none", {"none", "normal", "uniform"});
  c.jitter_ms = p.number("jitter_ms", 0.0, Range::closed(0, 500));
  c.seed = uint64_t(p.integer("seed", 1, Range::closed(0, 2e9)));
  c.render_from_estimate = p.boolean("render_from_estimate", false);
  c.predictor = p.string("predictor", "none", {"none", "main_sequence"});
  c.predictor_min_deg = p.number("predictor_min_deg", 1.0, Range::closed(0, 90));
  Params s = p.child("saccade");
  c.saccade_deg_s = s.number("velocity_threshold_deg_s", 75.0, Range::above(0, 5000));
  c.suppression_ms = s.number("suppression_ms", 50.0, Range::closed(0, 1000));
  Params m = p.child("main_sequence");
  c.ms_vmax_deg_s = m.number("vmax_deg_s", 600.0, Range::above(0, 5000));
  c.ms_c_deg = m.number("c_deg", 10.0, Range::above(0, 1000));
  c.ms_intercept_ms = m.number("intercept_ms", 21.0, Range::closed(0, 1000));
  c.ms_slope_ms_per_deg = m.number("slope_ms_per_deg", 2.2, Range::above(0, 100));
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
