// Gaze at an arbitrary time (latency what-if): the same interpolation as resample()
// (normalized lerp of the head-space gaze, `valid` from the nearest sample), clamped to the
// first/last sample outside the trace, and the eye-in-head angular speed by a central difference.
#include <algorithm>
#include <cmath>

#include "sim/trace/trace.h"

namespace fovsim {

TraceSample sample_at(const Trace& trace, double t) {
  const auto& in = trace.samples;
  if (in.empty()) return TraceSample{};
  if (t <= in.front().t) return in.front();
  if (t >= in.back().t) return in.back();
  auto it = std::upper_bound(in.begin(), in.end(), t,
                             [](double v, const TraceSample& s) { return v < s.t; });
  const TraceSample& b = *it;
  const TraceSample& a = *(it - 1);
  if (t == a.t) return a;
  double u = (t - a.t) / (b.t - a.t);
  TraceSample s = u < 0.5 ? a : b;
  s.t = t;
  s.head_pos = a.head_pos + (b.head_pos - a.head_pos) * u;
  if (a.gaze_dir == b.gaze_dir) {  // steady gaze stays bit-identical (no lerp rounding)
    s.gaze_dir = a.gaze_dir;
    return s;
  }
  glm::dvec3 g = a.gaze_dir * (1.0 - u) + b.gaze_dir * u;
  double n = glm::length(g);
  s.gaze_dir = n > 1e-12 ? g / n : a.gaze_dir;
  return s;
}

double angle_deg(const glm::dvec3& a, const glm::dvec3& b) {
  // atan2 form: accurate for tiny angles, unlike acos of the dot product.
  double c = glm::length(glm::cross(a, b)), d = glm::dot(a, b);
  return std::atan2(c, d) * 180.0 / 3.14159265358979323846;
}

double gaze_speed_deg_s(const Trace& trace, double t, double half_window_s) {
  TraceSample a = sample_at(trace, t - half_window_s), b = sample_at(trace, t + half_window_s);
  double dt = b.t - a.t;
  if (!(dt > 0)) return 0;
  return angle_deg(glm::normalize(a.gaze_dir), glm::normalize(b.gaze_dir)) / dt;
}

}  // namespace fovsim
