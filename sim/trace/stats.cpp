#include "sim/trace/stats.h"

#include <algorithm>
#include <cstdio>
#include <vector>

namespace fovsim {

// Reorders v (nth_element): callers only take percentiles and extremes of it afterwards.
static double pct(std::vector<double>& v, double p) {
  if (v.empty()) return 0;
  size_t k = size_t(std::clamp(p / 100.0, 0.0, 1.0) * double(v.size() - 1) + 0.5);
  std::nth_element(v.begin(), v.begin() + long(k), v.end());
  return v[k];
}

namespace {

// A head rotation between consecutive samples; larger first, ties by sample order.
struct Jump {
  double speed, deg, dt;
  size_t i;
};
bool jump_before(const Jump& a, const Jump& b) {
  return a.speed > b.speed || (a.speed == b.speed && a.i < b.i);
}

}  // namespace

TraceStats trace_stats(const Trace& tr) {
  TraceStats s;
  const auto& x = tr.samples;
  s.samples = x.size();
  if (x.empty()) return s;
  s.duration_s = tr.duration();
  std::vector<double> dts, ecc, speed, hspeed;
  for (auto* v : {&dts, &ecc, &speed, &hspeed}) v->reserve(x.size());
  // The 5 largest head rotations so far (jump_before): kept as they come rather than one entry
  // per sample (a long trace's stats cost its samples, not more).
  std::vector<Jump> jumps;
  s.constant_head = x.size() > 1;
  for (size_t i = 1; i < x.size() && s.constant_head; ++i)
    s.constant_head = x[i].head_pos == x[0].head_pos && x[i].head_rot == x[0].head_rot;
  long invalid = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    if (!x[i].valid) ++invalid;
    if (x[i].valid) ecc.push_back(rad2deg(angle_between(x[i].gaze_dir, glm::dvec3(0, 0, -1))));
    if (i == 0) continue;
    double dt = x[i].t - x[i - 1].t;
    dts.push_back(dt);
    if (dt <= 0) continue;
    if (x[i].valid && x[i - 1].valid)
      speed.push_back(rad2deg(angle_between(x[i].gaze_dir, x[i - 1].gaze_dir)) / dt);
    if (!s.constant_head && x[i].head_pos == x[i - 1].head_pos &&
        x[i].head_rot == x[i - 1].head_rot)
      ++s.repeated_poses;
    glm::dquat d = glm::conjugate(x[i - 1].head_rot) * x[i].head_rot;
    double ang = 2 * std::atan2(std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z), std::fabs(d.w));
    hspeed.push_back(rad2deg(ang) / dt);
    const Jump j{hspeed.back(), rad2deg(ang), dt, i};
    if (jumps.size() < 5 || jump_before(j, jumps.back())) {
      jumps.insert(std::upper_bound(jumps.begin(), jumps.end(), j, jump_before), j);
      if (jumps.size() > 5) jumps.pop_back();
    }
    s.head_path_m += glm::length(x[i].head_pos - x[i - 1].head_pos);
  }
  s.invalid_fraction = double(invalid) / double(x.size());
  if (!dts.empty()) {
    double med = pct(dts, 50);
    s.rate_hz = med > 0 ? 1.0 / med : 0;
    s.rate_mean_hz = s.duration_s > 0 ? double(x.size() - 1) / s.duration_s : 0;
    for (double dt : dts) {
      if (dt > 1.5 * med) ++s.gaps;
      if (dt < 0.25 * med) ++s.bursts;
      s.max_gap_s = std::max(s.max_gap_s, dt);
    }
  }
  s.ecc_p50 = pct(ecc, 50);
  s.ecc_p95 = pct(ecc, 95);
  s.ecc_max = ecc.empty() ? 0 : *std::max_element(ecc.begin(), ecc.end());
  s.speed_p50 = pct(speed, 50);
  s.speed_p95 = pct(speed, 95);
  s.speed_p99 = pct(speed, 99);
  s.head_speed_p50 = pct(hspeed, 50);
  s.head_speed_p99 = pct(hspeed, 99);
  s.head_speed_max = hspeed.empty() ? 0 : *std::max_element(hspeed.begin(), hspeed.end());
  {
    const size_t n = jumps.size();  // sorted, at most 5
    for (size_t k = 0; k < n && jumps[k].speed > 0; ++k) {
      const Jump& j = jumps[k];
      char jb[200];
      std::string where = j.i < tr.lines.size() ? "line " + std::to_string(tr.lines[j.i])
                                                : "sample " + std::to_string(j.i);
      std::snprintf(jb, sizeof jb, " (t=%.6g s): %.2f deg in %.2f ms (%.0f deg/s)", x[j.i].t, j.deg,
                    j.dt * 1e3, j.speed);
      s.head_jumps.push_back(where + jb);
    }
  }
  // Plausibility (one check, one row each): a value above its human-range limit is one
  // warning line, "<what> V <unit> is above L <unit> (<why>): <hint>".
  struct Check {
    double value, limit;
    const char* what;
    int precision;  // digits after the point of the value
    const char* unit;
    std::string why_hint;
  };
  const Check checks[] = {
      {s.speed_p99, kPlausibleSpeedP99, "eye-speed p99", 0, "deg/s",
       "saccades rarely exceed ~700 deg/s): check the time unit, bursts of samples, and the gaze "
       "coordinates"},
      {s.ecc_p95, kPlausibleEccP95, "gaze eccentricity p95", 1, "deg",
       "gaze rarely goes beyond ~35 deg in a headset): check the gaze space (head/world), "
       "coordinates and head orientation"},
      {s.head_speed_p50, kPlausibleHeadSpeedP50, "head-speed median", 0, "deg/s",
       "a head at rest or turning moves well below that most of the time): check the "
       "orientation unit (a map's \"unit\": \"rad\" on degrees multiplies by 57.3) and the "
       "time unit"},
      {s.head_speed_max, kPlausibleHeadSpeed, "head speed max", 0, "deg/s",
       "head turns rarely exceed ~800 deg/s): check the pose time in bursts (time.burst_pose), "
       "the orientation order and unit; largest at " +
           (s.head_jumps.empty() ? std::string("?") : s.head_jumps.front())},
  };
  for (const Check& c : checks) {
    if (!(c.value > c.limit)) continue;
    char b[160];
    std::snprintf(b, sizeof b, "%s %.*f %s is above %.0f %s (", c.what, c.precision, c.value,
                  c.unit, c.limit, c.unit);
    s.warnings.push_back(b + c.why_hint);
  }
  if (s.invalid_fraction > kWarnInvalidFraction) {
    char b[200];
    std::snprintf(b, sizeof b,
                  "%.1f %% of samples are flagged invalid (more than %.0f %%): check the "
                  "validity conditions",
                  100.0 * s.invalid_fraction, 100.0 * kWarnInvalidFraction);
    s.warnings.push_back(b);
  }
  if (s.bursts > 0)
    s.warnings.push_back(std::to_string(s.bursts) +
                         " intervals shorter than a quarter of the median (bursts after a stall) "
                         "inflate the eye speed: see the map's time.on_burst");
  return s;
}

