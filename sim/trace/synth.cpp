// Synthetic eye-movement generator (docs/architecture.md "Inputs: displays, traces, scenes,
// configs"). Parameter table: sim/trace/synth.h and models/eyemodel/default.json (sources in
// traces/README.md "Synthetic traces").
//
// Model, simulated at internal_rate_hz (1 kHz):
// - gaze-in-world G(t) and head orientation H(t) are simulated; eye-in-head = H^-1 G;
// - fixation: G stays on a world target while the head moves (VOR, gain vor_gain); when the
//   eye-in-head leaves the oculomotor range or the display FOV a quick phase (saccade) fires;
// - saccade: G rotates along the great circle to the target with duration
//   D = intercept + slope*A (Carpenter 1988) and peak velocity Vp = vmax (1 - exp(-A/c))
//   (form of Baloh et al. 1975); the velocity profile is sin^k(pi tau) with k chosen so the
//   profile has both D and Vp (smooth, zero velocity at both ends);
// - head-assisted shifts: beyond eye_only_range the head turns by slope*(A - range)
//   (Freedman & Sparks 1997) with a minimum-jerk profile; VOR then recentres the eye;
// - smooth pursuit: G turns with gain * the target's angular velocity after a latency, with
//   catch-up saccades to the predicted target when the position error exceeds a threshold;
// - blinks: Poisson (rate_per_min), duration gamma-clipped; valid=0 and the tracker holds the
//   last valid gaze; tracker noise (Gaussian, deg) and latency (samples) on output.
#include "sim/trace/synth.h"

#include <algorithm>
#include <cmath>

#include "sim/core/error.h"
#include "sim/core/rng.h"

