// `twfr`: time-warped foveated rendering (Franke et al. 2021, §4-§8).
//
// Parameters: the declaration twfr_params() at the end of this file (name, type, default,
// range, seed section, meaning); docs/methods.md and configs/README.md are generated from it.
//
// Pipeline per frame (Fig. 2): forward reprojection of last frame's colour + world positions
// (twfr_reproject), push-pull hole filling (twfr_pushpull), confidence and redraw map
// (twfr_confidence), OR-mipmap + sub-model culling (twfr_cull), redraw shading only where
// marked (Renderer::shade with a mask over the shared full-resolution G-buffer: the redraw
// pass's G-buffer and shading are discarded outside the map, §6.1), composition, optional TAA /
// motion smoothing (§6.2). The first frame (and any reset) redraws everything.
#include "sim/foveation/twfr.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "sim/core/param_table.h"
#include "sim/foveation/methods.h"

namespace fovsim {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

bool finite_mat(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

}  // namespace

namespace {
// The declaration of every key (parsing, defaults, ranges, docs, columns). The confidence maths
// runs in float; the values as given (double) go to the CSV columns so a swept epsilon = 0.2
// prints as 0.2, not 0.200000003.
const ParamTable<TwfrParams>& twfr_table() {
  using T = TwfrParams;
  // A confidence parameter: kept as given (double) and as the float the maths uses.
  auto conf = [](double T::Given::*g, float twfr::ConfidenceParams::*c) {
    return std::make_pair(
        std::function<void(T&, const Json&)>([g, c](T& t, const Json& v) {
          t.given.*g = v.get<double>();
          t.conf.*c = float(v.get<double>());
        }),
        std::function<Json(const T&)>([g](const T& t) { return Json(t.given.*g); }));
  };
  auto row = [&](ParamTable<T>& t, const char* key, double def, Range r, double T::Given::*g,
                 float twfr::ConfidenceParams::*c) -> ParamTable<T>& {
    auto [set, get] = conf(g, c);
    return t.custom(key, ParamKind::Number, Json(def), r, set, get).column();
  };
  static const ParamTable<T> t = [&] {
    ParamTable<T> t;
    row(t, "epsilon", 0.2, Range::closed(0, 1), &T::Given::epsilon,
        &twfr::ConfidenceParams::epsilon)
        .doc("§5.2, §8.1", "confidence threshold: a pixel is redrawn iff c <= epsilon");
    row(t, "phi_f", 10.0, Range::closed(0, 180), &T::Given::phi_f, &twfr::ConfidenceParams::phi_f)
        .doc("§5.2", "fovea angle phi_F (c_e = 0 inside; reprojected splats discarded inside)")
        .shown("10", "[0, 180] deg");
    row(t, "phi_0", 30.0, Range::closed(0, 180), &T::Given::phi_0, &twfr::ConfidenceParams::phi_0)
        .doc("§5.2", "eccentricity fully in the periphery (c_e = 1 beyond)")
        .shown("30", "[phi_f, 180] deg");
    row(t, "A", 0.6, Range::above(0, 1), &T::Given::A, &twfr::ConfidenceParams::A)
        .doc("§5.2", "hole-size confidence c_s(m) = A^m");
    row(t, "D", 0.75, Range::above(0, 1), &T::Given::D, &twfr::ConfidenceParams::D)
        .doc("§7", "dynamic confidence c_d(t) = D^t");
    t.boolean("taa", true, &T::taa)
        .doc("§6.2", "TAA on redrawn pixels and motion smoothing on reprojected ones")
        .number("taa_alpha", 0.1, Range::above(0, 1), &T::taa_alpha)
        .doc("§6.2", "TAA / motion-smoothing accumulation factor")
        .boolean("redraw_transparent", true, &T::redraw_transparent)
        .doc("§8.5", "transparent surfaces are redrawn every frame")
        .validate([](const T& t, Params& p) {
          if (t.conf.phi_0 < t.conf.phi_f)
            p.fail("phi_0", "must be >= phi_f (" + std::to_string(t.conf.phi_f) + " deg), got " +
                                std::to_string(t.conf.phi_0));
        });
    return t;
  }();
  return t;
}
}  // namespace

TwfrParams TwfrParams::from_params(Params& p) {
  return twfr_table().read(p);
}

TwfrMethod::TwfrMethod(const TwfrParams& p) : p_(p) {}

uint32_t TwfrMethod::required_channels() const {
  // Object ids: dynamic objects (§7); sub-model ids: which pixels a culled sub-model covers.
  return kShadingChannels | kObjectId | kSubModel;
}

void TwfrMethod::analytic_counters(const AnalyticFrame& f, Counters& c) const {
  const AnalyticWorkload& w = *f.workload;
  const double P = f.pixels;
  double rf = f.keys->number("redraw_fraction", w.redraw_fraction, Range::closed(0, 1));
  double pf = f.keys->number("prims_fraction", w.prims_fraction, Range::closed(0, 1));
  double T = std::max(0.0, w.triangles) * w.submitted_fraction;
  c.set(Counter::shaded_samples, rf * P);
  c.set(Counter::gbuffer_samples, rf * P);
  c.set(Counter::pixels_redrawn, rf * P);
  c.set(Counter::reproject_splats, P);  // every previous pixel carries a position
  c.set(Counter::reprojected_pixels, P);
  c.set(Counter::prims_submitted, pf * T);
  c.set(Counter::prims_culled, (1 - pf) * T);
}

std::vector<std::pair<std::string, double>> TwfrMethod::param_columns() const {
  std::vector<std::pair<std::string, double>> c = {{"epsilon", p_.conf.epsilon},
                                                   {"phi_f", p_.conf.phi_f},
                                                   {"phi_0", p_.conf.phi_0},
                                                   {"A", p_.conf.A},
                                                   {"D", p_.conf.D}};
  // The value as given when the float in use still equals it (mutable_params may change it).
  const auto given = twfr_table().columns(p_);
  for (auto& [k, v] : c)
    for (auto& [gk, gv] : given)
      if (gk == k && float(gv) == float(v)) v = gv;
  return c;
}

void TwfrMethod::reset() {
  has_state_ = false;
  prev_color_ = Image();
  prev_display_ = Image();
  samples_.clear();
}

void TwfrMethod::compute_object_motion(const Scene& scene, double t) {
  // §7: each sprite of a dynamic object moves with its object's change of transform.
  const size_t no = scene.objects.size();
  motion_.assign(no, glm::mat4(1.f));
  object_dynamic_.assign(no, 0);
  for (size_t o = 0; o < no; ++o) {
    const Object& ob = scene.objects[o];
    if (!ob.dynamic()) continue;
    object_dynamic_[o] = 1;
    glm::mat4 m = ob.transform_at(t) * glm::inverse(ob.transform_at(prev_t_));
    motion_[o] = finite_mat(m) ? m : glm::mat4(std::numeric_limits<float>::quiet_NaN());
  }
}

// The five stages of Franke et al. (2021), each a member below, and the state carried to the next
// frame. §8.5 limitations are flags of the frame; the run continues.
void TwfrMethod::render(const FrameContext& ctx, FrameOutput& out) {
  const GBuffer& g = *ctx.gbuffer;
  const Scene& scene = *ctx.scene;
  const Camera& cam = *ctx.camera;
  const int W = g.width, H = g.height;
  const size_t n = g.size();
  Counters& c = out.counters;
  timings_ = TwfrTimings{};

  // §8.5 limitations: reported, the run continues.
  bool moving_lights = false, transparency = false;
  for (const Light& l : scene.lights) moving_lights = moving_lights || l.moving();
  for (const Material& m : scene.materials) transparency = transparency || m.transparent;
  if (moving_lights) out.flags.push_back("twfr_moving_lights");
  if (transparency) out.flags.push_back("twfr_transparency");
  // Holes narrower than a simulated pixel (display levels below -log2 s) cannot occur here.
  if (ctx.render_scale < 1.0) out.flags.push_back("twfr_holes_below_pixel");

  // First frame of a trace, a reset or a new resolution: redraw everything.
  const bool restart = !has_state_ || width_ != W || height_ != H || ctx.prev_camera == nullptr;
  if (restart) {
    width_ = W;
    height_ = H;
    prev_t_ = ctx.t;
    samples_.assign(n, twfr::Sample{});
    prev_color_.resize(W, H, 3);
    prev_display_ = Image();  // no TAA history across a restart
  }

  const twfr::ReprojectStats rs = reproject(ctx);  // 1. forward reprojection (§4, §7)
  // 2. push-pull hole filling (§5.1), outside the fovea (redrawn anyway)
  auto t0 = Clock::now();
  const twfr::PushPullStats ps = twfr::push_pull_fill(
      color_, covered_, fovea_.data(), float(scene.exposure), level_, cc_, pushpull_);
  timings_.pushpull_ms = ms_since(t0);
  const twfr::ConfidenceStats cs = confidence(ctx, transparency);  // 3. redraw map (§5.2, §7)
  const twfr::CullStats cu = cull(ctx);  // 4. OR-mipmap and sub-model culling (§6.1)
  Image reprojected;
  const size_t shaded = redraw(ctx, c, ctx.want_debug ? &reprojected : nullptr);  // 5. (§6.1)

  // Composed colour (without TAA) is the next frame's reprojection input (§6.2).
  if (p_.taa) {
    t0 = Clock::now();
    apply_taa(ctx, color_, out.image, c);
    timings_.taa_ms = ms_since(t0);
  } else {
    out.image = color_;
  }
  std::swap(prev_color_, color_);
  std::swap(samples_, next_samples_);
  prev_cam_ = cam;
  prev_t_ = ctx.t;
  has_state_ = true;

  c.set(Counter::gbuffer_samples, double(shaded));
  c.set(Counter::fullres_pixels, double(n));
  c.set(Counter::pixels_redrawn, double(cs.redrawn));
  c.set(Counter::redraw_confidence_pixels, double(cs.by_confidence));
  c.set(Counter::fovea_pixels, double(cs.fovea));
  c.set(Counter::uncovered_pixels, double(cs.uncovered));
  c.set(Counter::forced_pixels, double(cs.forced));
  c.set(Counter::dynamic_pixels, double(cs.dynamic));
  c.set(Counter::reproject_splats, double(rs.splats));
  c.set(Counter::reprojected_pixels, double(rs.landed));
  c.set(Counter::fovea_splats_discarded, double(rs.fovea_discarded));
  c.set(Counter::holes_filled, double(ps.holes));
  for (size_t m = 1; m < ps.holes_per_level.size(); ++m)
    c.set(Counter::holes_mip, int(m), double(ps.holes_per_level[m]));
  c.set(Counter::prims_submitted, cu.prims_submitted);
  c.set(Counter::prims_culled, cu.prims_culled + cu.prims_offscreen);
  c.set(Counter::prims_offscreen, cu.prims_offscreen);
  c.set(Counter::prims_foveation_culled, cu.prims_culled);
  c.set(Counter::submodels_submitted,
        double(cu.submodels - cu.submodels_culled - cu.submodels_offscreen));
  c.set(Counter::submodels_culled, double(cu.submodels_culled + cu.submodels_offscreen));
  c.set(Counter::cull_conflicts, double(conflicts_));
  c.set(Counter::twfr_restart, restart ? 1.0 : 0.0);

  if (ctx.want_debug) debug_images(out, std::move(reprojected));
}

// 1. Forward reprojection (§4, §7) of the last frame's samples into color_ / next_samples_.
twfr::ReprojectStats TwfrMethod::reproject(const FrameContext& ctx) {
  const Scene& scene = *ctx.scene;
  const Camera& cam = *ctx.camera;
  const size_t n = ctx.gbuffer->size();
  const std::vector<float>& ecc = *ctx.eccentricity;
  auto t0 = Clock::now();
  compute_object_motion(scene, ctx.t);
  fovea_.resize(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1 << 14),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t i = r.begin(); i != r.end(); ++i)
                        fovea_[i] = ecc[i] < p_.conf.phi_f;
                    });
  twfr::ReprojectInput ri;
  ri.color = &prev_color_;
  ri.samples = &samples_;
  ri.object_motion = &motion_;
  ri.object_dynamic = &object_dynamic_;
  ri.camera = &cam;
  ri.eccentricity = &ecc;
  ri.fovea_deg = p_.conf.phi_f;
  twfr::ReprojectStats rs = twfr::forward_reproject(ri, color_, next_samples_, covered_, splat_);
  timings_.reproject_ms = ms_since(t0);
  return rs;
}