std::string format_stats(const TraceStats& s) {
  char b[1400];
  const std::string rep = s.constant_head ? std::string("not checked (constant head pose)")
                                          : std::to_string(s.repeated_poses) +
                                                " (head pose equal to the previous sample's)";
  std::snprintf(b, sizeof b,
                "samples            %zu\n"
                "duration           %.3f s\n"
                "rate               %.2f Hz (median interval), %.2f Hz (mean)\n"
                "gaps               %ld (> 1.5x median interval), longest %.1f ms\n"
                "bursts             %ld (< 0.25x median interval)\n"
                "repeated poses     %s\n"
                "invalid            %.1f %%\n"
                "gaze eccentricity  p50 %.1f  p95 %.1f  max %.1f deg\n"
                "gaze speed         p50 %.1f  p95 %.1f  p99 %.1f deg/s (eye in head)\n"
                "head speed         p50 %.1f  p99 %.1f  max %.1f deg/s, path %.2f m\n",
                s.samples, s.duration_s, s.rate_hz, s.rate_mean_hz, s.gaps, s.max_gap_s * 1e3,
                s.bursts, rep.c_str(), 100.0 * s.invalid_fraction, s.ecc_p50, s.ecc_p95, s.ecc_max,
                s.speed_p50, s.speed_p95, s.speed_p99, s.head_speed_p50, s.head_speed_p99,
                s.head_speed_max, s.head_path_m);
  std::string out = b;
  for (size_t k = 0; k < s.head_jumps.size(); ++k)
    out += std::string(k == 0 ? "largest head jumps " : "                   ") + s.head_jumps[k] +
           "\n";
  for (auto& w : s.warnings) out += "implausible        " + w + "\n";
  return out;
}

}  // namespace fovsim