namespace fovsim {

const std::vector<std::string>& synth_scenarios() {
  static const std::vector<std::string> s = {"fixate",  "free-viewing", "reading",
                                             "pursuit", "walk-through", "head-sweep"};
  return s;
}

namespace {

using dvec3 = glm::dvec3;
using dquat = glm::dquat;

// Yaw about +Y (positive turns the -Z forward towards -X, i.e. left), pitch about +X (positive up).
dvec3 dir_from(double az_deg, double el_deg) {
  double a = deg2rad(az_deg), e = deg2rad(el_deg);
  return {-std::sin(a) * std::cos(e), std::sin(e), -std::cos(a) * std::cos(e)};
}
double az_of(const dvec3& w) {
  return rad2deg(std::atan2(-w.x, -w.z));
}
double el_of(const dvec3& w) {
  return rad2deg(std::asin(std::clamp(w.y, -1.0, 1.0)));
}
double wrap180(double a) {
  a = std::fmod(a + 180.0, 360.0);
  if (a < 0) a += 360.0;
  return a - 180.0;
}
dquat head_quat(double yaw, double pitch, double roll) {
  return glm::angleAxis(deg2rad(yaw), dvec3(0, 1, 0)) *
         glm::angleAxis(deg2rad(pitch), dvec3(1, 0, 0)) *
         glm::angleAxis(deg2rad(roll), dvec3(0, 0, 1));
}
double min_jerk(double u) {
  u = std::clamp(u, 0.0, 1.0);
  return u * u * u * (10 - 15 * u + 6 * u * u);
}
dvec3 slerp_dir(const dvec3& a, const dvec3& b, double u) {
  double th = angle_between(a, b);
  if (th < 1e-12) return b;
  double s = std::sin(th);
  return glm::normalize(a * (std::sin((1 - u) * th) / s) + b * (std::sin(u * th) / s));
}
// Rotates `g` by `deg` towards direction angle phi (0 = right, 90 = up) in g's tangent plane.
dvec3 rotate_towards(const dvec3& g, double deg, double phi_deg) {
  dvec3 up(0, 1, 0);
  dvec3 right = glm::cross(g, up);
  if (glm::length(right) < 1e-9) right = dvec3(1, 0, 0);
  right = glm::normalize(right);
  dvec3 upl = glm::cross(right, g);
  dvec3 t = std::cos(deg2rad(phi_deg)) * right + std::sin(deg2rad(phi_deg)) * upl;
  return glm::normalize(std::cos(deg2rad(deg)) * g + std::sin(deg2rad(deg)) * t);
}

// Gamma(mean, sd) by Marsaglia-Tsang, clipped to [lo, hi].
double gamma_sample(Rng& rng, double mean, double sd, double lo, double hi) {
  double k = (mean * mean) / (sd * sd), theta = sd * sd / mean;
  double boost = 1.0;
  if (k < 1) {
    boost = std::pow(std::max(rng.uniform(), 1e-300), 1.0 / k);
    k += 1;
  }
  double d = k - 1.0 / 3.0, c = 1.0 / std::sqrt(9 * d), x = 0;
  for (;;) {
    double z = rng.normal(), v = 1 + c * z;
    if (v <= 0) continue;
    v = v * v * v;
    double u = rng.uniform();
    if (std::log(std::max(u, 1e-300)) < 0.5 * z * z + d - d * v + d * std::log(v)) {
      x = d * v;
      break;
    }
  }
  return std::clamp(x * theta * boost, lo, hi);
}

// Saccade velocity profile v(tau) ~ sin^k(pi tau): mean/peak ratio I(k) = Gamma((k+1)/2) /
// (sqrt(pi) Gamma(k/2+1)); choose k with Vp*D/A = 1/I(k).
double profile_ratio(double k) {
  return std::sqrt(kPi) * std::exp(std::lgamma(k / 2 + 1) - std::lgamma((k + 1) / 2));
}
struct Profile {
  std::vector<double> cdf;  // position fraction on a uniform tau grid
  double eval(double tau) const {
    double x = std::clamp(tau, 0.0, 1.0) * double(cdf.size() - 1);
    size_t i = std::min(size_t(x), cdf.size() - 2);
    double f = x - double(i);
    return cdf[i] * (1 - f) + cdf[i + 1] * f;
  }
};
Profile make_profile(double ratio) {
  double lo = 0.25, hi = 8.0;
  ratio = std::clamp(ratio, profile_ratio(lo), profile_ratio(hi));
  for (int it = 0; it < 60; ++it) {
    double mid = 0.5 * (lo + hi);
    (profile_ratio(mid) < ratio ? lo : hi) = mid;
  }
  double k = 0.5 * (lo + hi);
  const int n = 1024, sub = 8;
  Profile p;
  p.cdf.resize(n + 1);
  double acc = 0;
  p.cdf[0] = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < sub; ++j) {  // midpoint rule
      double u = (i * sub + j + 0.5) / double(n * sub);
      acc += std::pow(std::sin(kPi * u), k);
    }
    p.cdf[i + 1] = acc;
  }
  for (double& c : p.cdf) c /= acc;
  return p;
}

class Simulator {
 public:
  Simulator(const EyeModel& m, const SynthOptions& o, const Display& d)
      : m_(m), o_(o), d_(d), rng_(o.seed, 0x5eed0001ull), dt_(1.0 / m.internal_rate_hz) {
    lim_h_ = std::min(m.eye_range_deg, d.fov_h_deg / 2 - m.fov_margin_deg);
    lim_v_ = std::min(m.eye_range_deg, d.fov_v_deg / 2 - m.fov_margin_deg);
    if (lim_h_ < 1 || lim_v_ < 1)
      throw Error("synthetic trace", "display FOV " + std::to_string(d.fov_h_deg) + "x" +
                                         std::to_string(d.fov_v_deg) +
                                         " deg minus fov_margin_deg leaves no room for gaze");
    const auto& sc = synth_scenarios();
    if (std::find(sc.begin(), sc.end(), o.scenario) == sc.end())
      throw Error("synthetic trace", "unknown scenario \"" + o.scenario + "\"");
    scen_ = o.scenario;
    fix_mean_ = m.fix_mean_ms;
    fix_sd_ = m.fix_sd_ms;
    blink_rate_ = m.blink_rate_per_min;
    if (scen_ == "reading") {
      fix_mean_ = m.reading.fix_mean_ms;
      fix_sd_ = m.reading.fix_sd_ms;
      blink_rate_ = m.reading.blink_rate_per_min;
    }
    head_assist_ = scen_ == "free-viewing" || scen_ == "walk-through";
    for (double& p : phase_) p = rng_.uniform(0, 2 * kPi);
    build_sweep();
  }

