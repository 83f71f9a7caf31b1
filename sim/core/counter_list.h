// Every per-frame counter, declared once (docs/architecture.md "Cost model", "… a counter"): its
// frames.csv column name, unit, how it scales from the simulated resolution to the real display,
// and a doc line. Code writes `counters.set(Counter::shaded_samples, v)`, so a misspelt counter
// does not compile; the cost model (sim/cost/passes.cpp) and the row builder scale a counter by its
// declared Scale; docs/cost_model.md's counter table is generated from this list
// (`fovsim methods --markdown --counters`, checked by Docs.CounterTableMatchesDeclarations).
//
// A counter is one line: FOVSIM_COUNTER(name, unit, scale, doc). Scale:
//   Pixels     measured at the simulated resolution; x pixel_scale = (display W·H) / (simulated
//              W·H) at the real display (per-pixel work: samples, pixels, taps, screen rays)
//   Primitives triangles or sub-models: the same at any resolution
//   Fixed      independent of the display resolution (RSM texels, VPLs, importance samples,
//              flags, errors)
// An indexed counter (holes_mip) is a family written with an index: column holes_mip<k>.
#pragma once
#include <optional>
#include <string>
#include <string_view>

#define FOVSIM_COUNTERS(X)                                                                         \
  X(shaded_samples, "samples", Pixels,                                                             \
    "samples shaded by the method (frames.csv: scaled to the real display)")                       \
  X(gbuffer_samples, "samples", Pixels, "G-buffer samples read or written by the method's pass 1") \
  X(fullres_pixels, "pixels", Pixels,                                                              \
    "full-resolution pixels written by pass 2, composition or the screen passes (W·H)")            \
  X(buffer_pixels_allocated, "pixels", Pixels,                                                     \
    "pixels of the reduced buffer(s) the shading pass writes")                                     \
  X(buffer_pixels_used, "pixels", Pixels, "of those, pixels actually filled")                      \
  X(filter_taps, "taps", Pixels, "texel reads of reconstruction and filters (pass 2)")             \
  X(edge_samples, "samples", Pixels, "fvrs: extra samples from edge_aware")                        \
  X(direct_shaded_samples, "samples", Pixels, "flc: samples shaded with direct light (W·H)")       \
  X(primary_rays, "rays", Pixels, "primary rays traced by the renderer")                           \
  X(shadow_rays, "rays", Pixels, "shadow rays of direct shading")                                  \
  X(shaded_sample_vpls, "sample·VPLs", Pixels,                                                     \
    "Σ over shaded samples of the VPLs used (the indirect shading work)")                          \
  X(vpl_shadow_rays, "rays", Pixels, "VPL shadow rays of indirect shading (shading_visibility)")   \
  X(lp_texels, "texels", Pixels, "flc: texels of the log-polar light buffer")                      \
  X(lp_fallback_samples, "samples", Pixels, "flc: samples shaded at full rate as a fallback")      \
  X(pixels_redrawn, "pixels", Pixels, "twfr: pixels in the redraw map")                            \
  X(redraw_confidence_pixels, "pixels", Pixels, "twfr: redrawn because c ≤ ε")                     \
  X(fovea_pixels, "pixels", Pixels, "twfr: redrawn because in the fovea")                          \
  X(uncovered_pixels, "pixels", Pixels, "twfr: redrawn because nothing was reprojected")           \
  X(forced_pixels, "pixels", Pixels, "twfr: redrawn only because transparent")                     \
  X(dynamic_pixels, "pixels", Pixels, "twfr: reprojected pixels of dynamic objects")               \
  X(reproject_splats, "splats", Pixels, "twfr: previous-frame pixels splatted")                    \
  X(reprojected_pixels, "pixels", Pixels, "twfr: pixels receiving a depth-test-winning splat")     \
  X(fovea_splats_discarded, "splats", Pixels, "twfr: splats discarded in the new fovea")           \
  X(holes_filled, "pixels", Pixels, "twfr: pixels filled by push-pull")                            \
  X(holes_mip, "pixels", Pixels, "twfr: of those, filled at mip level k (column holes_mip<k>)")    \
  X(taa_pixels, "pixels", Pixels, "with taa: pixels that blended a reprojected history")           \
  X(motion_smoothed_pixels, "pixels", Pixels, "twfr with taa: pixels through motion smoothing")    \
  X(prims_submitted, "triangles", Primitives, "primitives submitted to the G-buffer pass")         \
  X(prims_culled, "triangles", Primitives, "primitives culled by the method")                      \
  X(prims_offscreen, "triangles", Primitives, "twfr: triangles of sub-models outside the view")    \
  X(prims_foveation_culled, "triangles", Primitives,                                               \
    "twfr: triangles of in-view sub-models culled by the redraw map")                              \
  X(submodels_submitted, "sub-models", Primitives, "twfr: sub-models drawn")                       \
  X(submodels_culled, "sub-models", Primitives, "twfr: sub-models culled (includes offscreen)")    \
  X(rsm_texels, "texels", Fixed, "texels of the frame's reflective shadow maps (shared work)")     \
  X(rsm_rays, "rays", Fixed, "rays traced to build the frame's RSMs")                              \
  X(vpls_total, "VPLs", Fixed, "VPLs of the frame")                                                \
  X(vpls_kept, "VPLs", Fixed, "VPLs the lighting strategy kept")                                   \
  X(importance_samples, "samples", Fixed, "flc: importance samples N_s")                           \
  X(halton_proposals, "samples", Fixed, "flc: Halton proposals of the quasi-MH chains (N_s·M)")    \
  X(contribution_evals, "evaluations", Fixed,                                                      \
    "per-VPL contribution evaluations (flc: VPLs × samples; fir: VPLs)")                           \
  X(blso_lookups, "lookups", Fixed, "flc: RSM lookups of the BLSO visibility")                     \
  X(visibility_rays, "rays", Fixed, "flc (exact), fir: visibility rays of VPL selection")          \
  X(lights, "lights", Fixed, "flc: lights of the scene")                                           \
  X(flc_rmse_fovea, "", Fixed, "flc: RMSE inside the fovea against the shared reference")          \
  X(flc_rmse_periphery, "", Fixed, "flc: RMSE outside the fovea")                                  \
  X(flc_tau, "", Fixed, "flc: (RMSE_p + 1e-6) / (RMSE_f + 1e-6)")                                  \
  X(cull_conflicts, "pixels", Fixed, "twfr: marked pixels on a culled sub-model (0)")              \
  X(twfr_restart, "0/1", Fixed, "twfr: 1 on a frame that redrew everything")

