// Analytic counters for each method (see the parameter table in analytic.h).
#include "sim/cost/analytic.h"

#include <algorithm>
#include <cmath>

#include "sim/core/error.h"
#include "sim/cost/passes.h"

namespace fovsim {

double fvrs_shaded_fraction(const Display& d, double gu, double gv, double r1, double r2) {
  if (d.width <= 0 || d.height <= 0) return 0;
  Camera cam = Camera::from_pose(d, glm::dvec3(0), glm::dquat(1, 0, 0, 0));
  glm::dvec3 g = gaze_dir_from_screen(d, gu, gv);
  const int nx = std::min(d.width, 256), ny = std::min(d.height, 256);
  double sum = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      double px = (i + 0.5) * d.width / nx, py = (j + 0.5) * d.height / ny;
      double e = cam.eccentricity_deg(px, py, g);
      sum += e < r1 ? 1.0 : (e < r2 ? 0.25 : 1.0 / 16.0);
    }
  return sum / (double(nx) * ny);
}

Counters analytic_counters(const std::string& method, const Json& params, const Workload& w,
                           const Display& d, const std::string& where) {
  if (!is_cost_method(method)) throw Error(where, "unknown method '" + method + "'");
  Params p(params.is_null() ? Json::object() : params, "", where);
  const double P = double(std::max(0, d.width)) * double(std::max(0, d.height));
  Counters c;
  auto shaded_frac_param = [&](double def) {
    double f = p.number("shaded_fraction", w.shaded_fraction >= 0 ? w.shaded_fraction : -1, Range::closed(-1, 1));
    return f >= 0 ? f : def;
  };
  if (method == "full") {
    c.set("shaded_samples", P);
    c.set("gbuffer_samples", P);
  } else if (has_mapping_pass2(method)) {
    double sigma = p.number("sigma", 1.8, Range::closed(1, 64));
    // KFR/RMFR: the w x h = (W/sigma) x (H/sigma) buffer is fully shaded (seed 004 eq. 2.x,
    // seed 003 §3.2); baselines at the same mean density (seed 003 §5.1) unless overridden.
    double buf = P / (sigma * sigma);
    double s = (method == "kfr" || method == "rmfr") ? buf : shaded_frac_param(1.0 / (sigma * sigma)) * P;
    c.set("shaded_samples", s);
    c.set("gbuffer_samples", s);
    c.set("buffer_pixels_allocated", buf);
    c.set("buffer_pixels_used", s);
    c.set("fullres_pixels", P);
    // Total taps of pass 2 (bilinear inverse map: 4 per full-resolution pixel).
    c.set("filter_taps", P * p.number("filter_taps_per_pixel", 4, Range::at_least(0)));
  } else if (method == "fvrs") {
    double f = shaded_frac_param(-1);
    if (f < 0)
      f = fvrs_shaded_fraction(d, p.number("gaze_u", 0.5, Range::closed(-1, 2)),
                               p.number("gaze_v", 0.5, Range::closed(-1, 2)),
                               p.number("r1", 10, Range::at_least(0)), p.number("r2", 20, Range::at_least(0)));
    c.set("shaded_samples", f * P);
    c.set("gbuffer_samples", P);
  } else if (method == "twfr") {
    double rf = p.number("redraw_fraction", w.twfr_redraw_fraction, Range::closed(0, 1));
    double pf = p.number("prims_fraction", w.twfr_prims_fraction, Range::closed(0, 1));
    double T = std::max(0.0, w.triangles) * w.submitted_fraction;
    c.set("shaded_samples", rf * P);
    c.set("gbuffer_samples", rf * P);
    c.set("pixels_redrawn", rf * P);
    c.set("reprojected_pixels", P);
    c.set("prims_submitted", pf * T);
    c.set("prims_culled", (1 - pf) * T);
  } else if (method == "flc") {
    double lights = std::max(1.0, w.lights);
    double total = w.rsm_res * w.rsm_res * lights;  // one VPL per RSM texel (seed 001 §3)
    double kept = std::min(total, p.number("vpl_budget", w.vpl_budget, Range::at_least(0)));
    double ns = w.importance_samples;
    double s = P * w.lpt_fraction;
    c.set("shaded_samples", s);
    c.set("gbuffer_samples", P);
    c.set("rsm_texels", total);
    c.set("vpls_total", total);
    c.set("vpls_kept", kept);
    c.set("importance_samples", ns);
    c.set("contribution_evals", total * ns);       // eq. 14 for every VPL and sample
    c.set("shaded_sample_vpls", s * kept / w.interleave);  // interleaved sampling (§6)
  }
  return c;
}

}  // namespace fovsim