  Trace run(SynthDebug* dbg) {
    Trace tr;
    tr.source = "synthetic:" + scen_ + ":" + std::to_string(o_.seed);
    long n = long(std::floor(o_.duration_s * m_.internal_rate_hz + 1e-9)) + 1;
    tr.samples.reserve(size_t(n));
    t_ = 0;
    update_head();
    // Start fixating straight ahead of the (base) head, or at the first target.
    if (scen_ == "reading") {
      G_ = reading_target();
    } else if (scen_ == "pursuit") {
      pur_az_ = pur_el_ = 0;
      new_waypoint();
      G_ = dir_from(0, 0);
    } else {
      G_ = H_ * dvec3(0, 0, -1);
    }
    center_ = G_;
    start_fixation(scen_ == "pursuit" ? m_.pursuit_latency_ms * 1e-3 : -1);
    for (long i = 0; i < n; ++i) {
      t_ = double(i) * dt_;
      update_head();
      if (scen_ == "pursuit") update_target();
      step();
      TraceSample s;
      s.t = t_;
      s.head_pos = pos_;
      s.head_rot = H_;
      s.gaze_dir = glm::normalize(glm::conjugate(H_) * G_);
      s.valid = !(t_ >= blink_t0_ && t_ < blink_t1_);
      tr.samples.push_back(s);
      if (dbg) {
        dbg->phase.push_back(
            state_ == Sac
                ? SynthDebug::Saccade
                : (scen_ == "pursuit" && pursuing_ ? SynthDebug::Pursuit : SynthDebug::Fixation));
        dbg->gaze_world.push_back(G_);
        dbg->target_world.push_back(scen_ == "pursuit" ? T_ : fix_target_);
        dbg->blink.push_back(s.valid ? 0 : 1);
      }
    }
    return tr;
  }

 private:
  enum State { Fix, Sac };

  // ---- head -------------------------------------------------------------------------------
  void build_sweep() {
    // head-sweep: yaw moves 0 -> +A -> -A -> +A ... with minimum-jerk sweeps whose peak speed is
    // peak_speed (min-jerk peak = 1.875 * distance / duration), separated by pauses.
    if (scen_ != "head-sweep") return;
    double A = m_.sweep.amplitude_deg, t = m_.sweep.pause_s, from = 0, to = A;
    while (t < o_.duration_s + 10) {
      double dist = std::fabs(to - from), dur = 1.875 * dist / m_.sweep.peak_speed_deg_s;
      sweep_.push_back({t, dur, from, to});
      t += dur + m_.sweep.pause_s;
      from = to;
      to = -to;
      if (from == 0) to = A;
    }
  }
  void base_head(double t, double& yaw, double& pitch, double& roll, dvec3& pos) const {
    yaw = pitch = roll = 0;
    pos = dvec3(0, m_.walk.eye_height_m, 0);
    if (scen_ == "fixate") {
      double a = m_.fixate.head_sway_deg, f = m_.fixate.head_sway_hz;
      yaw = a * std::sin(2 * kPi * f * t + phase_[0]);
      pitch = 0.5 * a * std::sin(2 * kPi * f * 1.37 * t + phase_[1]);
    } else if (scen_ == "walk-through") {
      const auto& w = m_.walk;
      yaw = w.yaw_amp_deg * (0.7 * std::sin(2 * kPi * w.yaw_hz * t + phase_[0]) +
                             0.3 * std::sin(2 * kPi * w.yaw_hz * 2.3 * t + phase_[1]));
      pitch = w.pitch_amp_deg * std::sin(2 * kPi * w.pitch_hz * t + phase_[2]) - 3.0;
      roll = 1.0 * std::sin(kPi * w.step_hz * t + phase_[3]);
      pos = dvec3(w.sway_m * std::sin(kPi * w.step_hz * t + phase_[3]),
                  w.eye_height_m + w.bob_m * std::sin(2 * kPi * w.step_hz * t), -w.speed_m_s * t);
    } else if (scen_ == "head-sweep") {
      for (const auto& s : sweep_) {
        if (t < s.t0) break;
        yaw = s.from + (s.to - s.from) * min_jerk((t - s.t0) / s.dur);
      }
    }
  }
  void update_head() {
    base_head(t_, by_, bp_, br_, pos_);
    if (hm_active_) {
      double u = (t_ - hm_t0_) / hm_dur_;
      if (u >= 1) {
        ay_ = hm_y1_;
        ap_ = hm_p1_;
        hm_active_ = false;
      } else if (u > 0) {
        double s = min_jerk(u);
        ay_ = hm_y0_ + (hm_y1_ - hm_y0_) * s;
        ap_ = hm_p0_ + (hm_p1_ - hm_p0_) * s;
      }
    }
    H_ = head_quat(by_ + ay_, bp_ + ap_, br_);
  }
  // Eye-in-head of a world direction under the current head is within the display FOV
  // (minus margin) and the oculomotor range.
  bool eye_ok(const dvec3& w, double extra = 0) const {
    dvec3 e = glm::conjugate(H_) * w;
    if (!(e.z < 0)) return false;
    double h = rad2deg(std::atan2(std::fabs(e.x), -e.z)),
           v = rad2deg(std::atan2(std::fabs(e.y), -e.z));
    double ecc = rad2deg(angle_between(e, dvec3(0, 0, -1)));
    return h <= lim_h_ + extra && v <= lim_v_ + extra && ecc <= m_.eye_range_deg + extra;
  }
  bool in_fov(
      const dvec3& w) const {  // display FOV only (transient limit during head-assisted shifts)
    dvec3 e = glm::conjugate(H_) * w;
    if (!(e.z < 0)) return false;
    return rad2deg(std::atan2(std::fabs(e.x), -e.z)) <= d_.fov_h_deg / 2 - m_.fov_margin_deg &&
           rad2deg(std::atan2(std::fabs(e.y), -e.z)) <= d_.fov_v_deg / 2 - m_.fov_margin_deg;
  }

