// `fvrs`: foveated variable-rate / coarse pixel shading (Patney et al. 2016 as run in Franke et al.
// 2021 §8.4): shading rate 1x1 inside r1 = 10 deg, 2x2 to r2 = 20 deg, 4x4 beyond, chosen per 4x4
// screen tile from the eccentricity at its centre. Visibility stays full resolution (the
// G-buffer); each coarse pixel is shaded once at the sample next to its centre and that colour
// is broadcast. With edge_aware, a pixel whose surface differs from its coarse sample (other
// material, hit vs. miss, depth off by > 5 %, normals > ~25 deg apart) is shaded itself, as
// coarse pixel shading shades once per coarse pixel *per primitive*. Tiles and coarse pixels
// are display pixels, applied at render.scale times their size (FvrsGrid below).
//
// Parameters: the declaration fvrs_params() at the end of this file (name, type, default,
// range, seed section, meaning); docs/methods.md and configs/README.md are generated from it.
#include "sim/foveation/fvrs.h"

#include <algorithm>
#include <cmath>

#include "sim/core/param_table.h"
#include "sim/foveation/mapping_method.h"
#include "sim/foveation/methods.h"

namespace fovsim {
namespace {

inline bool same_surface(const GBuffer& g, size_t a, size_t b) {
  const bool ha = g.hit(a), hb = g.hit(b);
  if (ha != hb) return false;
  if (!ha) return true;
  if (g.has(kMaterial) && g.material[a] != g.material[b]) return false;
  if (std::abs(g.depth[a] - g.depth[b]) > 0.05f * std::max(g.depth[a], g.depth[b])) return false;
  if (g.has(kNormal) && glm::dot(g.normal[a], g.normal[b]) < 0.9f) return false;
  return true;
}

// fvrs's parameters and sampling geometry (density, samples, iso-budget free parameter); the
// keys are the table params_table() at the end of this file.
struct FvrsGeometry final : GeometryOf<FvrsGeometry>, RadialThresholds {
  static constexpr const char* kMethod = method_id::fvrs;
  bool edge_aware = false;  // (default: params_table()) pixels on another surface than their coarse
                            // sample shade themselves

  static const ParamTable<MappingSpec>& params_table();
  double density(const MappingView& v, double x, double y) const override;
  double expected_samples(const MappingView& v) const override;
  bool shades_whole_buffer() const override { return false; }
  FreeParam free_param() const override { return {"radius_scale", 1e-4, 1e3, nullptr}; }
  double& free_ref() override { return radius_scale; }
  void widen_keys(double k, Json& p) const override { widen_radius_keys(k, p); }
};

// Scale invariance (docs/fidelity.md "Scale invariance of the methods"): the 4x4 tiles and the
// coarse-pixel edges 1, 2 and 4 of Patney et al. 2016 / Franke et al. 2021 §8.4 are display
// pixels; at render.scale s they are max(1, round(s * size)) simulated pixels. A coarse pixel of
// r simulated pixels then stands for (r / s)^2 display pixels shaded at 1 / R^2 of the display
// rate (R its edge in display pixels): its weight (r / R)^2 is the display samples it counts for
// in units of the simulated pixel (the cost model multiplies by (display / simulated pixels)),
// so shaded_samples stays the display's count. 1 at s = 1.
struct FvrsGrid {
  int tile = 4;                  // tile edge, simulated pixels
  int rate[3] = {1, 2, 4};       // coarse-pixel edge per level, simulated pixels
  double weight[3] = {1, 1, 1};  // (rate / display rate)^2
  double edge_weight = 1;        // an edge-aware extra sample: s (edges are lines)
  bool rounded = false;          // a tile or coarse rate is not s x its size
  static constexpr int kDisplayRate[3] = {1, 2, 4};
  static constexpr int kDisplayTile = 4;
};

FvrsGrid fvrs_grid(double s) {
  FvrsGrid g;
  if (s == 1.0) return g;
  auto px = [s](int size) { return std::max(1, int(std::lround(s * size))); };
  g.tile = px(FvrsGrid::kDisplayTile);
  g.rounded = std::abs(g.tile - s * FvrsGrid::kDisplayTile) > 1e-9;
  for (int i = 0; i < 3; ++i) {
    const int R = FvrsGrid::kDisplayRate[i];
    g.rate[i] = std::min(px(R), g.tile);
    g.weight[i] = double(g.rate[i]) * g.rate[i] / (double(R) * R);
    // The 1x1 rate floors to a simulated pixel at every s < 1: that is the simulation's own
    // resolution, not a change of the method; the coarse rates are.
    if (i > 0) g.rounded = g.rounded || std::abs(g.rate[i] - s * R) > 1e-9;
  }
  g.edge_weight = s;
  return g;
}

// fvrs (Patney et al. 2016 / Franke et al. 2021 §8.4): shading level (0: 1x1, 1: 2x2, 2: 4x4
// display pixels) of the tile whose top-left pixel is (bx*t, by*t), from the eccentricity at its
// centre.
int fvrs_level(const FvrsGeometry& s, const MappingView& v, int t, int bx, int by) {
  const double x0 = double(bx) * t, y0 = double(by) * t;
  const double cx = 0.5 * (x0 + std::min(x0 + t, double(v.W)));
  const double cy = 0.5 * (y0 + std::min(y0 + t, double(v.H)));
  const double e = v.ecc_deg(cx, cy);
  if (e < s.r1_eff()) return 0;
  if (e < s.r2_eff()) return 1;
  return 2;
}

class FvrsMethod final : public MappingMethod<FvrsGeometry> {
 public:
  using MappingMethod::MappingMethod;

