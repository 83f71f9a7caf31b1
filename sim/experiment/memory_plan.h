// The memory plan of a reference group (docs/architecture.md "Data flow of one frame",
// "Memory"): the estimate of what the group, a reference side and a cell hold, and the split of
// the group's cells into passes under the budget. run_cells_impl (engine.cpp) makes the plan;
// each pass (run_pass) runs the frame loop over its cells.
#pragma once
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "sim/core/params.h"
#include "sim/experiment/engine.h"
#include "sim/experiment/shared_config.h"
#include "sim/foveation/taa.h"
#include "sim/metrics/frame_metric.h"
#include "sim/metrics/metrics.h"
#include "sim/metrics/registry.h"

namespace fovsim {

struct Cell;

// The memory estimate (docs/architecture.md "Memory"), bytes, from the simulated size, the
// cells' methods and metrics, and the sequence metrics' windows. Calibrated against
// `/usr/bin/time -v` peaks (bench/README.md "Memory"); an estimate, not a bound.
struct MemoryEstimator {
  const Shared& sh;
  bool video = true;  // sequence metrics run as a video (their temporal window is held)
  int threads = 1;    // cells running at once at most (the engine isolates each cell's frame)
  double pixels() const { return double(sh.sim_display.width) * double(sh.sim_display.height); }
  double image() const { return 12 * pixels(); }  // RGB float
  double plane() const { return 4 * pixels(); }
  // At render.spp 1 `full` is the reference: the foveation-loss reference is aliased, unless
  // it is made with a TAA pass (the method's, taa.h).
  bool aliased(const TaaSettings& taa) const { return sh.rs.spp <= 1 && !taa.enabled; }
  // Once per group: the frame's reference, direct light, G-buffer (up to ~16 floats a pixel)
  // and eccentricity, the tone-mapped reference, a saved frame's image jobs.
  double group() const { return 5 * image() + 17 * plane(); }
  // A MetricsScratch: its copy of the reference and every enabled per-frame metric's scratch
  // (frame_metric.h).
  double scratch(const MetricsConfig& m) const { return frame_metrics_scratch_bytes(m, pixels()); }
  // Of every sequence metric `m` enables: one reference stream, one test stream, one test
  // stream fed with another stream's frames (push_same, push_frames_of) and one push's lent
  // working buffers.
  struct Seq {
    double ref = 0, test = 0, borrowing = 0, scratch = 0;
  };
  Seq sequence(const MetricsConfig& m) const {
    SequenceSetup su;
    su.display = &sh.display;
    su.width = sh.sim_display.width;
    su.height = sh.sim_display.height;
    su.fps = video ? sh.display.refresh_hz : 0.0;
    su.config = &m;
    Seq s;
    for (auto& d : metric_registry())
      if (d.sequence && d.sequence->enabled(m)) {
        const double t = d.sequence->test_bytes ? d.sequence->test_bytes(su) : 0.0;
        if (d.sequence->reference_bytes) s.ref += d.sequence->reference_bytes(su);
        s.test += t;
        s.borrowing += d.sequence->borrowing_holds_nothing ? 0.0 : t;
        if (d.sequence->scratch_bytes) s.scratch += d.sequence->scratch_bytes(su);
      }
    return s;
  }
  // A reference side (RefSide): the streams against the reference; with the foveation loss the
  // floor's test streams (fed with the foveation-loss reference's frames) and, unless aliased,
  // `full`'s images, TAA history and streams. Its floor's metrics use a cell workspace.
  double side(const MetricsConfig& m, const TaaSettings& taa) const {
    const Seq q = sequence(m);
    double b = q.ref;
    if (m.foveation_loss) {
      b += q.borrowing;
      if (!aliased(taa))
        b += q.ref + 2 * image() +
             double(TaaPass::bytes(sh.sim_display.width, sh.sim_display.height, taa));
    }
    return b;
  }
  // A cell: per method its image and working buffers, its per-frame metrics' state
  // (temporal_error's planes), its test streams (the one against `full` fed with the first's
  // frames unless aliased), its TAA pass's history; rows.
  double cell(const Cell& c) const;
  // A cell's workspace (CellWorkspace, lent per frame; one per cell running at once): the
  // tone-mapped image, the metrics' scratch (twice with a foveation-loss reference of its own),
  // the sequence metrics' and the TAA pass's lent working buffers.
  double workspace(const Cell& c) const;
};

// How a group's cells are split into passes under the memory budget (run_cells_impl).
struct MemoryPlan {
  double budget = INFINITY;  // bytes
  std::string budget_from;
  double resident = 0;  // resident memory when the plan was made (scene, trace, cells parsed)
  double group = 0;
  std::vector<double> cell;                 // per cell
  std::vector<double> workspace;            // per cell: its workspace (MemoryEstimator)
  std::vector<std::vector<size_t>> passes;  // cell indices, in order
  int threads = 1;                          // cells running at once at most

  // The workspaces pass `p` holds: as many as its cells running at once, of the largest.
  double workspaces(size_t p) const;

  // The manifest's "memory" record of pass `p`.
  Json record(size_t p, size_t sides_in_pass, double side_bytes, double seq_ref,
              const std::string& fl_reference) const;
};

// The budget (--memory-budget, run.memory_gb, else 75% of MemAvailable) and the passes: cells
// in order, as many per pass as the estimate fits in what the budget leaves after the memory
// resident now and the group's shared data; at least one per pass.
MemoryPlan plan_memory(const EngineOptions& opt, const Shared& sh,
                       const std::vector<std::unique_ptr<Cell>>& cells, const MemoryEstimator& est);

}  // namespace fovsim
