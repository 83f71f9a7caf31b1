// Parameters and sampling geometry of the image-mapping methods (kfr, rmfr) and the baselines
// (hyperbolic, linear, fvrs). MappingSpec holds the values; each method's own file declares
// which of them it reads (its ParamTable<MappingSpec>: keys, defaults, ranges, docs, columns)
// and its SamplingGeometry (density at a pixel, expected samples, the iso-budget's free
// parameter). Shared by the methods, the analytic density (`fovsim density`), the analytic
// counters of `predict` and the iso-budget solver, none of which name a method.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "sim/core/image.h"
#include "sim/core/param_info.h"
#include "sim/core/params.h"
#include "sim/foveation/mapping.h"

namespace fovsim {

struct MappingSpec;
struct MappingView;  // density.h

// The sampling geometry of one mapping method, defined in the method's file (kfr.cpp, ...).
// Adding a mapping method: its file defines a SamplingGeometry and a ParamTable<MappingSpec>
// (plus any MappingSpec fields it needs) and a line in method_list.h.
struct SamplingGeometry {
  const char* method;
  const ParamTable<MappingSpec>& (*params)();  // the keys it reads
  // Shading samples per screen pixel at screen point (x, y).
  double (*density)(const MappingSpec& s, const MappingView& v, double x, double y);
  // Density at every pixel centre into d (v.W x v.H, 1 channel); nullptr: density() per pixel.
  void (*density_image)(const MappingSpec& s, const MappingView& v, Image& d);
  // Samples the render pass shades for this view (exact, or the expected value).
  double (*expected_samples)(const MappingSpec& s, const MappingView& v);
  // True when a whole (W / sigma) x (H / sigma) buffer is allocated and shaded (kfr, rmfr):
  // the analytic counters then charge the buffer, else the expected samples.
  bool shades_whole_buffer;
  // Iso-budget (Ye et al. 2022 §5.1): the member the solver varies, and its search interval
  // (searched on a log axis; the shaded fraction is monotone in it).
  double MappingSpec::*free_param;
  double free_lo, free_hi;
  // Closed form of the free parameter for a target fraction, or nullptr (search). Returns
  // false when the target is out of reach (the value is then the closest reachable one).
  bool (*free_closed_form)(double target, double* value);
};

struct MappingSpec {
  std::string method = "kfr";                  // the geometry's method name
  const SamplingGeometry* geometry = nullptr;  // set by read_mapping_spec
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
  double target_shaded_fraction = 0;  // > 0: iso-budget, solve the free parameter for it

  double fx_pixels(int W) const { return fx_px > 0 ? fx_px : fx * W; }
  double fy_pixels(int H) const { return fy_px > 0 ? fy_px : fy * H; }
  double r1_eff() const { return r1 * radius_scale; }
  double r2_eff() const { return r2 * radius_scale; }

  // The spec of mapping method `method` as make_method reads it (tests; the methods read
  // theirs with read_mapping_spec); other methods are an error at `method`.
  static MappingSpec from_params(const std::string& method, Params& p);
  // Parameter columns for frames.csv (the geometry's table: sigma, alpha, fx, fy, r1, ...).
  std::vector<std::pair<std::string, double>> columns() const;
  // String parameters as written in the config (kfr: {"kernel", "power"}).
  std::vector<std::pair<std::string, std::string>> text_columns() const;
};

// Reads the keys of geometry `g` from p (unknown keys are left for Params::finish()).
MappingSpec read_mapping_spec(const SamplingGeometry& g, Params& p);

// Rows shared by the baselines, in column order: r1, r2 (columns: the radius-scaled values),
// radius_scale, with the r2 >= r1 rule. `source` cites the paper, r1_doc / r2_doc say what
// the radii bound.
void add_radius_rows(ParamTable<MappingSpec>& t, const char* source, const char* r1_doc,
                     const char* r2_doc);
// The optional target_shaded_fraction row (last: its column follows the others); `free`
// names the parameter the solver varies.
void add_target_row(ParamTable<MappingSpec>& t, const char* free);

}  // namespace fovsim
