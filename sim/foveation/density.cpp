#include "sim/foveation/density.h"

#include <algorithm>
#include <cmath>
#include <functional>

namespace fovsim {

MappingView MappingView::at(const Camera& cam, glm::dvec2 gaze_px) {
  MappingView v;
  v.W = cam.width;
  v.H = cam.height;
  v.cam = &cam;
  v.gaze_px = gaze_px;
  v.gaze_dir = cam.dir_head(gaze_px.x, gaze_px.y);
  return v;
}

double sample_density(const MappingSpec& s, const MappingView& v, double x, double y) {
  return s.geometry().density(v, x, y);
}

void density_image(const MappingSpec& s, const MappingView& v, Image& d) {
  d = Image(v.W, v.H, 1);
  s.geometry().density_image(v, d);
}

double expected_shaded_samples(const MappingSpec& s, const MappingView& v) {
  return s.geometry().expected_samples(v);
}

double sum_rows(int n, const std::function<double(int)>& row) {
  std::vector<double> rows(size_t(std::max(n, 0)), 0.0);
  parallel_rows(n, [&](int i) { rows[size_t(i)] = row(i); });
  double t = 0;
  for (double r : rows) t += r;  // in row order: the same sum at any thread count
  return t;
}

bool solve_iso_budget(const MappingSpec& s, const MappingView& v, double target, MappingSpec& out,
                      double* achieved) {
  out = s;
  SamplingGeometry& g = out.geometry();
  g.target_shaded_fraction = 0;
  const double total = double(v.W) * double(v.H);
  auto frac = [&] { return g.expected_samples(v) / total; };
  bool ok = true;
  const FreeParam fp = g.free_param();
  double& value = g.free_ref();
  if (fp.closed_form) {
    ok = fp.closed_form(target, &value);
  } else {
    // Monotone 1-D search on a log axis of the free parameter (kfr's fraction falls with
    // sigma, the baselines' rises with radius_scale: the direction is read off the ends).
    double lo = std::log(fp.lo), hi = std::log(fp.hi);
    auto set = [&](double t) {
      value = std::exp(t);
      return frac();
    };
    const double f_lo = set(lo), f_hi = set(hi);
    const double f_min = std::min(f_lo, f_hi), f_max = std::max(f_lo, f_hi);
    const bool falls = f_lo > f_hi;
    if (target >= f_max || target <= f_min) {
      ok = (target == f_max || target == f_min);
      const bool want_max = target >= f_max;
      set(falls == want_max ? lo : hi);
    } else {
      for (int it = 0; it < 36; ++it) {
        const double mid = 0.5 * (lo + hi);
        const double f = set(mid);
        const bool above = f > target;
        // Too many samples: move towards the end with fewer.
        if (above == falls)
          lo = mid;
        else
          hi = mid;
      }
      const double flo = set(lo), fhi = set(hi);
      set(std::abs(flo - target) <= std::abs(fhi - target) ? lo : hi);
    }
  }
  if (achieved) *achieved = frac();
  return ok;
}

}  // namespace fovsim
