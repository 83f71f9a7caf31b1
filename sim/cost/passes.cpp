// Pass lists and term values (docs/architecture.md "Cost model"). Terms and their units:
//   tris           triangles submitted to a raster pass (not scaled by pixel_scale); in the
//                  G-buffer pass times workload.tri_cost (the scene's relative triangle cost)
//   frags          rasterised fragments = pixels * overdraw
//   gbuffer_bytes  bytes written to the G-buffer = pixels * workload.gbuffer_bytes
//   shadow_tris    triangles * shadowed lights (one shadow map per light, shared by both eyes)
//   shadow_texels  shadow_map_res^2 * shadowed lights
//   shade_flops    shaded samples * lights * workload.shading_flops
//   vpl_flops      (FLC) shaded sample-VPL pairs * workload.vpl_flops
//   taps           (pass 2) full-resolution pixels * filter taps
//   pixels         full-resolution pixels a screen pass touches (reproject: sprites that land)
//   sprites        (TWFR) point sprites of the reprojection's warp (reproject_splats)
//   fill_pixels    (TWFR) pixels push-pull and the confidence pass run over
//   holes          (TWFR) hole pixels filled by push-pull, summed over mip levels
//   texels         (FLC) RSM texels; samples: importance samples * chain length;
//   flops          (contribution) FP32 operations the paper's algorithm states: eq. 14 per
//                  VPL-sample pair plus eqs. 12-13 per BLSO lookup (contribution_flops)
//   vpls           VPLs culled
//   taps           (post_aa) texel reads: 3x3 Gaussian + TAA clamp window eta^2 (eq. 15) +
//                  history, per full-resolution pixel (post_aa_taps_per_pixel)
#include "sim/cost/passes.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "sim/core/error.h"
#include "sim/core/message_text.h"
#include "sim/foveation/factory.h"

namespace fovsim {

namespace {

struct TermDef {
  const char* pass;
  const char* term;
  Resource res;
  int stage = 0;  // dispatch within the pass (Term::stage)
};

const std::vector<TermDef>& term_table() {
  static const std::vector<TermDef> t = {
      {"depth", "tris", Resource::Geometry},
      {"depth", "frags", Resource::Raster},
      {"shadow", "shadow_tris", Resource::Geometry},
      {"shadow", "shadow_texels", Resource::Raster},
      {"rsm", "tris", Resource::Geometry},
      {"rsm", "texels", Resource::Raster},
      {"gbuffer", "tris", Resource::Geometry},
      {"gbuffer", "frags", Resource::Raster},
      {"gbuffer", "gbuffer_bytes", Resource::Memory},
      {"skybox", "pixels", Resource::Raster},
      // Franke et al. 2021 §4-§5: the point-sprite warp (one primitive per previous pixel,
      // depth-tested), then push-pull over the mip chain and the confidence: two dispatches.
      {"reproject", "sprites", Resource::Geometry, 0},
      {"reproject", "pixels", Resource::Memory, 0},
      {"reproject", "fill_pixels", Resource::Memory, 1},
      {"reproject", "holes", Resource::Memory, 1},
      {"importance", "pixels", Resource::Memory},
      {"importance", "samples", Resource::Shading},
      {"contribution", "flops", Resource::Shading},
      {"light_culling", "vpls", Resource::Shading},
      {"lighting", "shade_flops", Resource::Shading},
      {"lighting", "vpl_flops", Resource::Shading},
      {"pass2", "taps", Resource::Memory},
      {"ssao", "pixels", Resource::Memory},
      {"tonemap", "pixels", Resource::Memory},
      {"taa", "pixels", Resource::Memory},
      {"post_aa", "taps", Resource::Memory},
  };  // "frame" has no terms: its overhead is the whole pass
  return t;
}

}  // namespace

const std::vector<std::string>& known_passes() {
  static const std::vector<std::string> p = {
      "depth",      "shadow",       "rsm",           "gbuffer",  "skybox", "reproject",
      "importance", "contribution", "light_culling", "lighting", "pass2",  "ssao",
      "tonemap",    "taa",          "post_aa",       "frame"};
  return p;
}

bool is_known_pass(const std::string& p) {
  auto& k = known_passes();
  return std::find(k.begin(), k.end(), p) != k.end();
}

// Every method of the factory has a cost model: its declared passes (MethodCost::passes in
// its file, with its lighting strategy's) select the pass structure below.
const std::vector<std::string>& cost_methods() {
  static const std::vector<std::string> m = [] {
    std::vector<std::string> v;
    for (const auto& e : method_table()) v.push_back(e.name);
    return v;
  }();
  return m;
}

bool is_cost_method(const std::string& m) {
  return find_method(m) != nullptr;
}

std::optional<Resource> find_term_resource(const std::string& pass, const std::string& term) {
  for (auto& d : term_table())
    if (pass == d.pass && term == d.term) return d.res;
  return std::nullopt;
}

const std::vector<std::string>& term_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (auto& d : term_table())
      if (std::find(v.begin(), v.end(), d.term) == v.end()) v.push_back(d.term);
    return v;
  }();
  return names;
}