  // ---- state machine ------------------------------------------------------------------------
  void start_fixation(double dur_s = -1) {
    state_ = Fix;
    fix_target_ = G_;
    fix_H_ = H_;
    double dur = dur_s >= 0
                     ? dur_s
                     : gamma_sample(rng_, fix_mean_, fix_sd_, m_.fix_min_ms, m_.fix_max_ms) * 1e-3;
    fix_end_ = t_ + dur;
    // Blink during this fixation with probability 1 - exp(-rate * duration) (Poisson).
    if (blink_rate_ > 0 && t_ >= blink_t1_) {
      double p = 1 - std::exp(-blink_rate_ / 60.0 * dur);
      if (rng_.uniform() < p) {
        double bd = gamma_sample(rng_, m_.blink_mean_ms, 0.3 * m_.blink_mean_ms, m_.blink_min_ms,
                                 m_.blink_max_ms) *
                    1e-3;
        blink_t0_ = t_ + rng_.uniform() * dur;
        blink_t1_ = blink_t0_ + bd;
      }
    }
  }
  void start_saccade(const dvec3& target) {
    double A = rad2deg(angle_between(G_, target));
    if (A < 1e-3) {
      start_fixation();
      return;
    }
    state_ = Sac;
    sac_G0_ = G_;
    sac_G1_ = target;
    sac_t0_ = t_;
    sac_dur_ = (m_.sac_intercept_ms + m_.sac_slope_ms_per_deg * A) * 1e-3;
    double vp = m_.sac_vmax_deg_s * (1 - std::exp(-A / m_.sac_c_deg));
    prof_ = make_profile(vp * sac_dur_ / A);
    fix_target_ = target;
    last_sac_end_ = t_ + sac_dur_;
    if (head_assist_) plan_head(target);
  }
  // Head contribution to a gaze shift (Freedman & Sparks 1997): slope*(A - eye_only_range),
  // at least enough to bring the final eye-in-head within the oculomotor range.
  void plan_head(const dvec3& target) {
    dvec3 fwd = H_ * dvec3(0, 0, -1);
    double d = rad2deg(angle_between(fwd, target));
    if (d <= m_.head_eye_only_range_deg) return;
    double frac = m_.head_slope * (d - m_.head_eye_only_range_deg) / d;
    frac = std::clamp(std::max(frac, (d - m_.eye_range_deg + 2) / d), 0.0, 1.0);
    double daz = wrap180(az_of(target) - az_of(fwd)), del = el_of(target) - el_of(fwd);
    hm_y0_ = ay_;
    hm_p0_ = ap_;
    hm_y1_ = ay_ + frac * daz;
    hm_p1_ = ap_ + frac * del;
    hm_t0_ = t_ + m_.head_latency_ms * 1e-3;
    hm_dur_ = (m_.head_dur_base_ms + m_.head_dur_slope_ms_per_deg * frac * d) * 1e-3;
    hm_active_ = true;
  }

