// The run config's "trace" block (keys documented in traces/README.md "Run config").
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "sim/core/error.h"
#include "sim/trace/importer.h"
#include "sim/trace/synth.h"
#include "sim/trace/trace.h"
#include "sim/trace/tracking.h"

namespace fovsim {

static std::string g6(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

static std::string resolve(const std::string& base_dir, const std::string& f) {
  std::filesystem::path p(f);
  if (p.is_absolute() || base_dir.empty()) return f;
  return (std::filesystem::path(base_dir) / p).lexically_normal().string();
}

Trace load_trace(Params& p, const Display& display, const std::string& base_dir, double needed_s,
                 TrackingPolicy* tracking) {
  p.ignore("comment");
  // Tracking loss in runs (tracking.h): parsed here so that every trace key is validated
  // in one place, with its JSON path. A column map's "on_invalid" is the default.
  TrackingPolicy tpol;
  const bool oi_given = p.has("on_invalid");
  parse_on_invalid(p.string("on_invalid", "hold", {"hold", "centre", "full", "widen"}),
                   tpol.on_invalid);
  tpol.widen_per_s = p.number("widen_per_s", 10.0, Range::closed(0, 1000));
  bool has_file = p.has("file"), has_syn = p.has("synthetic");
  if (has_file == has_syn)
    p.fail("", has_file ? "give either \"file\" or \"synthetic\", not both"
                        : "needs \"file\": \"traces/x.csv\" or \"synthetic\": {\"scenario\": ...}");
  TraceReadOptions opt;
  std::string pol = p.string("on_bad_sample", "fail", {"fail", "skip", "hold"});
  opt.on_bad = pol == "fail"   ? BadSamplePolicy::Fail
               : pol == "skip" ? BadSamplePolicy::Skip
                               : BadSamplePolicy::Hold;
  opt.quat_tolerance = p.number("quat_tolerance", 1e-3, Range::above(0, 0.5));
  double start = p.number("start", 0.0, Range::at_least(0));
  double duration = p.number("duration", 0.0, Range::at_least(0));
  std::string on_short = p.string("on_short", "fail", {"fail", "truncate", "hold"});
  bool do_resample = p.boolean("resample", true);
  double rate = p.number("rate_hz", display.refresh_hz, Range::above(0, 10000));
  const double max_samples =
      p.integer("max_samples", int(kDefaultMaxTraceSamples), Range::closed(1, 2e9));

  Trace tr;
  if (has_file) {
    std::string f = p.string("file");
    // A relative path is relative to the file that wrote it (a "base" config, config.h).
    auto dir_of = [&](const std::string& key) {
      std::string d = p.source_dir(key);
      return d.empty() ? base_dir : d;
    };
    std::string path = resolve(dir_of("file"), f);
    if (!std::filesystem::exists(path)) p.fail("file", "trace file not found: " + path);
    if (p.has("map")) {
      // A raw recording imported on the fly: its gaze is checked against the FOV row by row
      // (errors name file:line:column), and only the requested range (plus a margin for
      // resampling) is read.
      std::string map = resolve(dir_of("map"), p.string("map"));
      if (!std::filesystem::exists(map)) p.fail("map", "column map not found: " + map);
      ImportOptions io;
      io.on_fov = opt.on_bad;
      io.on_fov_explicit = p.has("on_bad_sample");  // else the map's "on_bad"
      ImportReport rep;
      if (duration > 0) io.stop_after_s = start + duration + 2.0 / rate;
      tr = import_trace(path, map, display, &rep, io);
      if (!oi_given && !rep.on_invalid.empty()) parse_on_invalid(rep.on_invalid, tpol.on_invalid);
    } else {
      tr = read_trace_csv(path, display, opt);
    }
  } else {
    Params s = p.child("synthetic");
    SynthOptions so;
    so.scenario = s.string("scenario", synth_scenarios());
    so.seed = uint64_t(check_integer(s.where("seed"),
                                     s.number("seed", 1, Range::closed(0, kMaxSynthSeed)),
                                     Range::closed(0, kMaxSynthSeed)));
    so.duration_s =
        s.number("duration", start + (duration > 0 ? duration : 10.0), Range::above(0, 36000));
    so.rate_hz = rate;
    EyeModel m;
    if (s.has("params")) {
      const Json& j = s.raw("params");
      std::string d = s.source_dir("params");
      m = load_eye_model(j, p.file(), s.path_of("params"), d.empty() ? base_dir : d);
    }
    // Sized before anything is generated.
    const double n_syn = synth_sample_count(m, so);
    if (n_syn > max_samples)
      s.fail("duration", "a synthetic trace of " + g6(so.duration_s) + " s at " + g6(so.rate_hz) +
                             " Hz has " + g6(n_syn) +
                             " samples, over the limit trace.max_samples = " + g6(max_samples) +
                             " (shorten it, lower trace.rate_hz or raise trace.max_samples)");
    tr = synthesize(m, so, display);
  }
  if (tr.samples.empty()) p.fail(has_file ? "file" : "synthetic", "trace has no samples");
  if (p.has("widen_per_s") && tpol.on_invalid != OnInvalid::Widen)
    p.fail("widen_per_s", "only used with \"on_invalid\": \"widen\"");
  if (tracking) *tracking = tpol;
  // The range the recording covers, before resampling shortens it to what the frames use:
  // start+duration is checked against this, not against the resampled part.
  const double raw_first = tr.samples.front().t, raw_last = tr.samples.back().t;
  double used_end = INFINITY;  // absolute time past which nothing is resampled
  if (do_resample) {
    // Only the range used: [first, first + start + (duration or what the caller needs)],
    // plus two periods for the end-of-range tests below. Checked before allocating.
    double used = std::min(duration > 0 ? duration : INFINITY, needed_s);
    double t_end = tr.samples.front().t + start + used + 2.0 / rate;
    used_end = t_end;
    double n = resampled_count(tr, rate, t_end);
    if (n > max_samples)
      p.fail("max_samples",
             "the frame range needs " + std::to_string(int64_t(std::min(n, 9e18))) +
                 " samples at " + std::to_string(rate) + " Hz (the trace spans " +
                 std::to_string(tr.samples.back().t - tr.samples.front().t) +
                 " s), over the limit of " + std::to_string(int64_t(max_samples)) +
                 " (set trace.duration or frames.count, or raise trace.max_samples)");
    tr = resample(tr, rate, t_end);
  }

  // Frame range: [first + start, first + start + duration).
  const double t_first = tr.samples.front().t;
  const double period = do_resample ? 1.0 / rate : 0.0, eps = 1e-9 + 1e-6 * period;
  const double from = t_first + start;
  if (from > raw_last + eps)
    p.fail("start", "start " + std::to_string(start) + " s is past the end of the trace (" +
                        std::to_string(raw_last - raw_first) + " s long)");
  double to = duration > 0 ? from + duration : INFINITY;
  bool short_trace = duration > 0 && to > raw_last + period + eps;
  if (short_trace) {
    std::string msg = "trace " + tr.source + " covers " +
                      std::to_string(raw_last - raw_first + period) +
                      " s but start+duration asks for " + std::to_string(start + duration) + " s";
    if (on_short == "fail") p.fail("duration", msg + " (set on_short to truncate or hold)");
    tr.warnings.push_back(msg + (on_short == "truncate" ? ": truncated (on_short=truncate)"
                                                        : ": last sample held (on_short=hold)"));
  }
  Trace out;
  out.source = tr.source;
  out.warnings = tr.warnings;
  for (const auto& s : tr.samples)
    if (s.t >= from - eps && s.t < to - eps) out.samples.push_back(s);
  if (on_short == "hold" && short_trace && !out.samples.empty() && period > 0) {
    // Held only up to what the frames use (the resampled range), not the whole duration.
    const double hold_to = std::min(to, used_end + period);
    TraceSample h = out.samples.back();
    // The held samples count towards the same limit, checked before any is added.
    const double n_hold = double(out.samples.size()) + std::max(0.0, (to - h.t) / period);
    if (n_hold > max_samples)
      p.fail("duration", "holding the last sample to start+duration = " + g6(start + duration) +
                             " s needs " + g6(std::ceil(n_hold)) + " samples at " + g6(rate) +
                             " Hz, over the limit trace.max_samples = " + g6(max_samples) +
                             " (shorten trace.duration or raise trace.max_samples)");
    for (long k = 1;; ++k) {
      TraceSample c = h;
      c.t = h.t + double(k) * period;
      if (c.t >= hold_to - eps) break;
      out.samples.push_back(c);
    }
  }
  if (out.samples.empty()) p.fail("duration", "the selected range contains no samples");
  for (const auto& w : out.warnings) std::cerr << "warning: " << w << "\n";
  return out;
}

}  // namespace fovsim