// 3. Confidence and redraw map (§5.2, §7); transparent surfaces forced (§8.5).
twfr::ConfidenceStats TwfrMethod::confidence(const FrameContext& ctx, bool transparency) {
  const GBuffer& g = *ctx.gbuffer;
  const Scene& scene = *ctx.scene;
  const int W = g.width, H = g.height;
  const size_t n = g.size();
  const std::vector<float>& ecc = *ctx.eccentricity;
  auto t0 = Clock::now();
  const bool use_forced = transparency && p_.redraw_transparent && g.has(kMaterial);
  dynamic_.resize(n);
  age_.resize(n);
  forced_.resize(use_forced ? n : 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1 << 14),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t i = r.begin(); i != r.end(); ++i) {
                        const twfr::Sample& s = next_samples_[i];
                        const bool dyn = covered_[i] && s.kind == twfr::kSurface && s.object >= 0 &&
                                         size_t(s.object) < object_dynamic_.size() &&
                                         object_dynamic_[size_t(s.object)];
                        dynamic_[i] = dyn;
                        age_[i] = s.age;
                        if (use_forced) {
                          const int32_t m = g.material[i];
                          forced_[i] = g.hit(i) && m >= 0 && size_t(m) < scene.materials.size() &&
                                       scene.materials[size_t(m)].transparent;
                        }
                      }
                    });
  twfr::ConfidenceInputs ci;
  ci.eccentricity = ecc.data();
  ci.hole_level = level_.data();
  ci.contrast = cc_.data();
  ci.dynamic = dynamic_.data();
  ci.age = age_.data();
  ci.fovea = fovea_.data();
  ci.forced = use_forced ? forced_.data() : nullptr;
  // Hole levels in display pixels (Franke et al. 2021 §5.2's m at the display's resolution).
  twfr::ConfidenceParams cp = p_.conf;
  cp.level_offset = ctx.render_scale == 1.0 ? 0.f : float(-std::log2(ctx.render_scale));
  twfr::ConfidenceStats cs = twfr::compute_redraw_map(ci, cp, W, H, conf_, redraw_);
  timings_.confidence_ms = ms_since(t0);
  return cs;
}