  void step() {
    if (state_ == Sac) {
      double u = (t_ - sac_t0_) / sac_dur_;
      if (u >= 1) {
        G_ = sac_G1_;
        if (scen_ == "pursuit") {
          state_ = Fix;
          pursuing_ = true;
          fix_end_ = 1e300;
        } else {
          start_fixation();
        }
      } else {
        G_ = slerp_dir(sac_G0_, sac_G1_, prof_.eval(u));
      }
      return;
    }
    if (scen_ == "pursuit") {
      step_pursuit();
      return;
    }
    // Fixation: gaze stays on the world target; VOR gain g leaves (1-g) of the head rotation.
    if (m_.vor_gain != 1.0) {
      dquat dh = H_ * glm::conjugate(fix_H_);
      G_ = glm::normalize(glm::slerp(dquat(1, 0, 0, 0), dh, 1.0 - m_.vor_gain) * fix_target_);
    } else {
      G_ = fix_target_;
    }
    // While a head-assisted shift is still under way the eye may be beyond its usual range
    // (the head is bringing the target towards the centre): only the FOV limits it then.
    bool out_of_range = hm_active_ ? !in_fov(G_) : !eye_ok(G_, 0.5);
    if (t_ >= fix_end_ || out_of_range) start_saccade(choose_target(out_of_range));
  }

  void step_pursuit() {
    if (!pursuing_) {  // latency: fixate, then a saccade onto the target
      if (t_ >= fix_end_) start_saccade(predict_target(rad2deg(angle_between(G_, T_))));
      return;
    }
    // G turns by gain * the target's rotation over the last step.
    dvec3 axis = glm::cross(T_prev_, T_);
    double ang = angle_between(T_prev_, T_);
    if (ang > 1e-12) {
      dquat r = glm::angleAxis(m_.pursuit_gain * ang, glm::normalize(axis));
      G_ = glm::normalize(r * G_);
    }
    double err = rad2deg(angle_between(G_, T_));
    if (err > m_.pursuit_catchup_deg && t_ - last_sac_end_ > 0.1)
      start_saccade(predict_target(err));
  }
  // Catch-up saccade lands where the target will be at the saccade's end.
  dvec3 predict_target(double amp) {
    double D = (m_.sac_intercept_ms + m_.sac_slope_ms_per_deg * amp) * 1e-3;
    double az = pur_az_, el = pur_el_;
    advance_target(az, el, D);
    return dir_from(az, el);
  }

