// Eye-model parameter tables (models/eyemodel/default.json, traces/README.md): one
// ParamTable<EyeModel> per section drives reading, writing (to_json) and the generated key
// tables of configs/README.md, so file, code and docs cannot drift.
#include <filesystem>

#include "sim/core/error.h"
#include "sim/trace/synth.h"

namespace fovsim {

namespace {

// One ParamTable<EyeModel> per section of the eye-model file ("" = the top level), bound to
// the members of EyeModel; the defaults are EyeModel's member initialisers (synth.h).
// `src` (declared in each section's block) cites where the section's values come from.
#define FOVSIM_EYE(key, member, range, meaning)                                   \
  number(                                                                         \
      key, kEyeDefaults.member, range, [](auto& m) -> auto& { return m.member; }) \
      .doc(src, meaning)
const EyeModel kEyeDefaults{};

// Long because: it is the declaration, one row per key of the eye-model file.
std::vector<EyeModelSection> make_tables() {
  std::vector<EyeModelSection> v;

  {
    const char* src = "ours (simulation step)";
    ParamTable<EyeModel> t;
    t.documented("comment", "any", "", "", "", "ignored")
        .FOVSIM_EYE("internal_rate_hz", internal_rate_hz, Range::closed(100, 10000),
                    "rate of the noise-free internal simulation (Hz)");
    v.push_back({"", std::move(t)});
  }
  {
    const char* src = "Rayner 1998; Henderson & Hollingworth 1998";
    ParamTable<EyeModel> t;
    t.documented("comment", "any", "", "", "", "ignored")
        .FOVSIM_EYE("mean_ms", fix_mean_ms, Range::closed(20, 10000),
                    "mean fixation duration (gamma distribution, ms)")
        .FOVSIM_EYE("sd_ms", fix_sd_ms, Range::above(0, 10000),
                    "standard deviation of fixation durations (ms)")
        .FOVSIM_EYE("min_ms", fix_min_ms, Range::closed(0, 10000), "shortest fixation (clip, ms)")
        .FOVSIM_EYE("max_ms", fix_max_ms, Range::closed(20, 60000), "longest fixation (clip, ms)")
        .validate([](const EyeModel& m, Params& p) {
          if (m.fix_min_ms > m.fix_max_ms) p.fail("min_ms", "must not exceed fixation.max_ms");
        });
    v.push_back({"fixation", std::move(t)});
  }
  {
    const char* src = "Carpenter 1988 (main sequence); Baloh et al. 1975; Bahill et al. 1975";
    ParamTable<EyeModel> t;
    t.documented("comment", "any", "", "", "", "ignored")
        .FOVSIM_EYE("intercept_ms", sac_intercept_ms, Range::closed(1, 200),
                    "main sequence: duration at 0 deg (D = intercept + slope A, ms)")
        .FOVSIM_EYE("slope_ms_per_deg", sac_slope_ms_per_deg, Range::closed(0, 20),
                    "main sequence: duration per degree of amplitude (ms/deg)")
        .FOVSIM_EYE("vmax_deg_s", sac_vmax_deg_s, Range::closed(50, 2000),
                    "peak velocity saturation: Vpeak = vmax (1 - exp(-A/c)) (deg/s)")
        .FOVSIM_EYE("c_deg", sac_c_deg, Range::above(0, 100),
                    "peak velocity constant c of the saturation (deg)")
        .FOVSIM_EYE("amplitude_mean_deg", amp_mean_deg, Range::above(0, 90),
                    "free-viewing saccade amplitude, gamma mean (deg)")
        .FOVSIM_EYE("amplitude_sd_deg", amp_sd_deg, Range::above(0, 90),
                    "free-viewing saccade amplitude, gamma sd (deg)")
        .FOVSIM_EYE("amplitude_min_deg", amp_min_deg, Range::above(0, 90),
                    "smallest saccade amplitude (clip, deg)")
        .FOVSIM_EYE("amplitude_max_deg", amp_max_deg, Range::above(0, 90),
                    "largest saccade amplitude (clip, deg)")
        .FOVSIM_EYE("horizontal_bias", horizontal_bias, Range::closed(0, 1),
                    "probability that a saccade goes near-horizontally (else a uniform direction)")
        .validate([](const EyeModel& m, Params& p) {
          if (m.amp_min_deg > m.amp_max_deg)
            p.fail("amplitude_min_deg", "must not exceed amplitude_max_deg");
        });
    v.push_back({"saccade", std::move(t)});
  }
  {
    const char* src = "Leigh & Zee (VOR gain); ours (range)";
    ParamTable<EyeModel> t;
    t.documented("comment", "any", "", "", "", "ignored")
        .FOVSIM_EYE(
            "range_deg", eye_range_deg, Range::closed(1, 90),
            "eye-in-head limit: beyond it a quick phase or head movement recentres the eye (deg)")
        .FOVSIM_EYE("fov_margin_deg", fov_margin_deg, Range::closed(0, 30),
                    "gaze kept this far inside the display FOV (deg)")
        .FOVSIM_EYE(
            "vor_gain", vor_gain, Range::closed(0, 1.5),
            "vestibulo-ocular reflex gain during fixation (1 = gaze stays on its world target)");
    v.push_back({"eye", std::move(t)});
  }
  {
    const char* src = "Freedman & Sparks 1997; Stahl 1999";
    ParamTable<EyeModel> t;
    t.documented("comment", "any", "", "", "", "ignored")
        .FOVSIM_EYE("eye_only_range_deg", head_eye_only_range_deg, Range::closed(0, 180),
                    "gaze shifts up to this amplitude are eye-only (deg)")
        .FOVSIM_EYE("slope", head_slope, Range::closed(0, 1),
                    "head contribution per degree beyond eye_only_range_deg")
        .FOVSIM_EYE("latency_ms", head_latency_ms, Range::closed(0, 1000),
                    "head movement onset after saccade onset (ms)")
        .FOVSIM_EYE("duration_base_ms", head_dur_base_ms, Range::closed(10, 5000),
                    "minimum-jerk head movement duration at 0 deg (ms)")
        .FOVSIM_EYE("duration_slope_ms_per_deg", head_dur_slope_ms_per_deg, Range::closed(0, 100),
                    "head movement duration per degree (ms/deg)");
    v.push_back({"head", std::move(t)});
  }
  {
    const char* src = "Lisberger et al. 1987; de Brouwer et al. 2002";
    ParamTable<EyeModel> t;
    t.documented("comment", "any", "", "", "", "ignored")
        .FOVSIM_EYE("gain", pursuit_gain, Range::closed(0, 1.5),
                    "smooth pursuit gain on the target angular velocity")
        .FOVSIM_EYE("catchup_threshold_deg", pursuit_catchup_deg, Range::above(0, 30),
                    "position error that triggers a catch-up saccade (deg)")
        .FOVSIM_EYE("latency_ms", pursuit_latency_ms, Range::closed(0, 2000),
                    "pursuit onset after target motion starts (ms)");
    v.push_back({"pursuit", std::move(t)});
  }
  {
    const char* src = "Bentivoglio et al. 1997";
    ParamTable<EyeModel> t;
    t.documented("comment", "any", "", "", "", "ignored")
        .FOVSIM_EYE("rate_per_min", blink_rate_per_min, Range::closed(0, 120),
                    "blinks per minute (Poisson)")
        .FOVSIM_EYE("mean_ms", blink_mean_ms, Range::above(0, 2000), "mean blink duration (ms)")
        .FOVSIM_EYE("min_ms", blink_min_ms, Range::closed(0, 2000), "shortest blink (clip, ms)")
        .FOVSIM_EYE("max_ms", blink_max_ms, Range::above(0, 5000), "longest blink (clip, ms)")
        .validate([](const EyeModel& m, Params& p) {
          if (m.blink_min_ms > m.blink_max_ms) p.fail("min_ms", "must not exceed blink.max_ms");
        });
    v.push_back({"blink", std::move(t)});
  }
  {
    const char* src = "ours (Pico Neo 3 Pro recording); Stein et al. 2021 (latency)";
    ParamTable<EyeModel> t;
    t.documented("comment", "any", "", "", "", "ignored")
        .FOVSIM_EYE("noise_deg", noise_deg, Range::closed(0, 10),
                    "Gaussian gaze noise of the reported trace (deg, sd)")
        .integer(
            "latency_samples", kEyeDefaults.latency_samples, Range::closed(0, 1000),
            [](auto& m) -> auto& { return m.latency_samples; })
        .doc(src, "tracker latency in output samples");
    v.push_back({"tracker", std::move(t)});
  }
  {
    const char* src = "ours";
    ParamTable<EyeModel> t;
    t.documented("comment", "any", "", "", "", "ignored")
        .FOVSIM_EYE("radius_deg", fixate.radius_deg, Range::above(0, 20),
                    "microsaccade targets stay within this angle of the central target (deg)")
        .FOVSIM_EYE("microsaccade_mean_deg", fixate.microsaccade_mean_deg, Range::above(0, 5),
                    "mean microsaccade amplitude (exponential, deg)")
        .FOVSIM_EYE("head_sway_deg", fixate.head_sway_deg, Range::closed(0, 30),
                    "head sway amplitude (deg)")
        .FOVSIM_EYE("head_sway_hz", fixate.head_sway_hz, Range::closed(0, 10),
                    "head sway frequency (Hz)");
    v.push_back({"scenarios/fixate", std::move(t)});
  }
  {
    const char* src = "ours";
    ParamTable<EyeModel> t;
    t.documented("comment", "any", "", "", "", "ignored")
        .FOVSIM_EYE("roi_h_deg", free_viewing.roi_h_deg, Range::above(0, 360),
                    "width of the viewed region (deg)")
        .FOVSIM_EYE("roi_v_deg", free_viewing.roi_v_deg, Range::above(0, 180),
                    "height of the viewed region (deg)")
        .FOVSIM_EYE("elevation_deg", free_viewing.elevation_deg, Range::closed(-45, 45),
                    "elevation of the region centre (deg)");
    v.push_back({"scenarios/free-viewing", std::move(t)});
  }
  {
    const char* src = "Rayner 1998";
    ParamTable<EyeModel> t;
    t.documented("comment", "any", "", "", "", "ignored")
        .FOVSIM_EYE("line_width_deg", reading.line_width_deg, Range::above(0, 80),
                    "text line width (deg)")
        .FOVSIM_EYE("line_spacing_deg", reading.line_spacing_deg, Range::above(0, 10),
                    "line spacing (deg)")
        .FOVSIM_EYE("lines", reading.lines, Range::closed(1, 60),
                    "lines per page before the return to the top")
        .FOVSIM_EYE("saccade_mean_deg", reading.saccade_mean_deg, Range::above(0, 20),
                    "mean forward saccade (deg)")
        .FOVSIM_EYE("saccade_sd_deg", reading.saccade_sd_deg, Range::above(0, 20),
                    "sd of forward saccades (deg)")
        .FOVSIM_EYE("regression_prob", reading.regression_prob, Range::closed(0, 1),
                    "probability that a saccade is a regression (backwards)")
        .FOVSIM_EYE("fixation_mean_ms", reading.fix_mean_ms, Range::closed(20, 10000),
                    "mean reading fixation (ms)")
        .FOVSIM_EYE("fixation_sd_ms", reading.fix_sd_ms, Range::above(0, 10000),
                    "sd of reading fixations (ms)")
        .FOVSIM_EYE("blink_rate_per_min", reading.blink_rate_per_min, Range::closed(0, 120),
                    "blinks per minute while reading")
        .FOVSIM_EYE("return_undershoot_deg", reading.return_undershoot_deg, Range::closed(0, 20),
                    "undershoot of the return sweep to the next line (deg)");
    v.push_back({"scenarios/reading", std::move(t)});
  }
  {
    const char* src = "ours";
    ParamTable<EyeModel> t;
    t.documented("comment", "any", "", "", "", "ignored")
        .FOVSIM_EYE("speed_min_deg_s", pursuit.speed_min_deg_s, Range::above(0, 200),
                    "slowest target segment (deg/s)")
        .FOVSIM_EYE("speed_max_deg_s", pursuit.speed_max_deg_s, Range::above(0, 200),
                    "fastest target segment (deg/s)")
        .FOVSIM_EYE("range_h_deg", pursuit.range_h_deg, Range::above(0, 45),
                    "target waypoints within +-this horizontally (deg)")
        .FOVSIM_EYE("range_v_deg", pursuit.range_v_deg, Range::above(0, 45),
                    "target waypoints within +-this vertically (deg)")
        .validate([](const EyeModel& m, Params& p) {
          if (m.pursuit.speed_min_deg_s > m.pursuit.speed_max_deg_s)
            p.fail("speed_min_deg_s", "must not exceed speed_max_deg_s");
        });
    v.push_back({"scenarios/pursuit", std::move(t)});
  }
  {
    const char* src = "Hirasaki et al. 1999";
    ParamTable<EyeModel> t;
    t.documented("comment", "any", "", "", "", "ignored")
        .FOVSIM_EYE("speed_m_s", walk.speed_m_s, Range::closed(0, 10), "walking speed (m/s)")
        .FOVSIM_EYE("eye_height_m", walk.eye_height_m, Range::closed(0, 3),
                    "eye height above the floor (m)")
        .FOVSIM_EYE("step_hz", walk.step_hz, Range::closed(0, 5), "step frequency (Hz)")
        .FOVSIM_EYE("bob_m", walk.bob_m, Range::closed(0, 0.2), "vertical head bob per step (m)")
        .FOVSIM_EYE("sway_m", walk.sway_m, Range::closed(0, 0.2), "lateral head sway per step (m)")
        .FOVSIM_EYE("yaw_amplitude_deg", walk.yaw_amp_deg, Range::closed(0, 90),
                    "head yaw oscillation amplitude (deg)")
        .FOVSIM_EYE("yaw_hz", walk.yaw_hz, Range::closed(0, 2),
                    "head yaw oscillation frequency (Hz)")
        .FOVSIM_EYE("pitch_amplitude_deg", walk.pitch_amp_deg, Range::closed(0, 45),
                    "head pitch oscillation amplitude (deg)")
        .FOVSIM_EYE("pitch_hz", walk.pitch_hz, Range::closed(0, 2),
                    "head pitch oscillation frequency (Hz)")
        .FOVSIM_EYE("roi_h_deg", walk.roi_h_deg, Range::above(0, 360),
                    "width of the region the gaze explores (deg)")
        .FOVSIM_EYE("roi_v_deg", walk.roi_v_deg, Range::above(0, 180),
                    "height of the region the gaze explores (deg)")
        .FOVSIM_EYE("elevation_deg", walk.elevation_deg, Range::closed(-45, 45),
                    "elevation of that region (deg)");
    v.push_back({"scenarios/walk-through", std::move(t)});
  }
  {
    const char* src = "ours";
    ParamTable<EyeModel> t;
    t.documented("comment", "any", "", "", "", "ignored")
        .FOVSIM_EYE("amplitude_deg", sweep.amplitude_deg, Range::above(0, 90),
                    "yaw sweep amplitude, +- (deg)")
        .FOVSIM_EYE("peak_speed_deg_s", sweep.peak_speed_deg_s, Range::above(0, 1000),
                    "peak head speed of a minimum-jerk sweep (deg/s)")
        .FOVSIM_EYE("pause_s", sweep.pause_s, Range::closed(0, 10), "pause between sweeps (s)");
    v.push_back({"scenarios/head-sweep", std::move(t)});
  }
  return v;
}
#undef FOVSIM_EYE

// Walks "scenarios/reading" to the child Params.
Params section(Params& root, const std::string& sec, std::vector<Params>& keep) {
  if (sec.empty()) return root;
  auto slash = sec.find('/');
  if (slash == std::string::npos) return root.child(sec);
  Params mid = root.child(sec.substr(0, slash));
  return mid.child(sec.substr(slash + 1));
}

}  // namespace

const std::vector<EyeModelSection>& eye_model_tables() {
  static const std::vector<EyeModelSection> v = make_tables();
  return v;
}

EyeModel EyeModel::from_params(Params& p) {
  EyeModel m;
  p.ignore("comment");
  if (p.has("sources")) p.raw("sources");  // documentation only
  std::vector<Params> keep;
  for (auto& sec : eye_model_tables()) {
    Params s = section(p, sec.path, keep);
    s.ignore("comment");
    sec.table.read_into(s, m);
  }
  return m;
}

Json EyeModel::to_json() const {
  Json j = Json::object();
  for (auto& sec : eye_model_tables())
    for (auto& row : sec.table.rows()) {
      if (row.doc_only) continue;
      Json::json_pointer ptr(std::string(sec.path).empty()
                                 ? "/" + row.key
                                 : "/" + std::string(sec.path) + "/" + row.key);
      j[ptr] = row.get(*this);
    }
  return j;
}

EyeModel load_eye_model(const Json& overrides, const std::string& where_file,
                        const std::string& where_path, const std::string& base_dir) {
  Json doc = EyeModel().to_json();
  std::string file = where_file, path = where_path;
  Json patch;
  if (overrides.is_string()) {
    std::filesystem::path f(overrides.get<std::string>());
    if (!f.is_absolute() && !base_dir.empty()) f = std::filesystem::path(base_dir) / f;
    if (!std::filesystem::exists(f))
      throw Error(where_file.empty() ? where_path : where_file + ": " + where_path,
                  "eye-model parameter file not found: " + f.string());
    patch = Params::parse_json_file(f.string());
    file = f.string();
    path = "";
  } else if (overrides.is_object()) {
    patch = overrides;
  } else {
    throw Error(
        where_file.empty() ? where_path : where_file + ": " + where_path,
        "expected a JSON object of overrides or a file name, got " + describe_json(overrides));
  }
  if (!patch.is_object()) throw Error(file, "expected a JSON object, got " + describe_json(patch));
  doc.merge_patch(patch);
  Params p(doc, file, path);
  EyeModel m = EyeModel::from_params(p);
  p.finish();
  return m;
}

}  // namespace fovsim
