// The cost model's view of a method (sim/cost/passes.cpp): its cost family and the passes it
// and its lighting strategy declare.
#pragma once

namespace fovsim {

// The pass structure a method's frames are charged for by the GPU cost model (method_list.h).
enum class CostFamily { Full, Mapping, Fvrs, Twfr, Flc };

// What a method and its lighting strategy declare to the cost model (sim/cost/passes.cpp), so
// it never infers a pipeline from names: the method's cost family (method_list.h), the passes
// its strategy adds (LightingStrategy::declare_passes) and the shared work it uses. Built by
// declared_passes (factory.h).
struct CostPasses {
  CostFamily family = CostFamily::Full;
  // Uses the frame's reflective shadow maps and VPLs (shared work, charged once per method as
  // the rsm pass and its vpl_flops) when the scene has indirect light.
  bool frame_rsm = false;
  bool own_vpls = false;    // builds VPLs even on a scene without indirect light (flc)
  bool importance = false;  // importance map + quasi-MH sampling (Yang et al. 2021 eqs. 3-9)
  bool culling = false;     // per-VPL contribution (Yang et al. 2021 eq. 14) + light culling
};

}  // namespace fovsim