  // Its shaded samples from the rate bands at the gaze (fvrs_shaded_fraction, the radius-scaled
  // r1 and r2), or the analytic key shaded_fraction; every pixel is rasterised.
  void analytic_counters(const AnalyticFrame& f, Counters& c) const override {
    const FvrsGeometry* g = f.geometry ? &f.geometry->as<FvrsGeometry>() : nullptr;
    c.set(Counter::shaded_samples, f.baseline_fraction(1.0, [&](double gu, double gv) {
      return fvrs_shaded_fraction(*f.display, gu, gv, g->r1_eff(), g->r2_eff());
    }) * f.pixels);
    c.set(Counter::gbuffer_samples, f.pixels);
  }

  void render(const FrameContext& ctx, FrameOutput& out) override {
    const FvrsGeometry& s = frame_geometry(ctx, out);
    const GBuffer& gb = *ctx.gbuffer;
    const int W = gb.width, H = gb.height;
    const MappingView view = view_of(ctx);
    const FvrsGrid grid = fvrs_grid(view.render_scale);
    const int t = grid.tile;
    const int bw = (W + t - 1) / t, bh = (H + t - 1) / t;
    mask_.assign(gb.size(), 0);
    rep_.assign(gb.size(), 0);
    std::vector<double> extra_rows(size_t(bh), 0.0), weighted_rows(size_t(bh), 0.0);
    // Per tile: rate, coarse-pixel representative sample, edge-aware extra samples.
    parallel_rows(bh, [&](int by) {
      double extra = 0, weighted = 0;
      for (int bx = 0; bx < bw; ++bx) {
        const int level = fvrs_level(s, view, t, bx, by);
        const int r = grid.rate[level];
        const int xe = std::min(bx * t + t, W), ye = std::min(by * t + t, H);
        for (int cy = by * t; cy < ye; cy += r)
          for (int cx = bx * t; cx < xe; cx += r) {
            const int rx = std::min(cx + r / 2, xe - 1), ry = std::min(cy + r / 2, ye - 1);
            const size_t ri = size_t(ry) * size_t(W) + size_t(rx);
            mask_[ri] = 1;
            weighted += grid.weight[level];
            for (int y = cy; y < std::min(cy + r, ye); ++y)
              for (int x = cx; x < std::min(cx + r, xe); ++x) {
                const size_t i = size_t(y) * size_t(W) + size_t(x);
                rep_[i] = uint32_t(ri);
                if (i != ri && s.edge_aware && !same_surface(gb, i, ri)) {
                  mask_[i] = 1;
                  rep_[i] = uint32_t(i);
                  extra += 1;
                }
              }
          }
      }
      extra_rows[size_t(by)] = extra;
      weighted_rows[size_t(by)] = weighted;
    });
    double extra = 0, weighted = 0;
    for (size_t i = 0; i < extra_rows.size(); ++i) {
      extra += extra_rows[i];
      weighted += weighted_rows[i];
    }
    // Display-equivalent samples (FvrsGrid): the coarse pixels' weights, the edge extras' s.
    const double extra_w = extra * grid.edge_weight;
    weighted += extra_w;
    size_t n_mask = 0;
    for (uint8_t b : mask_) n_mask += b;
    const double shaded =
        shade_buffer(ctx, gb, out.image, &mask_, out, n_mask > 0 ? weighted / double(n_mask) : 1.0);
    const double shaded_w = view.render_scale == 1.0 ? shaded : weighted;
    if (out.image.width != W || out.image.height != H) out.image.resize(W, H, 3);
    // Broadcast each coarse pixel's colour (reads only shaded slots, writes only unshaded ones).
    parallel_rows(H, [&](int y) {
      for (int x = 0; x < W; ++x) {
        const size_t i = size_t(y) * size_t(W) + size_t(x);
        if (mask_[i]) continue;
        std::copy_n(&out.image.data[size_t(rep_[i]) * 3], 3, &out.image.data[i * 3]);
      }
    });
    set_counters(out, shaded_w, shaded_w, double(W) * H, shaded_w, double(W) * H,
                 double(W) * H - shaded_w);
    out.counters.set(Counter::edge_samples, view.render_scale == 1.0 ? extra : extra_w);
    if (grid.rounded) out.flags.push_back("fvrs_rate_rounded");
    if (ctx.want_debug) debug_density(ctx, s, out);
  }

