// The run config's "trace" block (keys: trace_block_table(), sim/trace/trace_keys.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "sim/core/error.h"
#include "sim/trace/importer.h"
#include "sim/trace/synth.h"
#include "sim/trace/trace.h"
#include "sim/trace/trace_keys.h"
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

namespace {

// The trace read from the block's `file` (canonical CSV, or a raw recording imported with
// `map`) or generated from its `synthetic` object, before the frame range is applied.
Trace read_source(Params& p, const TraceBlock& b, const Display& display,
                  const std::string& base_dir, TrackingPolicy& tpol) {
  const bool oi_given = p.has("on_invalid");
  TraceReadOptions opt;
  opt.on_bad = b.on_bad_sample == "fail"   ? BadSamplePolicy::Fail
               : b.on_bad_sample == "skip" ? BadSamplePolicy::Skip
                                           : BadSamplePolicy::Hold;
  opt.quat_tolerance = b.quat_tolerance;
  if (p.has("file")) {
    // A relative path is relative to the file that wrote it (a "base" config, config.h).
    auto dir_of = [&](const std::string& key) {
      std::string d = p.source_dir(key);
      return d.empty() ? base_dir : d;
    };
    std::string path = resolve(dir_of("file"), b.file);
    if (!std::filesystem::exists(path)) p.fail("file", "trace file not found: " + path);
    if (!p.has("map")) return read_trace_csv(path, display, opt);
    // A raw recording imported on the fly: its gaze is checked against the FOV row by row
    // (errors name file:line:column), and only the requested range (plus a margin for
    // resampling) is read.
    std::string map = resolve(dir_of("map"), b.map);
    if (!std::filesystem::exists(map)) p.fail("map", "column map not found: " + map);
    ImportOptions io;
    io.on_fov = opt.on_bad;
    io.on_fov_explicit = p.has("on_bad_sample");  // else the map's "on_bad"
    ImportReport rep;
    if (b.duration > 0) io.stop_after_s = b.start + b.duration + 2.0 / b.rate_hz;
    Trace tr = import_trace(path, map, display, &rep, io);
    if (!oi_given && !rep.on_invalid.empty()) parse_on_invalid(rep.on_invalid, tpol.on_invalid);
    return tr;
  }
  Params s = p.child("synthetic");
  SynthBlock sb;
  sb.duration = b.start + (b.duration > 0 ? b.duration : 10.0);  // the default
  synth_block_table().read_into(s, sb);
  SynthOptions so;
  so.scenario = sb.scenario;
  so.seed = uint64_t(sb.seed);
  so.duration_s = sb.duration;
  so.rate_hz = b.rate_hz;
  EyeModel m;
  if (s.has("params")) {
    const Json& j = s.raw("params");
    std::string d = s.source_dir("params");
    m = load_eye_model(j, p.file(), s.path_of("params"), d.empty() ? base_dir : d);
  }
  // Sized before anything is generated.
  const double n_syn = synth_sample_count(m, so);
  if (n_syn > b.max_samples)
    s.fail("duration", "a synthetic trace of " + g6(so.duration_s) + " s at " + g6(so.rate_hz) +
                           " Hz has " + g6(n_syn) +
                           " samples, over the limit trace.max_samples = " + g6(b.max_samples) +
                           " (shorten it, lower trace.rate_hz or raise trace.max_samples)");
  return synthesize(m, so, display);
}

// Resamples only the range used: [first, first + start + (duration or what the caller needs)],
// plus two periods for the end-of-range tests; the sample count is checked before allocating.
// Returns the absolute time past which nothing was resampled.
double resample_used_range(Params& p, const TraceBlock& b, double needed_s, Trace& tr) {
  double used = std::min(b.duration > 0 ? b.duration : INFINITY, needed_s);
  double t_end = tr.samples.front().t + b.start + used + 2.0 / b.rate_hz;
  double n = resampled_count(tr, b.rate_hz, t_end);
  if (n > b.max_samples)
    p.fail("max_samples", "the frame range needs " + std::to_string(int64_t(std::min(n, 9e18))) +
                              " samples at " + std::to_string(b.rate_hz) + " Hz (the trace spans " +
                              std::to_string(tr.samples.back().t - tr.samples.front().t) +
                              " s), over the limit of " + std::to_string(int64_t(b.max_samples)) +
                              " (set trace.duration or frames.count, or raise trace.max_samples)");
  tr = resample(tr, b.rate_hz, t_end);
  return t_end;
}

// The frame range [first + start, first + start + duration) of `tr`, with `on_short` applied
// when the recording (raw_first .. raw_last) is shorter than start + duration.
Trace select_range(Params& p, const TraceBlock& b, const Trace& tr, double raw_first,
                   double raw_last, double used_end) {
  const double start = b.start, duration = b.duration, rate = b.rate_hz;
  const double t_first = tr.samples.front().t;
  const double period = b.resample ? 1.0 / rate : 0.0, eps = 1e-9 + 1e-6 * period;
  const double from = t_first + start;
  if (from > raw_last + eps)
    p.fail("start", "start " + std::to_string(start) + " s is past the end of the trace (" +
                        std::to_string(raw_last - raw_first) + " s long)");
  double to = duration > 0 ? from + duration : INFINITY;
  bool short_trace = duration > 0 && to > raw_last + period + eps;
  Trace out;
  out.source = tr.source;
  out.warnings = tr.warnings;
  if (short_trace) {
    std::string msg = "trace " + tr.source + " covers " +
                      std::to_string(raw_last - raw_first + period) +
                      " s but start+duration asks for " + std::to_string(start + duration) + " s";
    if (b.on_short == "fail") p.fail("duration", msg + " (set on_short to truncate or hold)");
    out.warnings.push_back(msg + (b.on_short == "truncate" ? ": truncated (on_short=truncate)"
                                                           : ": last sample held (on_short=hold)"));
  }
  for (const auto& s : tr.samples)
    if (s.t >= from - eps && s.t < to - eps) out.samples.push_back(s);
  if (b.on_short == "hold" && short_trace && !out.samples.empty() && period > 0) {
    // Held only up to what the frames use (the resampled range), not the whole duration.
    const double hold_to = std::min(to, used_end + period);
    TraceSample h = out.samples.back();
    // The held samples count towards the same limit, checked before any is added.
    const double n_hold = double(out.samples.size()) + std::max(0.0, (to - h.t) / period);
    if (n_hold > b.max_samples)
      p.fail("duration", "holding the last sample to start+duration = " + g6(start + duration) +
                             " s needs " + g6(std::ceil(n_hold)) + " samples at " + g6(rate) +
                             " Hz, over the limit trace.max_samples = " + g6(b.max_samples) +
                             " (shorten trace.duration or raise trace.max_samples)");
    for (long k = 1;; ++k) {
      TraceSample c = h;
      c.t = h.t + double(k) * period;
      if (c.t >= hold_to - eps) break;
      out.samples.push_back(c);
    }
  }
  return out;
}

}  // namespace

