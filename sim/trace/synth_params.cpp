// Eye-model parameter table (models/eyemodel/default.json, traces/README.md): one list of
// (section, key, range) drives both reading and writing, so file and code cannot drift.
#include <filesystem>

#include "sim/core/error.h"
#include "sim/trace/synth.h"

namespace fovsim {

namespace {

struct Field {
  const char* section;  // "fixation" or "scenarios/reading"
  const char* key;
  double* v;
  Range r;
};

std::vector<Field> fields(EyeModel& m) {
  const Range pos = Range::above(0), nonneg = Range::at_least(0), unit = Range::closed(0, 1);
  auto deg = [](double hi) { return Range::closed(0, hi); };
  return {
      {"", "internal_rate_hz", &m.internal_rate_hz, Range::closed(100, 10000)},
      {"fixation", "mean_ms", &m.fix_mean_ms, Range::closed(20, 10000)},
      {"fixation", "sd_ms", &m.fix_sd_ms, Range::above(0, 10000)},
      {"fixation", "min_ms", &m.fix_min_ms, Range::closed(0, 10000)},
      {"fixation", "max_ms", &m.fix_max_ms, Range::closed(20, 60000)},
      {"saccade", "intercept_ms", &m.sac_intercept_ms, Range::closed(1, 200)},
      {"saccade", "slope_ms_per_deg", &m.sac_slope_ms_per_deg, Range::closed(0, 20)},
      {"saccade", "vmax_deg_s", &m.sac_vmax_deg_s, Range::closed(50, 2000)},
      {"saccade", "c_deg", &m.sac_c_deg, Range::above(0, 100)},
      {"saccade", "amplitude_mean_deg", &m.amp_mean_deg, Range::above(0, 90)},
      {"saccade", "amplitude_sd_deg", &m.amp_sd_deg, Range::above(0, 90)},
      {"saccade", "amplitude_min_deg", &m.amp_min_deg, Range::above(0, 90)},
      {"saccade", "amplitude_max_deg", &m.amp_max_deg, Range::above(0, 90)},
      {"saccade", "horizontal_bias", &m.horizontal_bias, unit},
      {"eye", "range_deg", &m.eye_range_deg, Range::closed(1, 90)},
      {"eye", "fov_margin_deg", &m.fov_margin_deg, deg(30)},
      {"eye", "vor_gain", &m.vor_gain, Range::closed(0, 1.5)},
      {"head", "eye_only_range_deg", &m.head_eye_only_range_deg, Range::closed(0, 180)},
      {"head", "slope", &m.head_slope, unit},
      {"head", "latency_ms", &m.head_latency_ms, Range::closed(0, 1000)},
      {"head", "duration_base_ms", &m.head_dur_base_ms, Range::closed(10, 5000)},
      {"head", "duration_slope_ms_per_deg", &m.head_dur_slope_ms_per_deg, Range::closed(0, 100)},
      {"pursuit", "gain", &m.pursuit_gain, Range::closed(0, 1.5)},
      {"pursuit", "catchup_threshold_deg", &m.pursuit_catchup_deg, Range::above(0, 30)},
      {"pursuit", "latency_ms", &m.pursuit_latency_ms, Range::closed(0, 2000)},
      {"blink", "rate_per_min", &m.blink_rate_per_min, Range::closed(0, 120)},
      {"blink", "mean_ms", &m.blink_mean_ms, Range::above(0, 2000)},
      {"blink", "min_ms", &m.blink_min_ms, Range::closed(0, 2000)},
      {"blink", "max_ms", &m.blink_max_ms, Range::above(0, 5000)},
      {"tracker", "noise_deg", &m.noise_deg, deg(10)},
      {"scenarios/fixate", "radius_deg", &m.fixate.radius_deg, Range::above(0, 20)},
      {"scenarios/fixate", "microsaccade_mean_deg", &m.fixate.microsaccade_mean_deg,
       Range::above(0, 5)},
      {"scenarios/fixate", "head_sway_deg", &m.fixate.head_sway_deg, deg(30)},
      {"scenarios/fixate", "head_sway_hz", &m.fixate.head_sway_hz, Range::closed(0, 10)},
      {"scenarios/free-viewing", "roi_h_deg", &m.free_viewing.roi_h_deg, Range::above(0, 360)},
      {"scenarios/free-viewing", "roi_v_deg", &m.free_viewing.roi_v_deg, Range::above(0, 180)},
      {"scenarios/free-viewing", "elevation_deg", &m.free_viewing.elevation_deg,
       Range::closed(-45, 45)},
      {"scenarios/reading", "line_width_deg", &m.reading.line_width_deg, Range::above(0, 80)},
      {"scenarios/reading", "line_spacing_deg", &m.reading.line_spacing_deg, Range::above(0, 10)},
      {"scenarios/reading", "lines", &m.reading.lines, Range::closed(1, 60)},
      {"scenarios/reading", "saccade_mean_deg", &m.reading.saccade_mean_deg, Range::above(0, 20)},
      {"scenarios/reading", "saccade_sd_deg", &m.reading.saccade_sd_deg, Range::above(0, 20)},
      {"scenarios/reading", "regression_prob", &m.reading.regression_prob, unit},
      {"scenarios/reading", "fixation_mean_ms", &m.reading.fix_mean_ms, Range::closed(20, 10000)},
      {"scenarios/reading", "fixation_sd_ms", &m.reading.fix_sd_ms, Range::above(0, 10000)},
      {"scenarios/reading", "blink_rate_per_min", &m.reading.blink_rate_per_min,
       Range::closed(0, 120)},
      {"scenarios/reading", "return_undershoot_deg", &m.reading.return_undershoot_deg, deg(20)},
      {"scenarios/pursuit", "speed_min_deg_s", &m.pursuit.speed_min_deg_s, Range::above(0, 200)},
      {"scenarios/pursuit", "speed_max_deg_s", &m.pursuit.speed_max_deg_s, Range::above(0, 200)},
      {"scenarios/pursuit", "range_h_deg", &m.pursuit.range_h_deg, Range::above(0, 45)},
      {"scenarios/pursuit", "range_v_deg", &m.pursuit.range_v_deg, Range::above(0, 45)},
      {"scenarios/walk-through", "speed_m_s", &m.walk.speed_m_s, Range::closed(0, 10)},
      {"scenarios/walk-through", "eye_height_m", &m.walk.eye_height_m, Range::closed(0, 3)},
      {"scenarios/walk-through", "step_hz", &m.walk.step_hz, Range::closed(0, 5)},
      {"scenarios/walk-through", "bob_m", &m.walk.bob_m, Range::closed(0, 0.2)},
      {"scenarios/walk-through", "sway_m", &m.walk.sway_m, Range::closed(0, 0.2)},
      {"scenarios/walk-through", "yaw_amplitude_deg", &m.walk.yaw_amp_deg, deg(90)},
      {"scenarios/walk-through", "yaw_hz", &m.walk.yaw_hz, Range::closed(0, 2)},
      {"scenarios/walk-through", "pitch_amplitude_deg", &m.walk.pitch_amp_deg, deg(45)},
      {"scenarios/walk-through", "pitch_hz", &m.walk.pitch_hz, Range::closed(0, 2)},
      {"scenarios/walk-through", "roi_h_deg", &m.walk.roi_h_deg, Range::above(0, 360)},
      {"scenarios/walk-through", "roi_v_deg", &m.walk.roi_v_deg, Range::above(0, 180)},
      {"scenarios/walk-through", "elevation_deg", &m.walk.elevation_deg, Range::closed(-45, 45)},
      {"scenarios/head-sweep", "amplitude_deg", &m.sweep.amplitude_deg, Range::above(0, 90)},
      {"scenarios/head-sweep", "peak_speed_deg_s", &m.sweep.peak_speed_deg_s,
       Range::above(0, 1000)},
      {"scenarios/head-sweep", "pause_s", &m.sweep.pause_s, Range::closed(0, 10)},
  };
  (void)pos;
  (void)nonneg;
}

// Walks "scenarios/reading" to the child Params.
Params section(Params& root, const std::string& sec, std::vector<Params>& keep) {
  if (sec.empty()) return root;
  auto slash = sec.find('/');
  if (slash == std::string::npos) return root.child(sec);
  Params mid = root.child(sec.substr(0, slash));
  return mid.child(sec.substr(slash + 1));
}

}  // namespace

EyeModel EyeModel::from_params(Params& p) {
  EyeModel m;
  p.ignore("comment");
  if (p.has("sources")) p.raw("sources");  // documentation only
  std::vector<Params> keep;
  for (auto& f : fields(m)) {
    Params s = section(p, f.section, keep);
    s.ignore("comment");
    *f.v = s.number(f.key, *f.v, f.r);
  }
  Params tr = p.child("tracker");
  m.latency_samples = tr.integer("latency_samples", m.latency_samples, Range::closed(0, 1000));
  auto check = [&](bool ok, const std::string& sec, const std::string& key,
                   const std::string& msg) {
    if (!ok) p.fail(sec + "." + key, msg);
  };
  check(m.fix_min_ms <= m.fix_max_ms, "fixation", "min_ms", "must not exceed fixation.max_ms");
  check(m.amp_min_deg <= m.amp_max_deg, "saccade", "amplitude_min_deg",
        "must not exceed amplitude_max_deg");
  check(m.blink_min_ms <= m.blink_max_ms, "blink", "min_ms", "must not exceed blink.max_ms");
  check(m.pursuit.speed_min_deg_s <= m.pursuit.speed_max_deg_s, "scenarios.pursuit",
        "speed_min_deg_s", "must not exceed speed_max_deg_s");
  return m;
}

Json EyeModel::to_json() const {
  EyeModel m = *this;
  Json j = Json::object();
  for (auto& f : fields(m)) {
    Json::json_pointer ptr(std::string(f.section).empty()
                               ? "/" + std::string(f.key)
                               : "/" + std::string(f.section) + "/" + f.key);
    j[ptr] = *f.v;
  }
  j["tracker"]["latency_samples"] = latency_samples;
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
