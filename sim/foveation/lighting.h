// Lighting strategies: which VPLs a method's samples use for the one-bounce indirect light
// (docs/architecture.md "Methods and lighting strategies" "Lighting is its own axis"). The scene
// states what it needs (Scene::wants_indirect, Scene::vpl); the frame's VPL set is built once per
// frame with the shared G-buffer (FrameVpls, prepare_frame) and the reference is direct + indirect
// from ALL of them (the "tile-based deferred shading" ground truth of Yang et al., "Foveated light
// culling", §7). Every method shades the direct light at its own samples and adds the indirect
// light of the VPLs its strategy selects:
//   all_vpls  every VPL (TBDS, the ground truth)
//   flc       foveated light culling (importance map, quasi-MH samples, eq. 14, culling)
//   fir       foveated instant radiosity as the FLC paper describes it (visibility + position
//             relative to the fovea, VPL intensity ignored)
// A config selects one per method: {"method": "kfr", "lighting": {"method": "flc",
// "vpl_budget": 1024}}. The list is lighting_list.h; each strategy's file declares its
// parameters (ParamInfo) like the methods do; docs/methods.md embeds lighting_markdown().
#pragma once
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "sim/core/counters.h"
#include "sim/core/image.h"
#include "sim/core/params.h"
#include "sim/foveation/cost_passes.h"
#include "sim/render/gbuffer.h"
#include "sim/render/rsm.h"
#include "sim/render/vpl.h"

namespace fovsim {

class Renderer;
struct FrameContext;  // method.h
struct ParamInfo;     // sim/core/param_info.h

// The VPL set of one frame (computed once, shared by the reference and every method).
struct FrameVpls {
  std::vector<RSM> rsms;  // one per light (BLSO reads them)
  std::vector<VPL> vpls;
  VplSoA all;              // every VPL, weight 1
  VplShading shading;      // scene settings in world units
  float scene_diag = 1.f;  // world units
  // The indirect light of `all` at every pixel of the frame's shared G-buffer (RGB per pixel,
  // 0 on misses; `all_indirect_of` is that G-buffer), computed once with the reference
  // (prepare_frame) when VPL visibility is off, else empty. Every all_vpls strategy shading
  // samples of that G-buffer (itself, a mask of it, or an index view of it) adds these values
  // instead of evaluating the same shade_vpls again: the same L, so the same bits.
  Image all_indirect;
  const GBuffer* all_indirect_of = nullptr;
};

// Renders the RSMs of every light and their VPLs (FLC paper §3, S-1/S-2) with the scene's
// VplSettings at the renderer's current time. Counters: rsm_texels, rsm_rays.
void build_frame_vpls(const Renderer& r, FrameVpls& out, Counters* c = nullptr);

// Indirect light of VPL set v at a receiver (position p, unit normal n, albedo a), times
// `scale`: the SIMD loop of vpl_kernels.inc without visibility (bit-identical to
// shade_vpls_point in sim/render/vpl.cpp on every SIMD path), shade_vpls_point with it.
glm::vec3 shade_vpls(const VplSoA& v, const glm::vec3& p, const glm::vec3& n, const glm::vec3& a,
                     const VplShading& s, const Renderer* r, float scale = 1.f,
                     uint64_t* rays = nullptr);

// col[i] += indirect light of v at every hit sample i of g (a G-buffer or an index view of
// one) with mask[i] != 0 (mask optional); other samples are left as they are.
// Counters: shaded_sample_vpls, vpl_shadow_rays.
void add_indirect(GBufferRef g, const VplSoA& v, const VplShading& s, const Renderer* r,
                  const uint8_t* mask, Image& col, Counters* c = nullptr);

// Fills vp.all_indirect (resized to g's size) with the indirect light of vp.all at every
// sample of g (0 on misses) and sets vp.all_indirect_of = &g, when vp.shading.visibility is
// off; with visibility it clears both and returns false (no cache: shadow-ray counts are per
// sample). Counters: none (add_cached_indirect counts what each user adds).
bool cache_all_indirect(const GBuffer& g, const Renderer* r, FrameVpls& vp);
// col[i] += vp.all_indirect[g.src(i)] at every hit sample i of g with mask[i] != 0: what
// add_indirect(g, vp.all, vp.shading, ...) adds, bit for bit, when g views
// *vp.all_indirect_of. Counters: shaded_sample_vpls (as add_indirect).
void add_cached_indirect(GBufferRef g, const FrameVpls& vp, const uint8_t* mask, Image& col,
                         Counters* c = nullptr);

class LightingStrategy {
 public:
  virtual ~LightingStrategy() = default;
  virtual std::string name() const = 0;
  // Chooses this frame's weighted VPL subset from *ctx.vpls (non-null); fills the counters of
  // its passes (vpls_total, vpls_kept, importance_samples, contribution_evals, ...).
  virtual void begin_frame(const FrameContext& ctx, Counters& c) = 0;
  // The weighted subset chosen by begin_frame.
  virtual const VplSoA& selected(const FrameContext& ctx) const = 0;
  // After the method's image is final (linear RGB, W x H): temporal strategies keep history.
  virtual void end_frame(const FrameContext&, const Image&) {}
  virtual void reset() {}
  virtual bool temporal() const { return false; }
  virtual bool uses_all_vpls() const { return false; }
  // Debug buffers of the last frame (importance maps, ...), when the frame asked for them.
  virtual void debug_images(std::vector<std::pair<std::string, Image>>&) {}
  // Parameter columns for frames.csv (vpl_budget, ...).
  virtual std::vector<std::pair<std::string, double>> param_columns() const { return {}; }
  // The counters of its VPL-selection passes for `vpls` VPLs when nothing was rendered (the
  // analytic counters of `predict`/`budget`): each strategy declares its own passes, so the
  // cost model never infers them from the strategy's name. `importance_samples` is the
  // workload's per-frame importance sample count. Default: no selection passes.
  virtual void analytic_selection_counters(Counters&, double /*vpls*/,
                                           double /*importance_samples*/) const {}
  // The cost passes its selection adds and the shared work it uses (method.h CostPasses).
  // Default: the frame's RSMs and VPLs, no selection passes (all_vpls).
  virtual void declare_passes(CostPasses& p) const { p.frame_rsm = true; }

  // Adds the selected VPLs' indirect light at the samples of g (see add_indirect).
  void shade(const FrameContext& ctx, GBufferRef g, const uint8_t* mask, Image& col,
             Counters& c) const;
};

struct LightingEntry {
  const char* name;
  const char* summary;
  std::unique_ptr<LightingStrategy> (*create)(Params& p);
  const std::vector<ParamInfo>& (*params)();
};
const std::vector<LightingEntry>& lighting_table();
// Reads a `lighting` block ("method" selects the strategy, default all_vpls); unknown names
// and keys are errors with the JSON path.
std::unique_ptr<LightingStrategy> make_lighting(Params& p);
std::unique_ptr<LightingStrategy> default_lighting();  // all_vpls
class FoveationMethod;
struct FrameOutput;
// One frame of method m with its lighting strategy: when ctx.vpls is set, the strategy's
// begin_frame (its counters go to out), m.render with ctx.lighting set, end_frame and, with
// ctx.want_debug, its debug buffers. What the engine and the tests call.
void render_with_lighting(FoveationMethod& m, FrameContext ctx, FrameOutput& out);

// Parameter tables of every strategy as Markdown (embedded in docs/methods.md).
std::string lighting_markdown();

}  // namespace fovsim
