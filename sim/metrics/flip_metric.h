// The LDR-FLIP per-frame metric's scratch (flip_metric.cpp, frame_metric.h): its preparation of
// the reference and of the last test image, its working planes and the last call's error map
// (the `<label>_flip.png` images). For tests and tools that read them; the run engine does not.
#pragma once
#include "sim/metrics/flip.h"
#include "sim/metrics/frame_metric.h"

namespace fovsim {

struct FlipScratch : FrameMetricScratch {
  FlipPrepared ref, test;
  // Whether the last compute_metrics prepared `test` from its test image (false when it
  // skipped FLIP, or took the identical-images shortcut).
  bool test_valid = false;
  FlipWorkspace workspace;
  Image map;
  void reference_changed() override { ref.ppd = 0; }  // stale (a prepared ppd is > 0)
  void new_test() override { test_valid = false; }
};

// The FLIP scratch of `s`, or null when no call with FLIP on has used it.
const FlipScratch* flip_scratch(const MetricsScratch& s);

}  // namespace fovsim
