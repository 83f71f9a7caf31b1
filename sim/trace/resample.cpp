// Resampling to a fixed rate (traces/README.md "Resampling"): frame k is at t0 + k/hz;
// positions lerp, orientations slerp (shortest arc), gaze normalized lerp, `valid` from the
// nearest sample. A frame that coincides with an input sample (within 1e-6 of a period)
// copies it exactly, so resampling at the trace's own rate is the identity.
#include <algorithm>
#include <cmath>

#include "sim/core/error.h"
#include "sim/trace/trace.h"

namespace fovsim {

static glm::dquat slerp_short(glm::dquat a, glm::dquat b, double u) {
  double d = a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
  if (d < 0) {
    b = -b;
    d = -d;
  }
  glm::dquat r;
  if (d > 1.0 - 1e-12) {
    r = a * (1.0 - u) + b * u;  // identical up to rounding
  } else {
    double th = std::acos(d), s = std::sin(th);
    r = a * (std::sin((1.0 - u) * th) / s) + b * (std::sin(u * th) / s);
  }
  return glm::normalize(r);
}

double resampled_count(const Trace& trace, double hz, double t_end) {
  if (trace.samples.empty() || !(hz > 0)) return 0;
  const double t0 = trace.samples.front().t, t1 = std::min(trace.samples.back().t, t_end);
  if (t1 < t0) return 1;
  return std::floor((t1 - t0) * hz * (1.0 + 1e-12) + 1e-6) + 1;
}

Trace resample(const Trace& trace, double hz, double t_end) {
  if (!(hz > 0) || !std::isfinite(hz))
    throw Error("resample", "rate must be > 0 Hz, got " + std::to_string(hz));
  Trace out;
  out.source = trace.source;
  out.warnings = trace.warnings;
  const auto& in = trace.samples;
  if (in.empty()) return out;
  const double t0 = in.front().t, t1 = in.back().t, period = 1.0 / hz, snap = 1e-6 * period;
  size_t i = 0;
  for (long k = 0;; ++k) {
    double t = t0 + double(k) * period;
    if (t > t1 + snap || t > t_end + snap) break;
    while (i + 1 < in.size() && in[i + 1].t <= t + snap) ++i;
    if (std::fabs(in[i].t - t) <= snap || i + 1 >= in.size()) {
      out.samples.push_back(in[i]);
      continue;
    }
    const TraceSample &a = in[i], &b = in[i + 1];
    double u = (t - a.t) / (b.t - a.t);
    TraceSample s;
    s.t = t;
    s.head_pos = a.head_pos + (b.head_pos - a.head_pos) * u;
    s.head_rot = slerp_short(a.head_rot, b.head_rot, u);
    glm::dvec3 g = a.gaze_dir * (1.0 - u) + b.gaze_dir * u;
    double n = glm::length(g);
    s.gaze_dir = n > 1e-12 ? g / n : a.gaze_dir;
    s.valid = u < 0.5 ? a.valid : b.valid;
    out.samples.push_back(s);
  }
  return out;
}

}  // namespace fovsim
