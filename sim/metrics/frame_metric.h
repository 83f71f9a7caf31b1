// A per-frame metric: a function of one test image against one reference (PSNR, SSIM, FPSNR,
// the region RMSEs, LDR-FLIP, the temporal error), declared once in its own file
// (sim/metrics/<name>.cpp) and registered in one list, frame_metrics() (registry.cpp).
// compute_metrics runs the enabled ones in that order (the order of their frames.csv columns);
// the `metrics` block's table (metrics_config_table) has one row per toggle they declare; the
// run engine and its memory estimate reach them only through this declaration (their scratch,
// their images of saved frames). The summary's side of a metric (unit, direction, pooling) is
// its MetricDecl (registry.h); a stateful metric over the sequence is a SequenceMetric.
#pragma once
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "sim/core/image.h"
#include "sim/display/display.h"
#include "sim/metrics/error_sums.h"
#include "sim/metrics/metrics.h"

namespace fovsim {

// What a per-frame metric keeps from call to call (one per MetricsScratch): its preparation
// of the reference, of the last test image, its map of the last call.
struct FrameMetricScratch {
  virtual ~FrameMetricScratch() = default;
  // The reference's pixels differ from the previous call's: its preparations are stale.
  virtual void reference_changed() {}
  // A new call begins (whatever it prepared of the previous test image is not this call's).
  virtual void new_test() {}
};

// What a per-frame metric's compute reads.
struct FrameMetricArgs {
  const MetricsConfig& cfg;
  const Image& test;
  const Image& ref;
  const Camera& cam;
  const std::vector<float>& ecc;
  bool identical;                 // test's pixels are ref's (sizes equal)
  const detail::ErrorSums& sums;  // the shared error sums (filled when a metric asked: `sums`)
  TemporalState* temporal;        // the caller's temporal state, or null
  FrameMetricScratch* scratch;    // its own scratch (make_scratch), or null
  // Its scratch from another compute_metrics of the same test image against another reference
  // (the caller's `same_test`), or null: what it prepared of the test image may be reused.
  const FrameMetricScratch* same_test;
};

// One toggle of the `metrics` block (a row of metrics_config_table).
struct MetricToggle {
  const char* key = "";  // metrics.<key>
  bool def = true;
  const char* source = "";  // author and year
  const char* doc = "";     // one line: what it switches
};

struct FrameMetric {
  const char* name = "";  // the declaration's handle: its toggle's key
  MetricToggle toggle;    // on: compute_metrics writes its columns
  // The columns it writes under `cfg` (frames.csv names, in the order it writes them).
  std::vector<std::string> (*columns)(const MetricsConfig& cfg) = nullptr;
  // What it reads besides the two images (checked by compute_metrics before any work).
  bool needs_ecc = false, needs_camera = false;
  // Asks for the shared error sums (one fused pass over the squared error, error_sums.h): sets
  // what it needs in `req`. nullptr: it does not read them.
  void (*sums)(const MetricsConfig& cfg, detail::ErrorSumsRequest& req) = nullptr;
  // Its scratch (nullptr: none) and whether it prepares the reference (then compute_metrics
  // keeps one copy of the reference's pixels to tell when the preparation is stale).
  std::unique_ptr<FrameMetricScratch> (*make_scratch)() = nullptr;
  bool prepares_reference = false;
  // Bytes its scratch holds at `pixels` pixels (the run engine's memory estimate); nullptr: 0.
  double (*scratch_bytes)(double pixels) = nullptr;
  // Bytes of the per-method state it keeps (TemporalState) at `pixels`; nullptr: 0.
  double (*state_bytes)(double pixels) = nullptr;
  // Measured against the converged reference only (temporal_error): no `<column>_fl`.
  bool reference_only = false;
  void (*compute)(const FrameMetricArgs& a, MetricValues& out) = nullptr;
  // An image of saved frames, `<label><image_suffix>.png`, under `image_toggle` (with the
  // metric on) from its scratch of the last call. nullptr: none.
  const char* image_suffix = "";
  MetricToggle image_toggle;
  Image (*image)(const FrameMetricScratch& s) = nullptr;
};

// Every per-frame metric, in the order compute_metrics writes their columns.
const std::vector<FrameMetric>& frame_metrics();

// Every column the enabled per-frame metrics write under `cfg`, in order.
std::vector<std::string> frame_metric_columns(const MetricsConfig& cfg);

// The images the enabled per-frame metrics make of the last compute_metrics call that used
// `scratch`: (file-name suffix, image), e.g. ("_flip", the FLIP error map).
std::vector<std::pair<std::string, Image>> frame_metric_images(const MetricsConfig& cfg,
                                                               const MetricsScratch& scratch);

// Bytes a MetricsScratch holds under `cfg` at `pixels` pixels: the reference's copy (when a
// metric prepares it) and every enabled metric's scratch.
double frame_metrics_scratch_bytes(const MetricsConfig& cfg, double pixels);
// Bytes of one method's per-frame-metric state (its TemporalState) under `cfg`.
double frame_metrics_state_bytes(const MetricsConfig& cfg, double pixels);

// `cfg` with the metrics measured against the converged reference only switched off (the
// foveation-loss comparison's config).
MetricsConfig without_reference_only(const MetricsConfig& cfg);
// Whether `column` is written by a metric measured against the converged reference only.
bool is_reference_only_column(const MetricsConfig& cfg, const std::string& column);

}  // namespace fovsim