// 4. OR-mipmap and sub-model culling (§6.1); the shade mask without culled sub-models.
twfr::CullStats TwfrMethod::cull(const FrameContext& ctx) {
  const GBuffer& g = *ctx.gbuffer;
  const Scene& scene = *ctx.scene;
  const Camera& cam = *ctx.camera;
  const int W = g.width, H = g.height;
  const size_t n = g.size();
  auto t0 = Clock::now();
  ormip_.build(redraw_, W, H);
  const Renderer& rdr = *ctx.renderer;
  twfr::CullStats cu = twfr::cull_submodels(
      cam, ormip_, scene.submodels.size(), [&](size_t s) { return rdr.submodel_bounds_world(s); },
      [&](size_t s) { return double(scene.submodels[s].tri_count); }, culled_);
  // Pixels of culled sub-models are not shaded: their fragments are never generated. By
  // construction no marked pixel lies on a culled sub-model (counted, must stay 0).
  mask_.resize(n);
  const bool has_sub = g.has(kSubModel);
  conflicts_ = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, n, 1 << 14), size_t(0),
      [&](const tbb::blocked_range<size_t>& r, size_t acc) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
          uint8_t m = redraw_[i] ? 1 : 0;
          if (m && has_sub) {
            const int32_t s = g.submodel[i];
            if (s >= 0 && size_t(s) < culled_.size() && culled_[size_t(s)]) {
              m = 0;
              ++acc;
            }
          }
          mask_[i] = m;
        }
        return acc;
      },
      [](size_t a, size_t b) { return a + b; });
  timings_.cull_ms = ms_since(t0);
  return cu;
}

