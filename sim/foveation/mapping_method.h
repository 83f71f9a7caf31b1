// Common plumbing of the mapping methods and baselines: a base class that holds the
// MappingSpec, resolves an iso-budget target once per screen size, reports param_columns,
// and helpers for counters and debug buffers; MappingMethod<G> hands render() the method's
// own geometry struct G for the frame (resolved, widened), once per frame.
#pragma once
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "sim/core/rng.h"
#include "sim/foveation/density.h"
#include "sim/foveation/method.h"

namespace fovsim {

class MappingMethodBase : public FoveationMethod {
 public:
  explicit MappingMethodBase(MappingSpec s) : spec_(std::move(s)), active_(spec_) {}
  std::string name() const override { return spec_.method(); }
  uint32_t required_channels() const override { return kShadingChannels; }
  // The spec's columns with the free parameter as resolved (iso-budget), plus
  // iso_achieved_fraction when a target was given.
  std::vector<std::pair<std::string, double>> param_columns() const override;
  std::vector<std::pair<std::string, std::string>> text_param_columns() const override {
    return active_.text_columns();
  }
  const MappingSpec& active_spec() const { return active_; }
  const MappingSpec* mapping_spec() const override { return &active_; }
  // Its cost (method_cost.h) from its geometry: mapping_analytic_counters, the geometry's budget
  // knob and widened keys.
  void analytic_counters(const AnalyticFrame& f, Counters& c) const override;
  BudgetKnob budget_knob(const AnalyticWorkload&) const override {
    return active_.geometry().budget_knob();
  }
  void widen_cost_keys(double k, Json& p) const override { active_.geometry().widen_keys(k, p); }
  TaaSettings taa() const override { return active_.geometry().taa; }

 protected:
  // Resolves target_shaded_fraction (if any) for this screen: solves the free parameter with
  // the gaze at the screen centre (so the setting does not change with gaze) once per
  // screen size and camera FOV. Returns the spec to render with.
  const MappingSpec& resolve(const FrameContext& ctx, FrameOutput& out);
  static MappingView view_of(const FrameContext& ctx);
  // Writes the counters every mapping method reports (see docs/methods.md).
  static void set_counters(FrameOutput& out, double shaded, double gbuffer_samples,
                           double allocated, double used, double fullres, double taps);
  // Appends a 1-channel "sample_density" debug image (samples per pixel, analytic).
  void debug_density(const FrameContext& ctx, const SamplingGeometry& g, FrameOutput& out) const;

  MappingSpec spec_;    // as configured
  MappingSpec active_;  // as rendered (free parameter resolved)
  int res_w_ = -1, res_h_ = -1;
  double res_tan_h_ = 0, res_tan_v_ = 0;
  double achieved_ = -1;
  bool reachable_ = true;
};

// A mapping method over its geometry struct G (its file's GeometryOf<G>).
template <class G>
class MappingMethod : public MappingMethodBase {
 public:
  using MappingMethodBase::MappingMethodBase;

 protected:
  // The geometry this frame renders with: the configured one with the iso-budget's free
  // parameter resolved (resolve()) and, under tracking loss (ctx.widen = k > 1,
  // docs/tracking.md), widened by G::widen. Plain data for the render loops.
  const G& frame_geometry(const FrameContext& ctx, FrameOutput& out) {
    const G& g = resolve(ctx, out).template as<G>();
    if (!(ctx.widen > 1)) return g;
    widened_ = g;
    widened_.G::widen(ctx.widen);
    return widened_;
  }

 private:
  G widened_;  // the geometry of a frame under tracking loss
};

// The cost declaration of the image-mapping methods and baselines (kfr, rmfr, rmfr_auto,
// hyperbolic, linear): deferred shading of the reduced buffer's samples, then the inverse map
// to the screen (pass2); the baselines' shaded fraction and gaze and every method's pass-2 taps
// per pixel are analytic-only keys (mapping_analytic_counters).
const MethodCost& mapping_method_cost();
// Their analytic counters: a whole (W / r) x (H / r) buffer (SamplingGeometry::buffer_reduction)
// for kfr and rmfr (Meng 2018 §2.2, Ye et al. 2022 §3.2), the expected samples of the layers or
// sample pattern at the gaze for the baselines (AnalyticFrame::baseline_fraction), and the
// pass-2 taps (key filter_taps_per_pixel, default 4: a bilinear inverse map).
void mapping_analytic_counters(const AnalyticFrame& f, Counters& c);

// sigma' = max(1, sigma / k) for k > 1, sigma itself otherwise.
inline double widened_sigma(double sigma, double k) {
  return k > 1 ? std::max(1.0, sigma / k) : sigma;
}

// Shades the used slots of a gathered buffer (a G-buffer or an index view of the frame's) with the
// frame's renderer (direct light) and the method's lighting strategy (indirect light, when the
// scene has VPLs); returns the number of shaded samples (the renderer's shaded_samples counter when
// it reports one) and merges the renderer's other counters (shadow_rays, ...) into out.counters.
// `weight` multiplies the merged per-pixel (CounterScale::Pixels) counters: the display-pixel
// work one simulated sample stands for, relative to a sample of a buffer that scales with the
// simulated resolution (a coarse pixel sized in display pixels at render.scale < 1 stands for
// fewer display samples than the pixel_scale the cost model multiplies by; fvrs, hyperbolic).
double shade_buffer(const FrameContext& ctx, GBufferRef g, Image& col,
                    const std::vector<uint8_t>* used, FrameOutput& out, double weight = 1.0);

// Uniform [0,1) from (seed, frame, index): thread-count independent per-pixel randomness.
inline double hash01(uint64_t seed, uint64_t frame, uint64_t i) {
  uint64_t h = splitmix64(seed ^ splitmix64(frame + 0x9e3779b97f4a7c15ull) ^
                          splitmix64(i * 0xd1b54a32d192ed03ull + 1));
  return double(h >> 11) * (1.0 / 9007199254740992.0);
}

}  // namespace fovsim
