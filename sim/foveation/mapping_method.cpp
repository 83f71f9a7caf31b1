#include "sim/foveation/mapping_method.h"

#include <cmath>

namespace fovsim {

std::vector<std::pair<std::string, double>> MappingMethodBase::param_columns() const {
  auto c = active_.columns();
  if (spec_.target_shaded_fraction() > 0) {
    c.push_back({"target_shaded_fraction", spec_.target_shaded_fraction()});
    c.push_back({"iso_achieved_fraction", achieved_});
  }
  return c;
}

MappingView MappingMethodBase::view_of(const FrameContext& ctx) {
  MappingView v;
  v.W = ctx.gbuffer->width;
  v.H = ctx.gbuffer->height;
  v.cam = ctx.camera;
  v.gaze_px = ctx.gaze_px;
  v.gaze_dir = ctx.gaze_dir;
  v.ecc = ctx.eccentricity;
  v.widen = ctx.widen;
  v.render_scale = ctx.render_scale;
  return v;
}

const MappingSpec& MappingMethodBase::resolve(const FrameContext& ctx, FrameOutput& out) {
  if (!(spec_.target_shaded_fraction() > 0)) return active_;
  const int W = ctx.gbuffer->width, H = ctx.gbuffer->height;
  if (W != res_w_ || H != res_h_ || ctx.camera->tan_half_h != res_tan_h_ ||
      ctx.camera->tan_half_v != res_tan_v_) {
    // Solve at the centre gaze (Ye et al. 2022 §5.1 fixes the theoretical speedup per method, not
    // per frame), with an eccentricity map for that gaze.
    MappingView v = MappingView::at(*ctx.camera, glm::dvec2(W * 0.5, H * 0.5));
    v.render_scale = ctx.render_scale;  // the tiles and layers render() uses
    std::vector<float> ecc = eccentricity_map(*ctx.camera, v.gaze_dir);
    v.ecc = &ecc;
    reachable_ = solve_iso_budget(spec_, v, spec_.target_shaded_fraction(), active_, &achieved_);
    res_w_ = W;
    res_h_ = H;
    res_tan_h_ = ctx.camera->tan_half_h;
    res_tan_v_ = ctx.camera->tan_half_v;
  }
  if (!reachable_) out.flags.push_back("iso_budget_unreachable");
  return active_;
}

void MappingMethodBase::set_counters(FrameOutput& out, double shaded, double gbuffer_samples,
                                     double allocated, double used, double fullres, double taps) {
  out.counters.set(Counter::shaded_samples, shaded);
  out.counters.set(Counter::gbuffer_samples, gbuffer_samples);
  out.counters.set(Counter::buffer_pixels_allocated, allocated);
  out.counters.set(Counter::buffer_pixels_used, used);
  out.counters.set(Counter::fullres_pixels, fullres);
  out.counters.set(Counter::filter_taps, taps);
}

void MappingMethodBase::debug_density(const FrameContext& ctx, const SamplingGeometry& g,
                                      FrameOutput& out) const {
  MappingView v = view_of(ctx);
  Image d(v.W, v.H, 1);
  g.density_image(v, d);
  out.debug.emplace_back("sample_density", std::move(d));
}

void MappingMethodBase::analytic_counters(const AnalyticFrame& f, Counters& c) const {
  mapping_analytic_counters(f, c);
}

const MethodCost& mapping_method_cost() {
  static const MethodCost m = [] {
    MethodCost d;
    d.passes.inverse_map = true;
    d.analytic_keys = {"shaded_fraction", "gaze_u", "gaze_v", "filter_taps_per_pixel"};
    return d;
  }();
  return m;
}

void mapping_analytic_counters(const AnalyticFrame& f, Counters& c) {
  const double P = f.pixels;
  const bool whole_buffer = f.geometry && f.geometry->geometry().shades_whole_buffer();
  const double r = whole_buffer ? f.geometry->geometry().buffer_reduction() : 1.0;
  const double buf = P / (r * r);
  const double s = whole_buffer ? buf : f.baseline_fraction(1.0, [&](double gu, double gv) {
    const Display& d = *f.display;
    Camera cam = Camera::from_pose(d, glm::dvec3(0), glm::dquat(1, 0, 0, 0));
    MappingView v = MappingView::at(cam, {gu * d.width, gv * d.height});
    return expected_shaded_samples(*f.geometry, v) / P;
  }) * P;
  c.set(Counter::shaded_samples, s);
  c.set(Counter::gbuffer_samples, s);
  c.set(Counter::buffer_pixels_allocated, whole_buffer ? buf : s);
  c.set(Counter::buffer_pixels_used, s);
  c.set(Counter::fullres_pixels, P);
  // Total taps of pass 2 (bilinear inverse map: 4 per full-resolution pixel).
  c.set(Counter::filter_taps, P * f.keys->number("filter_taps_per_pixel", 4, Range::at_least(0)));
}

double shade_buffer(const FrameContext& ctx, GBufferRef g, Image& col,
                    const std::vector<uint8_t>* used, FrameOutput& out, double weight) {
  Counters c;
  ctx.renderer->shade(g, ctx.camera->position, col, used ? used->data() : nullptr, &c);
  // The scene's indirect light with the method's lighting strategy, at the same samples.
  if (ctx.lighting) ctx.lighting->shade(ctx, g, used ? used->data() : nullptr, col, c);
  double n = 0;
  if (used) {
    for (uint8_t b : *used) n += b;
  } else {
    n = double(g.size());
  }
  for (auto& e : c.entries())
    if (!(e.key == CounterKey{Counter::shaded_samples}))
      out.counters.add(e.key, counter_info(e.key.id).scale == CounterScale::Pixels && weight != 1.0
                                  ? e.value * weight
                                  : e.value);
  return n;
}

}  // namespace fovsim