// Stages: the block's keys (trace_block_table), the source (file, import or synthesis), the
// tracking policy, resampling of the range used, the frame range.
Trace load_trace(Params& p, const Display& display, const std::string& base_dir, double needed_s,
                 TrackingPolicy* tracking) {
  p.ignore("comment");
  TraceBlock b;
  b.rate_hz = display.refresh_hz;  // the default
  trace_block_table().read_into(p, b);
  const bool has_file = p.has("file"), has_syn = p.has("synthetic");
  if (has_file == has_syn)
    p.fail("", has_file ? "give either \"file\" or \"synthetic\", not both"
                        : "needs \"file\": \"traces/x.csv\" or \"synthetic\": {\"scenario\": ...}");
  // Tracking loss in runs (tracking.h): parsed here so that every trace key is validated
  // in one place, with its JSON path. A column map's "on_invalid" is the default.
  TrackingPolicy tpol;
  parse_on_invalid(b.on_invalid, tpol.on_invalid);
  tpol.widen_per_s = b.widen_per_s;

  Trace tr = read_source(p, b, display, base_dir, tpol);
  if (tr.samples.empty()) p.fail(has_file ? "file" : "synthetic", "trace has no samples");
  if (p.has("widen_per_s") && tpol.on_invalid != OnInvalid::Widen)
    p.fail("widen_per_s", "only used with \"on_invalid\": \"widen\"");
  if (tracking) *tracking = tpol;
  // The range the recording covers, before resampling shortens it to what the frames use:
  // start+duration is checked against this, not against the resampled part.
  const double raw_first = tr.samples.front().t, raw_last = tr.samples.back().t;
  double used_end = INFINITY;  // absolute time past which nothing is resampled
  if (b.resample) used_end = resample_used_range(p, b, needed_s, tr);
  Trace out = select_range(p, b, tr, raw_first, raw_last, used_end);
  if (out.samples.empty()) p.fail("duration", "the selected range contains no samples");
  for (const auto& w : out.warnings) std::cerr << "warning: " << w << "\n";
  return out;
}

}  // namespace fovsim
