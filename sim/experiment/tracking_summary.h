// Per-tracking-state means of a run with a `tracking` column (trace.on_invalid,
// docs/tracking.md), next to the saccade-phase means of the latency what-if (latency.h).
#pragma once
#include <string>
#include <vector>

#include "sim/experiment/table.h"

namespace fovsim {

// The tracking states of frames.csv's `tracking` column, in this order.
const std::vector<std::string>& tracking_states();

// Adds to every summary row, for each state s in tracking_states(): frames_<s> (the config's
// frames in that state) and, for every headline metric present in `frames` (est_ms_total,
// shaded_fraction and the registry's headline metrics; sequence-pooled metrics such as
// fvvdp_jod are left out: their value is pooled over a contiguous sequence), <metric>_<s>
// (mean over that state's finite values) and <metric>_<s>_ci95 (batch-means 95% half-width
// over those values in frame order, sim/core/stats.h: nan below 20 frames). The per-frame
// `tracking` text is dropped from the summary rows.
ResultTable summarize_tracking(const ResultTable& frames, const ResultTable& summary);

}  // namespace fovsim
