// Common plumbing of the mapping methods and baselines: a base class that holds the
// MappingSpec, resolves an iso-budget target once per screen size, reports param_columns,
// and helpers for counters and debug buffers.
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
  std::string name() const override { return spec_.method; }
  uint32_t required_channels() const override { return kShadingChannels; }
  // The spec's columns with the free parameter as resolved (iso-budget), plus
  // iso_achieved_fraction when a target was given.
  std::vector<std::pair<std::string, double>> param_columns() const override;
  std::vector<std::pair<std::string, std::string>> text_param_columns() const override {
    return active_.text_columns();
  }
  const MappingSpec& active_spec() const { return active_; }
  const MappingSpec* mapping_spec() const override { return &active_; }

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
  void debug_density(const FrameContext& ctx, const MappingSpec& s, FrameOutput& out) const;

  MappingSpec spec_;    // as configured
  MappingSpec active_;  // as rendered (free parameter resolved)
  int res_w_ = -1, res_h_ = -1;
  double res_tan_h_ = 0, res_tan_v_ = 0;
  double achieved_ = -1;
  bool reachable_ = true;
};

// The spec a mapping method renders a frame with under tracking loss (FrameContext::widen,
// docs/tracking.md): for k = ctx.widen > 1, kfr's and rmfr's reduced buffer grows by k per
// axis, sigma' = max(1, sigma / k) (Meng et al. 2018 eq. 2.8 and Ye et al. 2022 §3.2: every
// sampling rate of the map scales with 1 / sigma, so a region sampled at least at a given
// rate grows), and rmfr's foveal extents grow, f' = k f (Ye et al. 2022 eq. 4: as f grows the
// map tends to the uniform 1 / sigma). Returns `s` itself when k <= 1 or for other methods
// (the baselines widen through the eccentricity map); else fills and returns `tmp`.
const MappingSpec& widened_spec(const MappingSpec& s, double k, MappingSpec& tmp);
// sigma' = max(1, sigma / k) for k > 1, sigma itself otherwise.
inline double widened_sigma(double sigma, double k) {
  return k > 1 ? std::max(1.0, sigma / k) : sigma;
}

// Shades the used slots of a gathered buffer (a G-buffer or an index view of the frame's) with the
// frame's renderer (direct light) and the method's lighting strategy (indirect light, when the
// scene has VPLs); returns the number of shaded samples (the renderer's shaded_samples counter when
// it reports one) and merges the renderer's other counters (shadow_rays, ...) into out.counters.
double shade_buffer(const FrameContext& ctx, GBufferRef g, Image& col,
                    const std::vector<uint8_t>* used, FrameOutput& out);

// Uniform [0,1) from (seed, frame, index): thread-count independent per-pixel randomness.
inline double hash01(uint64_t seed, uint64_t frame, uint64_t i) {
  uint64_t h = splitmix64(seed ^ splitmix64(frame + 0x9e3779b97f4a7c15ull) ^
                          splitmix64(i * 0xd1b54a32d192ed03ull + 1));
  return double(h >> 11) * (1.0 / 9007199254740992.0);
}

}  // namespace fovsim