// 5. Redraw where marked and compose (§6.1, §6.2); returns the pixels shaded. `reprojected`:
// the composed colour before the redraw (debug image).
size_t TwfrMethod::redraw(const FrameContext& ctx, Counters& c, Image* reprojected) {
  const GBuffer& g = *ctx.gbuffer;
  const Camera& cam = *ctx.camera;
  const int W = g.width, H = g.height;
  const Renderer& rdr = *ctx.renderer;
  auto t0 = Clock::now();
  if (reprojected) *reprojected = color_;
  c.set(Counter::shaded_samples, 0);
  rdr.shade(g, cam.position, color_, mask_.data(), &c);
  if (ctx.lighting) ctx.lighting->shade(ctx, g, mask_.data(), color_, c);  // the scene's indirect
  // Redrawn pixels carry their exact world position (or sky direction) into the next frame;
  // hole-filled pixels carry none (§4).
  size_t shaded = tbb::parallel_reduce(
      tbb::blocked_range<int>(0, H), size_t(0),
      [&](const tbb::blocked_range<int>& rows, size_t acc) {
        for (int y = rows.begin(); y != rows.end(); ++y) {
          for (int x = 0; x < W; ++x) {
            const size_t i = size_t(y) * size_t(W) + size_t(x);
            twfr::Sample& s = next_samples_[i];
            if (mask_[i]) {
              ++acc;
              s.age = 0;
              if (g.hit(i)) {
                s.kind = twfr::kSurface;
                s.pos = g.position[i];
                s.object = g.has(kObjectId) ? g.object_id[i] : -1;
              } else {
                s.kind = twfr::kSky;
                s.pos = glm::vec3(cam.dir_world(x + 0.5, y + 0.5));
                s.object = -1;
              }
            } else if (!covered_[i]) {
              s = twfr::Sample{};
            }
          }
        }
        return acc;
      },
      [](size_t a, size_t b) { return a + b; });
  timings_.redraw_ms = ms_since(t0);
  return shaded;
}

