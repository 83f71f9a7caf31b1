// A cell's measurements (docs/architecture.md "Data flow of one frame", step 4 "metrics"): its
// `metrics` block, the workspace it borrows per frame, the reference side it shares with the
// cells of its group whose `metrics` block agrees (reference_side.h), and per method the
// streams its frames continue (temporal error, the sequence metrics' test streams, both
// against the reference and against `full` at the methods' sampling rate). Cell::measure
// (cell_metrics.cpp) is the step.
#pragma once
#include <memory>
#include <vector>

#include "sim/core/image.h"
#include "sim/core/scratch_pool.h"
#include "sim/metrics/metrics.h"
#include "sim/metrics/registry.h"

namespace fovsim {

struct RefSide;

// What a cell uses only while it processes a frame, lent from its pass's pool (CellWorkspaces,
// sim/core/scratch_pool.h) for Cell::process: as many exist as cells ran at once (at most the
// threads: the engine isolates each cell's frame), not one per cell. The reference side's floor
// borrows one too (its `scratch` prepares the same reference as the cells').
struct CellWorkspace {
  // compute_metrics' preparations against the reference and against `full` at the methods'
  // sampling rate (checked against the pixels on every call: never stale).
  MetricsScratch scratch, fl_scratch;
  Image out_display;  // the method's tone-mapped image
};
using CellWorkspaces = ScratchPool<CellWorkspace>;

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
  // The reference side of the sequence metrics and the foveation-loss reference, shared with
  // the other cells of the group whose `metrics` block is the same (made by
  // share_reference_sides before the first frame): its first method's (MethodRun::side; the
  // methods' sides differ only in the TAA of the foveation-loss reference).
  RefSide* side = nullptr;
};

}  // namespace fovsim