int term_stage(const std::string& pass, const std::string& term) {
  for (auto& d : term_table())
    if (pass == d.pass && term == d.term) return d.stage;
  return 0;
}

double roofline_ms(const std::vector<Term>& terms, const std::vector<double>& term_ms,
                   std::vector<std::pair<Resource, double>>* bound) {
  std::map<int, std::map<Resource, double>> per_stage;  // work / throughput per resource (ms)
  for (size_t i = 0; i < terms.size() && i < term_ms.size(); ++i)
    per_stage[terms[i].stage][terms[i].res] += term_ms[i];
  double ms = 0;
  for (auto& [stage, per_res] : per_stage) {
    Resource b = Resource::Fixed;
    double worst = 0;
    for (auto& [r, v] : per_res)
      if (v > worst) worst = v, b = r;
    ms += worst;
    if (bound) bound->push_back({b, worst});
  }
  return ms;
}

Resource term_resource(const std::string& pass, const std::string& term, const std::string& where) {
  if (const auto r = find_term_resource(pass, term)) return *r;
  std::string known;
  for (auto& d : term_table())
    if (pass == d.pass) known += std::string(known.empty() ? "" : ", ") + d.term;
  if (known.empty()) {
    std::string all;
    for (auto& p : known_passes()) all += (all.empty() ? "" : ", ") + p;
    throw Error(where, "unknown pass '" + pass + "' (known: " + all + ")");
  }
  throw Error(where, "unknown term '" + term + "' of pass '" + pass + "' (known: " + known + ")");
}

double contribution_flops(double evals, double lookups) {
  return evals * kEq14FlopsPerPair + lookups * kBlsoFlopsPerLookup;
}

double post_aa_taps_per_pixel(int width, int height) {
  if (width <= 0 || height <= 0) return 0;
  // Yang et al. 2021 §6, eq. 15: eta = 3 + 2 floor((r / L - 0.10) / 0.05), r the distance to the
  // gaze (here the centre), L the largest distance from the gaze to a corner (the text's
  // "/ e^L" read as "/ L": e^L of a pixel distance would make eta negative everywhere). The
  // window is at least 3 x 3 (the formula's constant; inside r < 0.1 L it gives 1 or -1).
  // Mean of eta^2 over a grid of at most 256 x 256 cell centres.
  const int nx = std::min(width, 256), ny = std::min(height, 256);
  const double cx = 0.5 * width, cy = 0.5 * height, L = std::hypot(cx, cy);
  double sum = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double x = (i + 0.5) * width / nx - cx, y = (j + 0.5) * height / ny - cy;
      const double eta =
          std::max(3.0, 3.0 + 2.0 * std::floor((std::hypot(x, y) / L - 0.10) / 0.05));
      sum += eta * eta;
    }
  return kPostAaGaussianTaps + sum / (double(nx) * ny) + kPostAaHistoryTaps;
}

double working_set_factor(const std::string& pass, const std::string& term, const GpuSpec& spec,
                          const Display& display) {
  if (pass != "reproject" || term == "holes") return 1.0;
  const double px = double(std::max(0, display.width)) * double(std::max(0, display.height));
  return l2_miss_fraction(spec, px * kReprojectBytesPerPixel);
}

