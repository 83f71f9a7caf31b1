// A cell's measurements (docs/architecture.md "Data flow of one frame", step 4 "metrics"): its
// `metrics` block, the scratch compute_metrics reuses, the reference side it shares with the
// cells of its group whose `metrics` block agrees (reference_side.h), and per method the
// streams its frames continue (temporal error, the sequence metrics' test streams, both
// against the reference and against `full` at the methods' sampling rate). Cell::measure
// (cell_metrics.cpp) is the step.
#pragma once
#include <memory>
#include <vector>

#include "sim/metrics/metrics.h"
#include "sim/metrics/registry.h"

namespace fovsim {

struct RefSide;

// A method's history in the cell's metrics.
struct MethodStreams {
  TemporalState temporal, temporal_fl;
  // Its history in each sequence metric of the cell (RefSide::seq, same order; e.g.
  // FovVideoVDP), and the same against `full` at the methods' sampling rate (foveation loss).
  std::vector<std::unique_ptr<SequenceTest>> seq, seq_fl;
  void reset();
};

struct CellMetrics {
  MetricsConfig cfg;
  MetricsScratch scratch, fl_scratch;  // per-cell scratch, reused every frame
  // The reference side of the sequence metrics and the foveation-loss reference, shared with
  // the other cells of the group whose `metrics` block is the same (made by
  // share_reference_sides before the first frame): its first method's (MethodRun::side; the
  // methods' sides differ only in the TAA of the foveation-loss reference).
  RefSide* side = nullptr;
};

}  // namespace fovsim