  // ---- targets -------------------------------------------------------------------------------
  dvec3 choose_target(bool forced) {
    if (scen_ == "reading") {
      dvec3 t = reading_target();
      if (eye_ok(t)) return t;
      return center_;
    }
    if (scen_ == "fixate") return fixate_target();
    return free_target(forced);
  }
  dvec3 fixate_target() {
    for (int tries = 0; tries < 50; ++tries) {
      double A = std::max(
          0.05, -m_.fixate.microsaccade_mean_deg * std::log(std::max(rng_.uniform(), 1e-12)));
      dvec3 c = rotate_towards(G_, A, rng_.uniform(0, 360));
      if (rad2deg(angle_between(c, center_)) <= m_.fixate.radius_deg && eye_ok(c)) return c;
    }
    return center_;
  }
  dvec3 free_target(bool forced) {
    double roi_h = scen_ == "walk-through" ? m_.walk.roi_h_deg : m_.free_viewing.roi_h_deg;
    double roi_v = scen_ == "walk-through" ? m_.walk.roi_v_deg : m_.free_viewing.roi_v_deg;
    double elev = scen_ == "walk-through" ? m_.walk.elevation_deg : m_.free_viewing.elevation_deg;
    if (scen_ == "head-sweep") {
      roi_h = 2 * lim_h_;
      roi_v = 2 * lim_v_;
      elev = 0;
    }
    // Head velocity direction (for anticipatory quick phases).
    double yb0, pb0, rb0, yb1, pb1, rb1;
    dvec3 p0, p1;
    base_head(t_, yb0, pb0, rb0, p0);
    base_head(t_ + 0.05, yb1, pb1, rb1, p1);
    double head_dir = wrap180(yb1 - yb0);  // >0: turning left
    for (int tries = 0; tries < 60; ++tries) {
      double A = gamma_sample(rng_, m_.amp_mean_deg, m_.amp_sd_deg, m_.amp_min_deg, m_.amp_max_deg);
      double phi;
      if ((forced || scen_ == "head-sweep") && std::fabs(head_dir) > 0.05) {
        phi = (head_dir > 0 ? 180.0 : 0.0) + 20 * rng_.normal();  // go where the head is going
        if (forced) A = std::max(A, 10.0);
      } else if (rng_.uniform() < m_.horizontal_bias) {
        phi = (rng_.uniform() < 0.5 ? 0.0 : 180.0) + 10 * rng_.normal();
      } else {
        phi = rng_.uniform(0, 360);
      }
      dvec3 c = rotate_towards(G_, A, phi);
      double az_rel = wrap180(az_of(c) - yb0), el_rel = el_of(c) - (pb0 + elev);
      if (std::fabs(az_rel) > roi_h / 2 || std::fabs(el_rel) > roi_v / 2) continue;
      bool ok = eye_ok(c) ||
                (head_assist_ && in_fov(c) &&
                 rad2deg(angle_between(H_ * dvec3(0, 0, -1), c)) > m_.head_eye_only_range_deg);
      if (!ok) continue;
      return c;
    }
    // Fallback: re-centre on the head's forward direction.
    return H_ * dvec3(0, 0, -1);
  }
  dvec3 reading_target() {
    const auto& r = m_.reading;
    double left = -r.line_width_deg / 2, right = r.line_width_deg / 2;
    if (!read_started_) {
      read_started_ = true;
      read_line_ = 0;
      read_x_ = left;
    } else if (read_x_ >= right) {  // return sweep to the next line (undershoots its start)
      read_line_ = (read_line_ + 1) % int(r.lines);
      read_x_ = left + r.return_undershoot_deg * rng_.uniform();
    } else if (rng_.uniform() < r.regression_prob) {
      read_x_ = std::max(left, read_x_ - std::max(0.3, 0.6 * r.saccade_mean_deg +
                                                           0.3 * r.saccade_sd_deg * rng_.normal()));
    } else {
      read_x_ += std::max(0.3, r.saccade_mean_deg + r.saccade_sd_deg * rng_.normal());
      read_x_ = std::min(read_x_, right);
    }
    double top = (r.lines - 1) / 2 * r.line_spacing_deg;
    return dir_from(-read_x_, top - read_line_ * r.line_spacing_deg);
  }

  // Pursuit target: constant-speed segments between random waypoints.
  void new_waypoint() {
    const auto& p = m_.pursuit;
    wp_az_ = rng_.uniform(-p.range_h_deg, p.range_h_deg);
    wp_el_ = rng_.uniform(-p.range_v_deg, p.range_v_deg);
    wp_speed_ = rng_.uniform(p.speed_min_deg_s, p.speed_max_deg_s);
  }
  void advance_target(double& az, double& el, double dt) const {
    double daz = wp_az_ - az, del = wp_el_ - el, dist = std::hypot(daz, del), s = wp_speed_ * dt;
    if (dist <= s || dist < 1e-9) {
      az = wp_az_;
      el = wp_el_;
    } else {
      az += daz / dist * s;
      el += del / dist * s;
    }
  }
  void update_target() {
    T_prev_ = T_;
    if (t_ > 0) advance_target(pur_az_, pur_el_, dt_);
    if (std::hypot(wp_az_ - pur_az_, wp_el_ - pur_el_) < 1e-9) new_waypoint();
    T_ = dir_from(pur_az_, pur_el_);
    if (t_ == 0) T_prev_ = T_;
  }

