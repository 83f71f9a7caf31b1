// A cell's outputs at the end of its pass (docs/architecture.md "Data flow of one frame", step 6
// "Outputs"): frames.csv, summary.csv/summary.json (means with 95% intervals, start-up frames
// left out), paired.csv, the manifest (status "complete" last); what the group's stages hand
// to them.
#pragma once
#include <string>

#include "sim/core/params.h"
#include "sim/experiment/engine.h"
#include "sim/experiment/frame_order.h"
#include "sim/experiment/method_memo.h"
#include "sim/experiment/phase_times.h"
#include "sim/experiment/reference_cache.h"
#include "sim/experiment/shared_config.h"
#include "sim/experiment/startup.h"
#include "sim/render/renderer.h"

namespace fovsim {

struct Cell;

// What the group-level stages hand to write_cell_outputs.
struct GroupOutputs {
  const EngineOptions& opt;
  const FrameOrder& order;
  const ReferenceCache* rcache;
  const std::string& no_cache_dir;
  const Renderer& renderer;
  const PhaseTimes& group_phases;
  PhaseClock outputs_start;  // when the outputs stage began
  int threads;
  const MethodMemo* memo;
  const Json& memory;  // the pass's manifest "memory" record (MemoryPlan::record)
};

// The start-up frames the cell's means leave out (startup.h): each method's declared warm-up,
// each stateful metric's settle time at the run's frame rate.
StartupPlan startup_plan(const Cell& c, const Shared& sh);

// One cell's outputs, written atomically with the manifest ("complete") last: frames.csv,
// summary.csv (means with intervals, reference floor, latency phases, tracking states),
// paired.csv with the fidelity's known bias, summary.json; the --target record.
CellResult write_cell_outputs(Cell& c, const Shared& sh, const GroupOutputs& g);

}  // namespace fovsim