// Long because: it is the one list of a frame's passes in pipeline order (depth prepass,
// shadows, RSMs, TWFR's reprojection, G-buffer or forward pass, skybox, importance, culling,
// lighting, mapping pass 2, SSAO, tone map), each a few lines that read the counters it needs;
// split per pass, each piece would need the same counters, display and workload, and the order
// would no longer be visible in one place.
std::vector<PassWork> assemble_passes(const CostInputs& in, const Workload& w,
                                      std::vector<std::string>* missing) {
  const std::string& m = in.method;
  if (!is_cost_method(m)) {
    std::string all;
    for (auto& k : cost_methods()) all += (all.empty() ? "" : ", ") + k;
    throw Error("cost", "unknown method '" + m + "' (known: " + all + ")");
  }
  // The pipeline is what the method and its strategy declare, never inferred from counters.
  const CostPasses decl = in.passes ? *in.passes : declared_passes(m);
  const Counters empty;
  const Counters& c = in.counters ? *in.counters : empty;
  auto note = [&](Counter id) {
    const std::string name = counter_name(id);
    if (missing && std::find(missing->begin(), missing->end(), name) == missing->end())
      missing->push_back(name);
  };
  // Every input and intermediate value must be finite: an infinity or NaN (a workload, a
  // counter read from a frames.csv, or their product beyond any real scene) is an error naming
  // the method and the value, never dropped -- an infinity charged as 0 made a frame cheaper.
  // Negative counts are charged as 0.
  auto pos = [&](double v, const std::string& what) {
    if (!std::isfinite(v))
      throw Error("cost of method '" + m + "'",
                  what + " is " + shortest_number(v) +
                      " (not finite: the workload's or the counters' values are too large for "
                      "the cost model)");
    return std::max(0.0, v);
  };
  auto counter = [&](Counter id) {
    return pos(c.get(id), std::string("counter ") + counter_name(id));
  };
  // A counter the method should have filled, at the real display: a Pixels counter
  // (counter_list.h) measured at the simulated resolution is scaled by pixel_scale. Absent: noted
  // and `fallback` (already at the display).
  auto need = [&](Counter id, double fallback) {
    if (!c.has(id)) {
      note(id);
      return fallback;
    }
    if (counter_info(id).scale == CounterScale::Pixels)
      return pos(counter(id) * pos(display_scale(id, in.pixel_scale), "pixel_scale"),
                 std::string("counter ") + counter_name(id) + " at the display's resolution");
    return counter(id);
  };

  const SceneFeatures& f = in.features;
  const double scale = pos(in.pixel_scale, "pixel_scale");
  const double eyes = std::max(1, in.display.eyes);
  const double P = double(std::max(0, in.display.width)) * double(std::max(0, in.display.height));
  const double T = pos(w.tris(f) * w.submitted_fraction, "the submitted triangles");
  const double lights = pos(w.nlights(f), "the lights");
  const double shadowed = pos(w.nshadowed(f), "the shadowed lights");
  // Lighting passes (docs/architecture.md "Methods and lighting strategies" lighting axis): a scene
  // with indirect light charges every method that declares the frame's RSMs for them and the VPL
  // shading of its samples (the flc method builds VPLs on any scene); the importance / contribution
  // / culling passes exist when its lighting strategy declares them. A scene without indirect light
  // has none.
  const bool vpl = decl.frame_rsm && (f.indirect || decl.own_vpls);
  const bool has_importance = decl.importance;
  const bool has_culling = decl.culling;

  // Shaded samples per eye at the real resolution. A full-resolution pipeline shades every
  // pixel by definition.
  const double S =
      decl.full_resolution
          ? (c.has(Counter::shaded_samples)
                 ? counter(Counter::shaded_samples) * display_scale(Counter::shaded_samples, scale)
                 : P)
          : (decl.direct_at_every_pixel && c.has(Counter::direct_shaded_samples)
                 ? need(Counter::direct_shaded_samples, P)  // FLC: direct at every pixel
                 : need(Counter::shaded_samples, 0));

  std::vector<PassWork> out;
  auto add = [&](const char* pass, std::vector<Term> terms) {
    for (auto& t : terms) {
      t.value = pos(t.value, "pass " + std::string(pass) + ", term " + t.name);
      t.stage = term_stage(pass, t.name);
    }
    out.push_back({pass, std::move(terms)});
  };
  const double Tsub = decl.culls_primitives ? need(Counter::prims_submitted, T)
                                            : T;  // foveation culling (Franke et al. 2021 §6.1)

  if (w.pipeline.depth_prepass)
    add("depth", {{"tris", Resource::Geometry, T * eyes},
                  {"frags", Resource::Raster, P * w.overdraw * eyes}});
  if (shadowed > 0)  // no shadow pass without shadowed lights
    add("shadow",
        {{"shadow_tris", Resource::Geometry, T * shadowed},
         {"shadow_texels", Resource::Raster, w.shadow_map_res * w.shadow_map_res * shadowed}});
  if (vpl) {  // reflective shadow maps, one per light (Yang et al. 2021 §3, S-2)
    // The frame's RSMs: counted by the method (predict, a re-costed frames.csv) or the frame's
    // shared work it declares (a run).
    const Counters& rc = !c.has(Counter::rsm_texels) && in.shared ? *in.shared : c;
    const double fallback = w.rsm_res * w.rsm_res * std::max(1.0, lights);
    double texels = rc.has(Counter::rsm_texels)
                        ? pos(rc.get(Counter::rsm_texels), "counter rsm_texels")
                        : (note(Counter::rsm_texels), fallback);
    add("rsm", {{"tris", Resource::Geometry, T * std::max(1.0, lights)},
                {"texels", Resource::Raster, texels}});
  }
  if (decl.reprojection) {  // reprojection + push-pull + confidence (Franke et al. 2021 §4-§5)
    // The warp: "a uniform grid with a resolution equal to that of the input image ... each
    // cell ... a pixel-sized point sprite" (§4), so one primitive per previous pixel that
    // carries a world position (hole-filled pixels have none: "the point sprite's vertex will be
    // clipped"; counter reproject_splats, every pixel without counters), and the bytes of the
    // sprites that land (depth-test winners); then push-pull builds and reads the mip chain of
    // the whole image and the confidence is computed per pixel (§5).
    double sprites = need(Counter::reproject_splats, P);
    double rp = need(Counter::reprojected_pixels, P);
    double holes = 0;
    for (auto& e : c.entries())
      if (e.key.id == Counter::holes_mip) holes += pos(e.value, "counter holes_mip");
    add("reproject",
        {{"sprites", Resource::Geometry, sprites * eyes},
         {"pixels", Resource::Memory, rp * eyes},
         {"fill_pixels", Resource::Memory, P * eyes},
         {"holes", Resource::Memory, holes * display_scale(Counter::holes_mip, scale) * eyes}});
  }
  // G-buffer (deferred) or forward geometry pass (fVRS); TWFR discards confident pixels.
  {
    double written = decl.redraws_marked_pixels ? need(Counter::pixels_redrawn, S) : P;
    add("gbuffer", {{"tris", Resource::Geometry, Tsub * w.tri_cost * eyes},
                    {"frags", Resource::Raster, P * w.overdraw * eyes},
                    {"gbuffer_bytes", Resource::Memory, written * w.gbuffer_bytes * eyes}});
  }
  if (w.pipeline.skybox) add("skybox", {{"pixels", Resource::Raster, P * eyes}});
  if (vpl && has_importance) {  // importance map (eqs. 3-9) + quasi-MH sampling (Alg. 1)
    double ns = need(Counter::importance_samples, 0);
    add("importance", {{"pixels", Resource::Memory, P * eyes},
                       {"samples", Resource::Shading, ns * w.chain_length * eyes}});
  }
  if (vpl && has_culling) {  // per-VPL importance (FLC: eq. 14 with BLSO) + culling
    double ns = c.has(Counter::importance_samples) ? counter(Counter::importance_samples) : 0;
    double vt = need(Counter::vpls_total, 0);
    double evals =
        c.has(Counter::contribution_evals) ? counter(Counter::contribution_evals) : vt * ns;
    if (!c.has(Counter::contribution_evals)) note(Counter::contribution_evals);
    // BLSO (eqs. 11-13): 2 N' shadow-map lookups per pair; exact visibility casts rays instead
    // (not costed: no paper measures a ray's cost). A strategy without visibility has none.
    const double lookups = c.has(Counter::blso_lookups) ? counter(Counter::blso_lookups) : 0;
    add("contribution", {{"flops", Resource::Shading, contribution_flops(evals, lookups) * eyes}});
    add("light_culling", {{"vpls", Resource::Shading, vt * eyes}});
  }
  {
    // fVRS is a forward renderer (Franke et al. 2021 §8.4): every rasterised fragment is shaded.
    const double fwd = decl.forward_shading ? std::max(1.0, w.overdraw) : 1.0;
    std::vector<Term> t = {
        {"shade_flops", Resource::Shading, S * fwd * lights * w.shading_flops * eyes}};
    if (vpl) {  // indirect light: shaded samples x VPLs used (all of them for all_vpls)
      double vf = w.vpl_flops >= 0 ? w.vpl_flops : w.shading_flops;
      // Yang et al. 2021 §7, Fig. 7: the cost rises "almost quadratically" with the VPLs kept;
      // the workload's vpl_exponent (1: linear) scales the per-VPL work by
      // (kept / vpl_ref)^(exponent - 1), so at the calibrated budget vpl_ref it is unchanged.
      if (w.vpl_exponent != 1.0 && c.has(Counter::vpls_kept) && w.vpl_ref > 0)
        vf *= std::pow(counter(Counter::vpls_kept) / w.vpl_ref, w.vpl_exponent - 1.0);
      t.push_back(
          {"vpl_flops", Resource::Shading, need(Counter::shaded_sample_vpls, 0) * vf * eyes});
    }
    add("lighting", std::move(t));
  }
  if (decl.inverse_map) {  // inverse map to the screen (pass 2)
    // filter_taps is the frame's total of texture taps (like every counter, a total, scaled
    // to the display like other pixel counters); without it, bilinear = 4 taps per pixel.
    double full = need(Counter::fullres_pixels, P);
    double taps = c.has(Counter::filter_taps) ? need(Counter::filter_taps, 0) : 4.0 * full;
    if (!c.has(Counter::filter_taps)) note(Counter::filter_taps);
    add("pass2", {{"taps", Resource::Memory, taps * eyes}});
  }
  const double post_px = decl.redraws_marked_pixels ? need(Counter::pixels_redrawn, S) : P;
  if (w.pipeline.ssao)
    add("ssao", {{"pixels", Resource::Memory, post_px * eyes}});  // TWFR skips reprojected
  if (w.pipeline.tonemap) add("tonemap", {{"pixels", Resource::Memory, post_px * eyes}});
  // TAA: the workload's pipeline has it (the seeds' tables; `predict`), or the method ran the
  // pass this frame (counter taa_pixels: the shared TAA post pass of taa.h, twfr's §6.2). The
  // pass reads and writes every pixel whether or not it found a history. FLC's post_aa
  // already holds its TAA (Yang et al. 2021 §6).
  const bool taa = w.pipeline.taa || (!w.pipeline.post_aa && c.has(Counter::taa_pixels));
  if (taa) add("taa", {{"pixels", Resource::Memory, P * eyes}});
  if (w.pipeline.post_aa)  // Yang et al. 2021 §6: 3x3 Gaussian + TAA with clamp size eta (eq. 15)
    add("post_aa", {{"taps", Resource::Memory,
                     P * post_aa_taps_per_pixel(in.display.width, in.display.height) * eyes}});
  // The frame's GPU work outside the listed passes (present, UI, blits): a fixed per-frame
  // cost independent of resolution and method (Meng 2018 Table 4.1: "Total GPU Time" minus
  // "Total"). Its share falls as the per-pixel work grows with resolution, which is why a
  // foveated method's speedup rises with resolution (Meng 2018 §1, §4.0.2).
  if (w.pipeline.frame) add("frame", {});
  return out;
}

}  // namespace fovsim