  const EyeModel& m_;
  SynthOptions o_;
  const Display& d_;
  Rng rng_;
  double dt_, t_ = 0;
  std::string scen_;
  double lim_h_, lim_v_, fix_mean_, fix_sd_, blink_rate_;
  bool head_assist_ = false;
  double phase_[4];
  struct Sweep {
    double t0, dur, from, to;
  };
  std::vector<Sweep> sweep_;
  // head
  double by_ = 0, bp_ = 0, br_ = 0, ay_ = 0, ap_ = 0;
  dvec3 pos_{0.0};
  dquat H_{1, 0, 0, 0};
  bool hm_active_ = false;
  double hm_t0_ = 0, hm_dur_ = 1, hm_y0_ = 0, hm_p0_ = 0, hm_y1_ = 0, hm_p1_ = 0;
  // eye
  State state_ = Fix;
  dvec3 G_{0, 0, -1}, center_{0, 0, -1}, fix_target_{0, 0, -1};
  dquat fix_H_{1, 0, 0, 0};
  double fix_end_ = 0;
  dvec3 sac_G0_{0, 0, -1}, sac_G1_{0, 0, -1};
  double sac_t0_ = 0, sac_dur_ = 1, last_sac_end_ = -1;
  Profile prof_;
  double blink_t0_ = -1, blink_t1_ = -1;
  // reading
  bool read_started_ = false;
  int read_line_ = 0;
  double read_x_ = 0;
  // pursuit
  bool pursuing_ = false;
  double pur_az_ = 0, pur_el_ = 0, wp_az_ = 0, wp_el_ = 0, wp_speed_ = 10;
  dvec3 T_{0, 0, -1}, T_prev_{0, 0, -1};
};

}  // namespace

double synth_sample_count(const EyeModel& m, const SynthOptions& o) {
  return o.duration_s * std::max(o.rate_hz, m.internal_rate_hz) + 1.0;
}

Trace synth_internal(const EyeModel& m, const SynthOptions& o, const Display& d, SynthDebug* dbg) {
  if (!(o.duration_s > 0)) throw Error("synthetic trace", "duration must be > 0 s");
  Simulator sim(m, o, d);
  return sim.run(dbg);
}

Trace synthesize(const EyeModel& m, const SynthOptions& o, const Display& d) {
  if (!(o.rate_hz > 0)) throw Error("synthetic trace", "rate must be > 0 Hz");
  Trace in = synth_internal(m, o, d);
  Trace out = resample(in, o.rate_hz);
  // Tracker: latency (samples), Gaussian noise, blink hold, clamp into the FOV.
  Rng noise(o.seed, 0x7acce700ull);
  const size_t n = out.samples.size();
  std::vector<glm::dvec3> g(n);
  std::vector<bool> valid(n);
  for (size_t i = 0; i < n; ++i) {
    size_t j = i >= size_t(m.latency_samples) ? i - size_t(m.latency_samples) : 0;
    g[i] = out.samples[j].gaze_dir;
    valid[i] = out.samples[j].valid;
  }
  glm::dvec3 last(0, 0, -1);
  bool have = false;
  for (size_t i = 0; i < n; ++i) {
    TraceSample& s = out.samples[i];
    s.valid = valid[i];
    double nx = noise.normal(), ny = noise.normal();  // drawn for every sample: stable streams
    if (!s.valid) {
      s.gaze_dir = have ? last : g[i];
      continue;
    }
    glm::dvec3 v = g[i];
    if (m.noise_deg > 0) {
      glm::dvec3 right = glm::normalize(glm::cross(v, glm::dvec3(0, 1, 0)));
      glm::dvec3 up = glm::cross(right, v);
      v = glm::normalize(v + std::tan(deg2rad(m.noise_deg * nx)) * right +
                         std::tan(deg2rad(m.noise_deg * ny)) * up);
    }
    if (!gaze_inside_fov(d, v)) {
      double u = 0.5, w = 0.5;
      gaze_screen_from_dir(d, v, u, w);
      v = gaze_dir_from_screen(d, std::clamp(u, 0.0, 1.0), std::clamp(w, 0.0, 1.0));
    }
    s.gaze_dir = v;
    last = v;
    have = true;
  }
  return out;
}

}  // namespace fovsim