// Debug images: redraw reasons, confidence, hole levels, the reprojected colour.
void TwfrMethod::debug_images(FrameOutput& out, Image reprojected) const {
  const int W = width_, H = height_;
  const size_t n = size_t(W) * size_t(H);
  Image rm(W, H, 3);
  for (size_t i = 0; i < n; ++i) {
    glm::vec3 col(0.f);
    const uint8_t r = redraw_[i];
    if (r & twfr::kRedrawForced)
      col = {0.2f, 1.f, 0.2f};
    else if (r & twfr::kRedrawFovea)
      col = {0.3f, 0.5f, 1.f};
    else if (r & twfr::kRedrawUncovered)
      col = {1.f, 0.2f, 0.2f};
    else if (r & twfr::kRedrawConfidence)
      col = {1.f, 1.f, 1.f};
    rm.data[3 * i] = col.r;
    rm.data[3 * i + 1] = col.g;
    rm.data[3 * i + 2] = col.b;
  }
  Image conf(W, H, 1), holes(W, H, 1);
  for (size_t i = 0; i < n; ++i) {
    conf.data[i] = conf_[i];
    holes.data[i] = level_[i] == twfr::kUncovered ? 8.f : float(level_[i]);
  }
  out.debug.emplace_back("redraw", std::move(rm));
  out.debug.emplace_back("confidence", heatmap(conf, 0.f, 1.f));
  out.debug.emplace_back("holes", heatmap(holes, 0.f, 8.f));
  out.debug.emplace_back("reprojected", std::move(reprojected));
}