 private:
  std::vector<uint8_t> mask_;
  std::vector<uint32_t> rep_;
};

// Display samples per pixel: 1 / R^2 of the tile's level, R in display pixels (at s = 1 the
// simulated coarse pixel; at s < 1 the rate the coarse pixel stands for, FvrsGrid).
double FvrsGeometry::density(const MappingView& v, double x, double y) const {
  const FvrsGrid g = fvrs_grid(v.render_scale);
  const int t = g.tile;
  int bx = std::clamp(int(std::floor(x / t)), 0, std::max(0, (v.W - 1) / t));
  int by = std::clamp(int(std::floor(y / t)), 0, std::max(0, (v.H - 1) / t));
  const int level = fvrs_level(*this, v, t, bx, by);
  const int r = g.rate[level];
  return g.weight[level] / (double(r) * r);
}

// Coarse pixels per tile, each with its weight (FvrsGrid; partial tiles at the screen edge count
// their coarse pixels that intersect the screen).
double FvrsGeometry::expected_samples(const MappingView& v) const {
  const FvrsGrid g = fvrs_grid(v.render_scale);
  const int t = g.tile;
  const int bw = (v.W + t - 1) / t, bh = (v.H + t - 1) / t;
  return sum_rows(bh, [&](int by) {
    double n = 0;
    for (int bx = 0; bx < bw; ++bx) {
      const int level = fvrs_level(*this, v, t, bx, by);
      const int r = g.rate[level];
      const int ex = std::min(t, v.W - bx * t), ey = std::min(t, v.H - by * t);
      n += double((ex + r - 1) / r) * double((ey + r - 1) / r) * g.weight[level];
    }
    return n;
  });
}

const ParamTable<MappingSpec>& FvrsGeometry::params_table() {
  using G = FvrsGeometry;
  static const ParamTable<MappingSpec> t = [] {
    ParamTable<MappingSpec> t;
    add_radius_rows<G>(t, "Franke et al. 2021 §8.4", "1x1 shading inside (deg)",
                       "2x2 inside, 4x4 beyond (deg)");
    t.boolean("edge_aware", true, field<G>(&G::edge_aware))
        .doc("Vaidyanathan 2014", "pixels of another surface shade themselves");
    add_target_row(t, "radius_scale");
    return t;
  }();
  return t;
}

}  // namespace

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
      // The share of its pixels a band shades: 1 / R^2 for coarse pixels of R x R display pixels.
      const int R = FvrsGrid::kDisplayRate[e < r1 ? 0 : (e < r2 ? 1 : 2)];
      sum += 1.0 / (double(R) * R);
    }
  return sum / (double(nx) * ny);
}

std::unique_ptr<FoveationMethod> create_fvrs(Params& p) {
  return std::make_unique<FvrsMethod>(read_mapping_spec<FvrsGeometry>(p));
}

const std::vector<ParamInfo>& fvrs_params() {
  return FvrsGeometry::params_table().info();
}

// A forward renderer at coarse shading rates (Franke et al. 2021 §8.4): no reduced buffer, no
// inverse map; the baselines' shaded fraction and gaze are analytic-only keys.
const MethodCost& fvrs_cost() {
  static const MethodCost m = [] {
    MethodCost d;
    d.passes.forward_shading = true;
    d.analytic_keys = {"shaded_fraction", "gaze_u", "gaze_v"};
    return d;
  }();
  return m;
}

}  // namespace fovsim
