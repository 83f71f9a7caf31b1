// `flc` method extras for benchmarks and drivers (the method itself is created by the factory).
#pragma once
#include "sim/foveation/method.h"

namespace fovsim {

// Wall-clock time (ms) of each stage of the last render() of an `flc` method, split like the
// seed's Table 2. Not written to frames.csv (timings are not deterministic).
struct FlcStageTimes {
  double rsm = 0;           // RSMs + VPL generation (S-1, S-2)
  double ground_truth = 0;  // shading with all VPLs (0 when cached)
  double importance = 0;    // importance map (§4.1)
  double sampling = 0;      // Halton + Alg. 1 (§4.2)
  double contribution = 0;  // eq. 14 with visibility (§5)
  double culling = 0;       // stochastic culling (§5)
  double shading = 0;       // indirect shading with the kept VPLs (S-7, §6)
  double compose = 0;       // direct + indirect, tau, history
  double total() const {
    return rsm + ground_truth + importance + sampling + contribution + culling + shading + compose;
  }
};
// nullptr when `m` is not an flc method.
const FlcStageTimes* flc_stage_times(const FoveationMethod& m);
// Drops the cached ground-truth images (benchmarks timing the ground truth).
void flc_clear_ground_truth_cache();

}  // namespace fovsim
