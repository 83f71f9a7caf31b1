// `fvrs`: foveated variable-rate / coarse pixel shading (Patney et al. 2016 as run in Franke et al.
// 2021 §8.4): shading rate 1x1 inside r1 = 10 deg, 2x2 to r2 = 20 deg, 4x4 beyond, chosen per 4x4
// screen tile from the eccentricity at its centre. Visibility stays full resolution (the
// G-buffer); each coarse pixel is shaded once at the sample next to its centre and that colour
// is broadcast. With edge_aware, a pixel whose surface differs from its coarse sample (other
// material, hit vs. miss, depth off by > 5 %, normals > ~25 deg apart) is shaded itself, as
// coarse pixel shading shades once per coarse pixel *per primitive*.
//
// Parameters: the declaration fvrs_params() at the end of this file (name, type, default,
// range, seed section, meaning); docs/methods.md and configs/README.md are generated from it.
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
  static constexpr const char* kMethod = "fvrs";
  bool edge_aware = true;  // pixels on another surface than their coarse sample shade themselves

  static const ParamTable<MappingSpec>& params_table();
  double density(const MappingView& v, double x, double y) const override;
  double expected_samples(const MappingView& v) const override;
  bool shades_whole_buffer() const override { return false; }
  FreeParam free_param() const override { return {"radius_scale", 1e-4, 1e3, nullptr}; }
  double& free_ref() override { return radius_scale; }
  void widen_keys(double k, Json& p) const override { widen_radius_keys(k, p); }
};

// fvrs (Patney et al. 2016 / Franke et al. 2021 §8.4): shading rate (coarse pixel edge 1, 2 or 4)
// of the 4x4 block whose top-left pixel is (bx*4, by*4), from the eccentricity at its centre.
int fvrs_rate(const FvrsGeometry& s, const MappingView& v, int bx, int by) {
  const double x0 = bx * 4.0, y0 = by * 4.0;
  const double cx = 0.5 * (x0 + std::min(x0 + 4.0, double(v.W)));
  const double cy = 0.5 * (y0 + std::min(y0 + 4.0, double(v.H)));
  const double e = v.ecc_deg(cx, cy);
  if (e < s.r1_eff()) return 1;
  if (e < s.r2_eff()) return 2;
  return 4;
}

class FvrsMethod final : public MappingMethod<FvrsGeometry> {
 public:
  using MappingMethod::MappingMethod;

  void render(const FrameContext& ctx, FrameOutput& out) override {
    const FvrsGeometry& s = frame_geometry(ctx, out);
    const GBuffer& gb = *ctx.gbuffer;
    const int W = gb.width, H = gb.height;
    const MappingView view = view_of(ctx);
    const int bw = (W + 3) / 4, bh = (H + 3) / 4;
    mask_.assign(gb.size(), 0);
    rep_.assign(gb.size(), 0);
    std::vector<double> extra_rows(size_t(bh), 0.0);
    // Per 4x4 tile: rate, coarse-pixel representative sample, edge-aware extra samples.
    parallel_rows(bh, [&](int by) {
      double extra = 0;
      for (int bx = 0; bx < bw; ++bx) {
        const int r = fvrs_rate(s, view, bx, by);
        const int xe = std::min(bx * 4 + 4, W), ye = std::min(by * 4 + 4, H);
        for (int cy = by * 4; cy < ye; cy += r)
          for (int cx = bx * 4; cx < xe; cx += r) {
            const int rx = std::min(cx + r / 2, xe - 1), ry = std::min(cy + r / 2, ye - 1);
            const size_t ri = size_t(ry) * size_t(W) + size_t(rx);
            mask_[ri] = 1;
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
    });
    double extra = 0;
    for (double e : extra_rows) extra += e;
    const double shaded = shade_buffer(ctx, gb, out.image, &mask_, out);
    if (out.image.width != W || out.image.height != H) out.image.resize(W, H, 3);
    // Broadcast each coarse pixel's colour (reads only shaded slots, writes only unshaded ones).
    parallel_rows(H, [&](int y) {
      for (int x = 0; x < W; ++x) {
        const size_t i = size_t(y) * size_t(W) + size_t(x);
        if (mask_[i]) continue;
        std::copy_n(&out.image.data[size_t(rep_[i]) * 3], 3, &out.image.data[i * 3]);
      }
    });
    set_counters(out, shaded, shaded, double(W) * H, shaded, double(W) * H, double(W) * H - shaded);
    out.counters.set(Counter::edge_samples, extra);
    if (ctx.want_debug) debug_density(ctx, s, out);
  }

 private:
  std::vector<uint8_t> mask_;
  std::vector<uint32_t> rep_;
};

double FvrsGeometry::density(const MappingView& v, double x, double y) const {
  int bx = std::clamp(int(std::floor(x / 4)), 0, std::max(0, (v.W - 1) / 4));
  int by = std::clamp(int(std::floor(y / 4)), 0, std::max(0, (v.H - 1) / 4));
  int r = fvrs_rate(*this, v, bx, by);
  return 1.0 / (r * r);
}

// Coarse pixels per 4x4 block (partial blocks at the screen edge count their coarse pixels
// that intersect the screen).
double FvrsGeometry::expected_samples(const MappingView& v) const {
  const int bw = (v.W + 3) / 4, bh = (v.H + 3) / 4;
  return sum_rows(bh, [&](int by) {
    double n = 0;
    for (int bx = 0; bx < bw; ++bx) {
      const int r = fvrs_rate(*this, v, bx, by);
      const int ex = std::min(4, v.W - bx * 4), ey = std::min(4, v.H - by * 4);
      n += double((ex + r - 1) / r) * double((ey + r - 1) / r);
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

std::unique_ptr<FoveationMethod> create_fvrs(Params& p) {
  return std::make_unique<FvrsMethod>(read_mapping_spec<FvrsGeometry>(p));
}

const std::vector<ParamInfo>& fvrs_params() {
  return FvrsGeometry::params_table().info();
}

}  // namespace fovsim