namespace fovsim {

enum class Counter : int {
#define FOVSIM_COUNTER_ID(name, unit, scale, doc) name,
  FOVSIM_COUNTERS(FOVSIM_COUNTER_ID)
#undef FOVSIM_COUNTER_ID
};
#define FOVSIM_COUNTER_ONE(name, unit, scale, doc) +1
inline constexpr int kCounterCount = 0 FOVSIM_COUNTERS(FOVSIM_COUNTER_ONE);
#undef FOVSIM_COUNTER_ONE

enum class CounterScale { Pixels, Primitives, Fixed };

struct CounterInfo {
  const char* name;  // frames.csv column (indexed counters: name + index)
  const char* unit;
  CounterScale scale;
  const char* doc;
};

inline const CounterInfo& counter_info(Counter c) {
  static const CounterInfo t[] = {
#define FOVSIM_COUNTER_INFO(name, unit, scale, doc) {#name, unit, CounterScale::scale, doc},
      FOVSIM_COUNTERS(FOVSIM_COUNTER_INFO)
#undef FOVSIM_COUNTER_INFO
  };
  return t[int(c)];
}
inline const char* counter_name(Counter c) {
  return counter_info(c).name;
}

// A counter and, for an indexed family (holes_mip), its index (-1: not indexed).
struct CounterKey {
  Counter id;
  int index = -1;
  std::string name() const {
    return index < 0 ? std::string(counter_name(id))
                     : std::string(counter_name(id)) + std::to_string(index);
  }
  bool operator==(const CounterKey& o) const { return id == o.id && index == o.index; }
};

// The indexed families (written with an index, never without).
inline bool counter_indexed(Counter c) {
  return c == Counter::holes_mip;
}

// The counters the row builders write themselves rather than copy from the method's counters
// (frames.csv / the analytic summary): shaded_samples (scaled to the display, with
// shaded_fraction beside it), prims_submitted (default: the scene's triangles) and prims_culled
// (default 0).
inline bool reported_by_row_builder(Counter c) {
  return c == Counter::shaded_samples || c == Counter::prims_submitted ||
         c == Counter::prims_culled;
}
// The counters a row holds at the real display's resolution: the row builder's own (above) and
// every counter that does not scale with pixels (Primitives, Fixed). The other Pixels counters
// stay at the simulated resolution in frames.csv.
inline bool at_display_resolution(Counter c) {
  return reported_by_row_builder(c) || counter_info(c).scale != CounterScale::Pixels;
}

// The key of a column name ("shaded_samples", "holes_mip3"); nullopt for a name no counter has.
std::optional<CounterKey> find_counter(std::string_view name);

// Factor that takes a counter measured at the simulated resolution to the real display:
// pixel_scale for Pixels counters, 1 for the others.
inline double display_scale(Counter c, double pixel_scale) {
  return counter_info(c).scale == CounterScale::Pixels ? pixel_scale : 1.0;
}

// The markdown table of every counter (docs/cost_model.md, between kCounterDocsBegin/End).
std::string counters_markdown();
inline constexpr const char* kCounterDocsBegin = "<!-- BEGIN GENERATED COUNTERS";
inline constexpr const char* kCounterDocsEnd = "<!-- END GENERATED COUNTERS -->";

}  // namespace fovsim
