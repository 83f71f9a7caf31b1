#include "sim/foveation/density.h"

#include <algorithm>
#include <cmath>

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
  if (s.method == "kfr") {
    auto m = LogPolarMap::make(v.W, v.H, reduced_size(v.W, s.sigma), reduced_size(v.H, s.sigma),
                               v.gaze_px, s.kernel);
    return m.density(x, y);
  }
  if (s.method == "rmfr") {
    auto m = RectMap::make(v.W, v.H, reduced_size(v.W, s.sigma), reduced_size(v.H, s.sigma),
                           v.gaze_px, s.fx_pixels(v.W), s.fy_pixels(v.H));
    return m.density(x, y);
  }
  const double e = v.ecc_deg(x, y);
  if (s.method == "linear") return linear_probability(s, e);
  if (s.method == "fvrs") {
    int bx = std::clamp(int(std::floor(x / 4)), 0, std::max(0, (v.W - 1) / 4));
    int by = std::clamp(int(std::floor(y / 4)), 0, std::max(0, (v.H - 1) / 4));
    int r = fvrs_rate(s, v, bx, by);
    return 1.0 / (r * r);
  }
  // hyperbolic: the finest layer that covers the point within its eccentricity limit
  auto layers = hyperbolic_layers(s, v);
  for (auto& L : layers)
    if (L.w > 0 && e < L.ecc_limit && x >= L.x0 && x < L.x1 && y >= L.y0 && y < L.y1)
      return 1.0 / (L.s * L.s);
  return 1.0 / (s.s3 * s.s3);
}

namespace {
double kfr_count(const MappingSpec& s, const MappingView& v) {
  const int w = reduced_size(v.W, s.sigma), h = reduced_size(v.H, s.sigma);
  auto m = LogPolarMap::make(v.W, v.H, w, h, v.gaze_px, s.kernel);
  std::vector<double> rows(size_t(h), 0.0);
  parallel_rows(h, [&](int iv) {
    double n = 0;
    for (int iu = 0; iu < w; ++iu) {
      glm::dvec2 p = m.inverse(iu + 0.5, iv + 0.5);
      if (p.x >= 0 && p.y >= 0 && p.x < v.W && p.y < v.H) n += 1;
    }
    rows[size_t(iv)] = n;
  });
  double n = 0;
  for (double r : rows) n += r;
  return n;
}
}  // namespace

double expected_shaded_samples(const MappingSpec& s, const MappingView& v) {
  if (s.method == "kfr") return kfr_count(s, v);
  if (s.method == "rmfr") return double(reduced_size(v.W, s.sigma)) * reduced_size(v.H, s.sigma);
  if (s.method == "hyperbolic") {
    return hyperbolic_needed(s, v, hyperbolic_layers(s, v), nullptr);
  }
  if (s.method == "linear") {
    std::vector<double> rows(size_t(v.H), 0.0);
    parallel_rows(v.H, [&](int y) {
      double n = 0;
      for (int x = 0; x < v.W; ++x) {
        double e = v.ecc ? double((*v.ecc)[size_t(y) * size_t(v.W) + size_t(x)])
                         : v.ecc_deg(x + 0.5, y + 0.5);
        n += linear_probability(s, e);
      }
      rows[size_t(y)] = n;
    });
    double n = 0;
    for (double r : rows) n += r;
    return n;
  }
  // fvrs: coarse pixels per 4x4 block (partial blocks at the screen edge count their coarse
  // pixels that intersect the screen).
  const int bw = (v.W + 3) / 4, bh = (v.H + 3) / 4;
  std::vector<double> rows(size_t(bh), 0.0);
  parallel_rows(bh, [&](int by) {
    double n = 0;
    for (int bx = 0; bx < bw; ++bx) {
      const int r = fvrs_rate(s, v, bx, by);
      const int ex = std::min(4, v.W - bx * 4), ey = std::min(4, v.H - by * 4);
      n += double((ex + r - 1) / r) * double((ey + r - 1) / r);
    }
    rows[size_t(by)] = n;
  });
  double n = 0;
  for (double r : rows) n += r;
  return n;
}

bool solve_iso_budget(const MappingSpec& s, const MappingView& v, double target, MappingSpec& out,
                      double* achieved) {
  out = s;
  out.target_shaded_fraction = 0;
  const double total = double(v.W) * double(v.H);
  auto frac = [&](const MappingSpec& m) { return expected_shaded_samples(m, v) / total; };
  bool ok = true;
  if (s.method == "rmfr") {
    out.sigma = std::max(1.0, 1.0 / std::sqrt(target));  // S = sigma^2 (Ye et al. 2022 §3.2)
    ok = target <= 1.0;
  } else {
    // Monotone 1-D search on a log axis: kfr's fraction falls with sigma, the baselines'
    // rises with radius_scale.
    const bool is_kfr = s.method == "kfr";
    double lo = is_kfr ? 0.0 : std::log(1e-4), hi = is_kfr ? std::log(1e4) : std::log(1e3);
    auto set = [&](double t) {
      if (is_kfr)
        out.sigma = std::exp(t);
      else
        out.radius_scale = std::exp(t);
      return frac(out);
    };
    const double f_lo = set(lo), f_hi = set(hi);
    const double f_min = std::min(f_lo, f_hi), f_max = std::max(f_lo, f_hi);
    if (target >= f_max || target <= f_min) {
      ok = (target == f_max || target == f_min);
      const bool want_max = target >= f_max;
      set((f_lo > f_hi) == want_max ? lo : hi);
    } else {
      for (int it = 0; it < 36; ++it) {
        const double mid = 0.5 * (lo + hi);
        const double f = set(mid);
        const bool above = f > target;
        // kfr: too many samples -> larger sigma; baselines: too many -> smaller radius.
        if (above == is_kfr)
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
