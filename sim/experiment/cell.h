// One cell of a reference group (docs/architecture.md "Data flow of one frame", step 4): its
// methods, and one small part per concern — its measurements (cell_metrics.h), cost side
// (cell_rows.h), images (cell_images.h), latency what-if (cell_latency.h), method memo
// (cell_memo.h), tracking-loss swap (cell_tracking.h) and --target state — and the frames it
// accumulated. Cell::process is one frame of the cell; each step lives in the file of its
// concern (cell.cpp: parse, process, step_method; cell_metrics.cpp: measure; cell_images.cpp:
// queue_method_images; cell_rows.cpp: build_rows; cell_memo.cpp: replay_method, record_frame,
// memo_images).
#pragma once
#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "sim/core/watchdog.h"
#include "sim/experiment/cell_images.h"
#include "sim/experiment/cell_latency.h"
#include "sim/experiment/cell_memo.h"
#include "sim/experiment/cell_metrics.h"
#include "sim/experiment/cell_rows.h"
#include "sim/experiment/cell_tracking.h"
#include "sim/experiment/engine.h"
#include "sim/experiment/gaze_source.h"
#include "sim/experiment/phase_times.h"
#include "sim/experiment/run_config.h"
#include "sim/experiment/shared_config.h"
#include "sim/experiment/table.h"
#include "sim/foveation/frame.h"
#include "sim/foveation/method.h"

namespace fovsim {

// One method entry of a cell.
struct MethodRun {
  std::string label;
  std::string stem;  // safe_file_name(label): the only form of the label used in file names
  std::string method;
  std::unique_ptr<FoveationMethod> impl;
  TrackingSwap tracking;  // trace.on_invalid = full: `full` rendered while lost
  MethodStreams streams;  // its history in the cell's metrics
  FrameOutput fo;         // reused every frame (its image keeps its storage)
  MethodMemoState memo;   // replayed or recorded (method_memo.h)
  // Its reference side (reference_side.h): the cell's `metrics` block with the foveation-loss
  // reference made with its TAA settings (set by share_reference_sides).
  RefSide* side = nullptr;
};

// --target (intervals.h): each cell stops on its own once its targets hold, so its frames do
// not depend on the other cells of its group (sweep batches and shards give the same cell).
struct CellTarget {
  bool stopped = false, met = false;
  int used = 0, warmup = 0;  // recorded and warm-up frames evaluated
};

struct Cell {
  const CellJob* job = nullptr;
  std::string name;
  std::vector<MethodRun> methods;
  uint32_t channels = 0;  // the G-buffer channels its methods need
  CellMetrics metric;
  CellCost cost;
  CellImages images;
  CellLatency latency;               // the latency what-if (docs/latency.md)
  std::unique_ptr<GazeSource> gaze;  // the gaze each method sees (made by parse_group)
  OutputsBlock outputs;              // the `outputs` block as read (run_config.h)
  bool print_table = false;
  CellTarget target;
  Json manifest;
  std::vector<std::string> warnings;  // config_warnings(): manifest "warnings", printed by the CLI
  Watchdog* watchdog = nullptr;       // a method's frame taking far longer than its previous frames
  size_t watchdog_slot = 0;
  // What the frames accumulate.
  std::set<std::string> flags_seen;
  ResultTable frames;
  double cell_ms = 0;
  PhaseTimes phases;  // manifest "phases" (phase_times.h)

  // The cell's own keys (per_cell_keys): methods, metrics, gpus, budget, workload, outputs,
  // latency.
  void parse(Params& root, const std::string& models, bool default_print);

  // What every stage of one frame of this cell reads (process() below).
  struct FrameIn {
    const Shared& sh;
    const FrameData& fd;
    const Image& ref_display;  // the reference, tone-mapped: every row is measured against it
    CellWorkspace& ws;         // lent for this frame (cell_metrics.h)
    int fi;
    double ref_ms;
    bool record;       // false: a warm-up frame (state advances, no rows, no images)
    bool want_images;  // this frame is one of outputs.image_frames
    std::string img_dir;
    SceneFeatures features;
  };
  // What step_method produced for one method on one frame.
  struct Step {
    double lat_ms = 0;        // the end-to-end latency the method's gaze had (latency what-if)
    double sim_ms = 0;        // wall time of the method and its lighting
    std::string cost_method;  // the method costed (`full` while trace.on_invalid = full swaps)
    const FoveationMethod* impl = nullptr;  // the method that rendered (its declared passes)
    const Image* linear = nullptr;          // its linear image (or the reference's)
  };

  // This cell's work on one frame: per method the gaze (GazeSource), step_method, measure,
  // its images and build_rows; the images are written together at the end of the frame.
  // `record` false: a warm-up frame under --target or frames.warmup.
  // `pool` lends the frame's workspace.
  void process(const Shared& sh, const Renderer& renderer, const FrameData& fd,
               const Image& ref_display, int fi, double ref_ms, bool record, CellWorkspaces& pool);

  // Method `mi` on this frame: its gaze, the method (or `full` while tracking is lost under
  // trace.on_invalid = full) with its lighting strategy, the frame's shared RSM counters, tone
  // mapping into in.ws.out_display.
  Step step_method(const FrameIn& in, size_t mi, FrameContext& ctx, PhaseClock& pc);

  // The metrics of in.ws.out_display (method `m`'s frame) against the reference, at the true gaze;
  // sequence metrics' pooled value and the metric of this frame alone (heat maps of the saved
  // frames into `heat`); with metrics.foveation_loss the same against `full` at the methods'
  // sampling rate.
  MetricValues measure(const FrameIn& in, MethodRun& m,
                       std::vector<std::pair<std::string, Image>>& heat);

  // The images of method `m` on a saved frame: display and linear image, error map, the
  // per-frame metrics' maps, sequence metrics' heat maps, the method's debug buffers.
  void queue_method_images(const FrameIn& in, MethodRun& m, const Image& lin,
                           std::vector<std::pair<std::string, Image>>& heat);

  // One ResultRow per GPU profile for method `mi` on this frame (results/README.md): the cost
  // estimate (its first GPU's total is the gaze source's feedback), parameter and lighting
  // columns, gaze, latency and tracking columns, counters, est_ms_*, metrics, timings.
  void build_rows(const FrameIn& in, size_t mi, const Step& st, const FrameContext& ctx,
                  const MetricValues& metrics);

  // The method memo's images of this frame: memoised methods' files written as stored, and the
  // files just written for the methods being recorded read back into their records.
  void memo_images(const FrameIn& in);
  // The method memo's record of method `m` on this frame: what build_rows reads and the images
  // queued for it (images.jobs from `queued` on).
  void record_frame(const FrameIn& in, MethodRun& m, const Step& st, const MetricValues& metrics,
                    size_t queued);
  // A memoised method on this frame: its gaze (the gaze source's state and the row's gaze
  // columns), the stored counters, metrics, flags and images, and build_rows as when computed.
  void replay_method(const FrameIn& in, size_t mi, FrameContext& ctx);

  // Forget the frame history (temporal methods, temporal_error) before a non-contiguous frame.
  void reset_temporal();
};

// The key of the reference side (RefSide) a cell shares: its resolved `metrics` block.
std::string side_key(const Cell& c);
// The TAA of method m's foveation-loss reference (its own; none without the foveation loss).
TaaSettings side_taa(const Cell& c, const MethodRun& m);
// The key of method m's reference side: the cell's plus the TAA of its foveation-loss reference.
std::string method_side_key(const Cell& c, const MethodRun& m);

}  // namespace fovsim
