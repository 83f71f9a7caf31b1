// Parameters of the image-mapping methods (kfr, rmfr) and the baselines (hyperbolic, linear,
// fvrs) in one struct, read from a method's JSON block with ranges and JSON paths. Shared by
// the methods, the analytic density (`fovsim density`) and the iso-budget solver.
// Every key is documented in docs/methods.md and in the table at the top of each method file.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "sim/core/params.h"
#include "sim/foveation/mapping.h"

namespace fovsim {

struct MappingSpec {
  std::string method = "kfr";  // kfr | rmfr | hyperbolic | linear | fvrs
  // kfr (Meng 2018 ch. 2) and rmfr (Ye et al. 2022 §3.2)
  double sigma = 1.8;       // W / w (= H / h)
  KernelFn kernel;          // kfr kernel K and alpha
  bool internal_aa = true;  // kfr §2.2.3 3x3 Gaussian on the peripheral part of the LP-buffer
  double internal_aa_start = 0.5;  // fraction of the LP-buffer width where "the right part" starts
  bool post_aa = true;             // kfr §2.3.2 eq. 2.14 Gaussian post filter
  double fx = 0.38, fy = 0.38;     // rmfr, as fractions of W / H ...
  double fx_px = 0, fy_px = 0;     // ... or in pixels when > 0 (keys fx_px / fy_px)
  // baselines (Ye et al. 2022 §5.1)
  double r1 = 10, r2 = 20;            // eccentricity thresholds, degrees
  double s1 = 1, s2 = 2, s3 = 12.35;  // hyperbolic layer pixel sizes
  double blend_deg = 1.0;     // hyperbolic: width of the smoothstep blend inside each layer edge
  double p_min = 0.047;       // linear: minimum sampling probability
  double radius_scale = 1.0;  // baselines: multiplies r1 and r2 (the iso-budget free parameter)
  bool edge_aware =
      true;           // fvrs: pixels on another surface than their coarse sample shade themselves
  uint64_t seed = 0;  // linear: stochastic sample pattern
  double target_shaded_fraction = 0;  // > 0: iso-budget, solve sigma / radius_scale for it

  double fx_pixels(int W) const { return fx_px > 0 ? fx_px : fx * W; }
  double fy_pixels(int H) const { return fy_px > 0 ? fy_px : fy * H; }
  double r1_eff() const { return r1 * radius_scale; }
  double r2_eff() const { return r2 * radius_scale; }

  // Reads the keys of `method` from p (unknown keys are left for Params::finish()).
  static MappingSpec from_params(const std::string& method, Params& p);
  // Parameter columns for frames.csv (sigma, alpha, kernel index, fx, fy, r1, ...).
  std::vector<std::pair<std::string, double>> columns() const;
  // String parameters as written in the config (kfr: {"kernel", "power"}).
  std::vector<std::pair<std::string, std::string>> text_columns() const;
};

bool is_mapping_method(const std::string& name);

}  // namespace fovsim
