// A cell's manifest as it starts (status "running"; write_cell_outputs completes it), the
// fidelity record of its render.scale and the warnings its config earns (results/README.md
// "manifest.json").
#pragma once
#include <set>
#include <string>
#include <vector>

#include "sim/core/params.h"
#include "sim/experiment/engine.h"
#include "sim/experiment/shared_config.h"

namespace fovsim {

// UTC now, ISO 8601 ("2026-01-02T03:04:05Z").
std::string iso_now();

// The fidelity a run used and the bias the fidelity ladder (docs/fidelity.md, `fovsim
// fidelity` on the quickstart methods, top rung render.scale 0.5, 90 frames) measured for it:
// the largest |difference| of any method's mean from the top rung's. Rungs not measured say
// so; nothing is extrapolated.
Json fidelity_record(double scale, int stride, int spp, double display_ppd);

// Values that are valid but probably not what was meant (printed as warnings, recorded in
// the manifest): an angle in degrees below 1 (phi_f = 0.17 reads as radians), image frames
// that are not frames of the run, an implausible trace (trace_stats: a map's "unit": "rad" on
// degrees gives head speeds of hundreds of deg/s). `shared`: also the shared keys' warnings.
std::vector<std::string> config_warnings(const Json& doc, const Params& root, const Shared& sh,
                                         const std::set<int>& image_frames, bool shared);

// The manifest a cell starts with (status "running"; write_cell_outputs completes it).
Json cell_manifest(const CellJob& job, const Shared& sh, const Json& resolved,
                   const EngineOptions& opt);

}  // namespace fovsim
