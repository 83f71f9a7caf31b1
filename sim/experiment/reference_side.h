// The reference side of one frame's measurements (docs/architecture.md "Data flow of one
// frame", step 3 "Reference side"), once per group of cells whose `metrics` blocks agree: the
// sequence metrics' reference streams (FovVideoVDP's temporal window and pyramids of the
// reference), `full` at the methods' sampling rate (metrics.foveation_loss) with its own
// streams, and the reference's floor. Every cell sharing it only reads it while its methods are
// measured (in parallel); per cell remain the methods' test streams.
//
// At render.spp 1 with `full`'s default lighting, `full` *is* the shared reference
// (image_is_reference): the foveation-loss reference is then the reference itself, aliased
// (fl_ref points at the tone-mapped reference; no second image, no second set of streams), and
// every `<metric>_fl` sequence value is the plain one (the same test against the same frames).
#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "sim/experiment/cell_metrics.h"
#include "sim/experiment/phase_times.h"
#include "sim/experiment/shared_config.h"
#include "sim/foveation/frame.h"
#include "sim/foveation/method.h"
#include "sim/metrics/metrics.h"
#include "sim/metrics/registry.h"

namespace fovsim {

struct RefSide {
  std::string key;   // the resolved `metrics` block
  std::string file;  // the first cell's config file (location of the fl `full`'s Params)
  MetricsConfig mcfg, fl_mcfg;
  struct Seq {
    const MetricDecl* decl = nullptr;
    // Against the converged reference; against `full` at the methods' sampling rate (null when
    // aliased); `floor` scores that `full` against the converged reference (at_floor).
    std::unique_ptr<SequenceReference> ref, ref_fl;
    std::unique_ptr<SequenceTest> floor;
  };
  std::vector<Seq> seq;
  bool ready = false;
  bool video = true;  // consecutive frames at the refresh rate (describe_sequence_metrics)
  SequenceSetup setup;
  // The TAA of the foveation-loss reference: the method's (taa.h), so that `full` and the
  // method it is compared with end with the same post pass.
  TaaSettings taa;
  std::unique_ptr<FoveationMethod> fl_full;
  FrameOutput fl_fo;
  Image fl_display;
  const Image* fl_ref = nullptr;  // the foveation-loss reference: &fl_display or the reference
  int aliased = -1;               // -1 before the first frame; 1: fl_ref is the reference
  // The reference's floor: every metric of `full` at the methods' sampling rate against the
  // converged reference, per recorded frame (column -> frame -> value); summary `at_floor`
  // names the metrics a method cannot be told from it by (mark_reference_floor, summary.h).
  std::map<std::string, std::map<int, double>> floor_vals;
  int cells = 0;  // cells sharing it (memory estimate, manifest)

  const SequenceReference& ref_fl(size_t k) const {
    return seq[k].ref_fl ? *seq[k].ref_fl : *seq[k].ref;
  }
  bool fl_aliased() const { return aliased == 1; }

  // The sequence metrics' reference streams, made on the first frame.
  void begin(const Shared& sh);
  // Frame `fi`'s reference side: the streams pushed at the true gaze, then (foveation loss)
  // `full` at the methods' sampling rate, its streams and the floor (with a workspace from
  // `pool`). Phases go to `ph`.
  void frame(const Shared& sh, const Renderer& renderer, const FrameData& fd,
             const Image& ref_display, int fi, bool record, PhaseTimes& ph, CellWorkspaces& pool);
  // Forget the frame history before a non-contiguous frame.
  void reset();
};

}  // namespace fovsim
