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

std::vector<HyperLayer> hyperbolic_layers(const MappingSpec& s, const MappingView& v) {
  std::vector<HyperLayer> out;
  const double max_px = 4.0 * (v.W + v.H) + std::abs(v.gaze_px.x) + std::abs(v.gaze_px.y);
  auto ecc = [&](double x, double y) { return v.ecc_deg(x, y); };
  const double radii[2] = {s.r1_eff(), s.r2_eff()};
  const double sizes[3] = {s.s1, s.s2, s.s3};
  for (int i = 0; i < 3; ++i) {
    HyperLayer L;
    L.s = sizes[i];
    if (i < 2) {
      const double R = radius_px_for_deg(ecc, v.gaze_px, radii[i], max_px);
      // Snap to whole pixels so an s = 1 layer samples pixel centres exactly.
      L.x0 = std::max(0.0, std::floor(v.gaze_px.x - R));
      L.y0 = std::max(0.0, std::floor(v.gaze_px.y - R));
      L.x1 = std::min(double(v.W), std::ceil(v.gaze_px.x + R));
      L.y1 = std::min(double(v.H), std::ceil(v.gaze_px.y + R));
      L.ecc_limit = radii[i];
    } else {
      L.x0 = 0, L.y0 = 0, L.x1 = v.W, L.y1 = v.H;
      L.ecc_limit = 1e9;
    }
    if (L.x1 > L.x0 && L.y1 > L.y0 && (i == 2 || L.ecc_limit > 0)) {
      L.w = std::max(1, int(std::ceil((L.x1 - L.x0) / L.s - 1e-9)));
      L.h = std::max(1, int(std::ceil((L.y1 - L.y0) / L.s - 1e-9)));
    }
    out.push_back(L);
  }
  return out;
}

void hyper_effective_weights(const MappingSpec& s, const std::vector<HyperLayer>& layers, double px,
                             double py, double e, float eff[3]) {
  float rem = 1.f;
  for (int i = 0; i < 3; ++i) {
    const HyperLayer& L = layers[size_t(i)];
    float w = 0.f;
    if (L.w > 0 && px >= L.x0 && px < L.x1 && py >= L.y0 && py < L.y1)
      w = i == 2 ? 1.f : hyper_weight(e, L.ecc_limit, std::min(s.blend_deg, L.ecc_limit));
    if (i == 2) w = 1.f;  // the outer layer covers the screen
    eff[i] = rem * w;
    rem *= 1.f - w;
  }
}

double hyperbolic_needed(const MappingSpec& s, const MappingView& v,
                         const std::vector<HyperLayer>& layers, std::vector<uint8_t>* masks) {
  std::vector<uint8_t> local[3];
  std::vector<uint8_t>* m = masks ? masks : local;
  for (size_t i = 0; i < 3; ++i)
    m[i].assign(size_t(std::max(layers[i].w, 0)) * size_t(std::max(layers[i].h, 0)), 0);
  // Serial: footprints of neighbouring pixels overlap (no write races); ~W*H cheap steps.
  for (int y = 0; y < v.H; ++y)
    for (int x = 0; x < v.W; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      const double e =
          v.ecc ? double((*v.ecc)[size_t(y) * size_t(v.W) + size_t(x)]) : v.ecc_deg(px, py);
      float eff[3];
      hyper_effective_weights(s, layers, px, py, e, eff);
      for (size_t i = 0; i < 3; ++i) {
        const HyperLayer& L = layers[i];
        if (eff[i] <= 0.f || L.w <= 0) continue;
        // The bilinear taps of mapping.cpp's bilinear() at ((px - x0)/s, (py - y0)/s).
        const double fx = (px - L.x0) / L.s - 0.5, fy = (py - L.y0) / L.s - 0.5;
        const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) {
            const int lx = std::clamp(x0 + dx, 0, L.w - 1), ly = std::clamp(y0 + dy, 0, L.h - 1);
            m[i][size_t(ly) * size_t(L.w) + size_t(lx)] = 1;
          }
      }
    }
  double n = 0;
  for (size_t i = 0; i < 3; ++i)
    for (uint8_t b : m[i]) n += b;
  return n;
}

double linear_probability(const MappingSpec& s, double e) {
  const double r1 = s.r1_eff(), r2 = s.r2_eff();
  if (!(e > r1)) return 1.0;
  if (!(e < r2)) return s.p_min;
  return 1.0 - (1.0 - s.p_min) * (e - r1) / (r2 - r1);
}

int fvrs_rate(const MappingSpec& s, const MappingView& v, int bx, int by) {
  const double x0 = bx * 4.0, y0 = by * 4.0;
  const double cx = 0.5 * (x0 + std::min(x0 + 4.0, double(v.W)));
  const double cy = 0.5 * (y0 + std::min(y0 + 4.0, double(v.H)));
  const double e = v.ecc_deg(cx, cy);
  if (e < s.r1_eff()) return 1;
  if (e < s.r2_eff()) return 2;
  return 4;
}

double sample_density(const MappingSpec& s, const MappingView& v, double x, double y) {
  return s.geometry->density(s, v, x, y);
}

void density_image(const MappingSpec& s, const MappingView& v, Image& d) {
  d = Image(v.W, v.H, 1);
  if (s.geometry->density_image) {
    s.geometry->density_image(s, v, d);
    return;
  }
  parallel_rows(v.H, [&](int y) {
    for (int x = 0; x < v.W; ++x) d.at(x, y)[0] = float(sample_density(s, v, x + 0.5, y + 0.5));
  });
}

double expected_shaded_samples(const MappingSpec& s, const MappingView& v) {
  return s.geometry->expected_samples(s, v);
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
  out.target_shaded_fraction = 0;
  const double total = double(v.W) * double(v.H);
  auto frac = [&](const MappingSpec& m) { return expected_shaded_samples(m, v) / total; };
  bool ok = true;
  const SamplingGeometry& g = *s.geometry;
  double MappingSpec::*free = g.free_param;
  if (g.free_closed_form) {
    ok = g.free_closed_form(target, &(out.*free));
  } else {
    // Monotone 1-D search on a log axis of the free parameter (kfr's fraction falls with
    // sigma, the baselines' rises with radius_scale: the direction is read off the ends).
    double lo = std::log(g.free_lo), hi = std::log(g.free_hi);
    auto set = [&](double t) {
      out.*free = std::exp(t);
      return frac(out);
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
  if (achieved) *achieved = frac(out);
  return ok;
}

}  // namespace fovsim