// §6.2: redrawn pixels get TAA, reprojected pixels motion smoothing: both reproject the pixel's
// world position into the previous frame, fetch the history colour (bilinear), clip it to the
// 3x3 colour box of the current pixel and accumulate with alpha. Hole-filled pixels pass through.
void TwfrMethod::apply_taa(const FrameContext& ctx, const Image& cur, Image& out, Counters& c) {
  const int W = cur.width, H = cur.height;
  out = cur;
  const bool have_hist = has_state_ && prev_display_.width == W && prev_display_.height == H;
  size_t taa = 0, smooth = 0;
  if (have_hist) {
    std::vector<glm::mat4> inv_motion(motion_.size(), glm::mat4(1.f));
    for (size_t o = 0; o < motion_.size(); ++o)
      if (object_dynamic_[o]) inv_motion[o] = glm::inverse(motion_[o]);
    const float a = float(p_.taa_alpha);
    struct Acc {
      size_t taa = 0, smooth = 0;
    };
    Acc acc = tbb::parallel_reduce(
        tbb::blocked_range<int>(0, H), Acc{},
        [&](const tbb::blocked_range<int>& rows, Acc ac) {
          for (int y = rows.begin(); y != rows.end(); ++y) {
            for (int x = 0; x < W; ++x) {
              const size_t i = size_t(y) * size_t(W) + size_t(x);
              const twfr::Sample& s = next_samples_[i];
              if (s.kind == twfr::kNoSample) continue;
              glm::dvec2 px;
              bool ok;
              if (s.kind == twfr::kSky) {
                ok = prev_cam_.project_head(prev_cam_.to_head_dir(glm::dvec3(s.pos)), px);
              } else {
                glm::vec3 p = s.pos;
                if (s.object >= 0 && size_t(s.object) < inv_motion.size() &&
                    object_dynamic_[size_t(s.object)])
                  p = glm::vec3(inv_motion[size_t(s.object)] * glm::vec4(p, 1.f));
                ok = prev_cam_.project_world(glm::dvec3(p), px);
              }
              if (!ok || !std::isfinite(px.x) || !std::isfinite(px.y) || !prev_cam_.inside(px))
                continue;
              // Bilinear history fetch.
              const double u = px.x - 0.5, v = px.y - 0.5;
              const int x0 = std::clamp(int(std::floor(u)), 0, W - 1),
                        y0 = std::clamp(int(std::floor(v)), 0, H - 1);
              const int x1 = std::min(x0 + 1, W - 1), y1 = std::min(y0 + 1, H - 1);
              const float fx = float(std::clamp(u - std::floor(u), 0.0, 1.0)),
                          fy = float(std::clamp(v - std::floor(v), 0.0, 1.0));
              float hist[3], lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
              for (int k = 0; k < 3; ++k) {
                hist[k] = (1 - fy) * ((1 - fx) * prev_display_.at(x0, y0)[k] +
                                      fx * prev_display_.at(x1, y0)[k]) +
                          fy * ((1 - fx) * prev_display_.at(x0, y1)[k] +
                                fx * prev_display_.at(x1, y1)[k]);
              }
              for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                  const int nx = std::clamp(x + dx, 0, W - 1), ny = std::clamp(y + dy, 0, H - 1);
                  const float* q = cur.at(nx, ny);
                  for (int k = 0; k < 3; ++k) {
                    lo[k] = std::min(lo[k], q[k]);
                    hi[k] = std::max(hi[k], q[k]);
                  }
                }
              float* o = out.at(x, y);
              const float* q = cur.at(x, y);
              for (int k = 0; k < 3; ++k)
                o[k] = a * q[k] + (1 - a) * std::clamp(hist[k], lo[k], hi[k]);
              if (mask_[i])
                ++ac.taa;
              else
                ++ac.smooth;
            }
          }
          return ac;
        },
        [](Acc l, const Acc& r) {
          l.taa += r.taa;
          l.smooth += r.smooth;
          return l;
        });
    taa = acc.taa;
    smooth = acc.smooth;
  }
  prev_display_ = out;
  c.set(Counter::taa_pixels, double(taa));
  c.set(Counter::motion_smoothed_pixels, double(smooth));
}

std::unique_ptr<FoveationMethod> create_twfr(Params& p) {
  return std::make_unique<TwfrMethod>(TwfrParams::from_params(p));
}

const std::vector<ParamInfo>& twfr_params() {
  return twfr_table().info();
}

// Reprojection with push-pull and confidence (§4-§5), a redraw of the marked pixels only, on
// the primitives foveated culling keeps (§6.1). Its redraw fraction is measured, not derived
// from phi_f, so its cost under tracking loss is not modelled.
const MethodCost& twfr_cost() {
  static const MethodCost m = [] {
    MethodCost d;
    d.passes.reprojection = d.passes.redraws_marked_pixels = d.passes.culls_primitives = true;
    d.analytic_keys = {"redraw_fraction", "prims_fraction"};
    d.widening_modelled = false;
    return d;
  }();
  return m;
}

}  // namespace fovsim
