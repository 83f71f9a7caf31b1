// `flc` method extras for benchmarks and drivers (the method itself is created by the factory).
#pragma once
#include "sim/foveation/method.h"

namespace fovsim {

// Wall-clock time (ms) of each stage of the last frame of an `flc` method, split like the
// FLC paper's Table 2. Not written to frames.csv (timings are not deterministic). RSMs, VPLs
// and the ground truth (all VPLs) are the shared frame data now (prepare_frame), not timed here.
struct FlcStageTimes {
  double importance = 0;    // importance map (§4.1)
  double sampling = 0;      // Halton + Alg. 1 (§4.2)
  double contribution = 0;  // eq. 14 with visibility (§5)
  double culling = 0;       // stochastic culling (§5)
  double shading = 0;       // indirect shading with the kept VPLs (S-7, §6)
  double compose = 0;       // direct + indirect, tau
  double total() const {
    return importance + sampling + contribution + culling + shading + compose;
  }
};
// nullptr when `m` is not an flc method.
const FlcStageTimes* flc_stage_times(const FoveationMethod& m);

}  // namespace fovsim
