// The cost model's view of a method (sim/cost/passes.cpp): the passes it and its lighting
// strategy declare.
#pragma once

namespace fovsim {

// What a method and its lighting strategy declare to the cost model (sim/cost/passes.cpp), so
// it never infers a pipeline from names or counters: the method's pipeline (its declaration,
// MethodCost::passes in method_cost.h), the passes its strategy adds
// (LightingStrategy::declare_passes) and the shared work it uses. Built by declared_passes
// (factory.h). Every flag off: deferred shading of the method's samples at the G-buffer.
struct CostPasses {
  // The method's pipeline.
  // Shades every pixel (full): without a shaded_samples counter it shades W x H, and is the
  // unfoveated pipeline the calibration tables and `trace.on_invalid = full` compare with.
  bool full_resolution = false;
  // Shades the direct light at every pixel and the indirect light at its own samples (flc:
  // direct_shaded_samples, when counted, are its shaded samples).
  bool direct_at_every_pixel = false;
  // A forward renderer (fvrs, Franke et al. 2021 §8.4): every rasterised fragment is shaded.
  bool forward_shading = false;
  // Shades a reduced buffer and maps it back to the screen (kfr, rmfr, the baselines): the
  // inverse-map pass `pass2`.
  bool inverse_map = false;
  // Reprojects the previous frame with push-pull hole filling and a confidence map (twfr,
  // Franke et al. 2021 §4-§5): the `reproject` pass.
  bool reprojection = false;
  // Redraws only the pixels it marks (twfr): its G-buffer writes, SSAO and tone map cover the
  // pixels_redrawn, not the screen.
  bool redraws_marked_pixels = false;
  // Submits only the primitives foveated culling keeps (twfr, Franke et al. 2021 §6.1):
  // prims_submitted.
  bool culls_primitives = false;

  // Lighting: set by the strategy, own_vpls by a method that brings its own.
  // Uses the frame's reflective shadow maps and VPLs (shared work, charged once per method as
  // the rsm pass and its vpl_flops) when the scene has indirect light.
  bool frame_rsm = false;
  // Builds and counts its VPLs itself, even on a scene without indirect light (flc).
  bool own_vpls = false;
  bool importance = false;  // importance map + quasi-MH sampling (Yang et al. 2021 eqs. 3-9)
  bool culling = false;     // per-VPL contribution (Yang et al. 2021 eq. 14) + light culling
};

}  // namespace fovsim
