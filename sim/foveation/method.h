// The FoveationMethod interface (docs/architecture.md "Methods and lighting strategies"). A method
// declares the G-buffer channels it needs (Falcor reflect() role), renders one frame from the
// shared full-resolution G-buffer and reference, fills per-pass counters for the cost model and may
// emit debug buffers. Temporal methods keep state across frames and reset on request.
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sim/core/counters.h"
#include "sim/core/image.h"
#include "sim/core/param_info.h"
#include "sim/core/params.h"
#include "sim/display/display.h"
#include "sim/foveation/cost_passes.h"
#include "sim/foveation/lighting.h"
#include "sim/foveation/method_cost.h"
#include "sim/foveation/taa.h"
#include "sim/render/gbuffer.h"
#include "sim/render/renderer.h"
#include "sim/scene/scene.h"

namespace fovsim {

struct MappingSpec;  // sim/foveation/mapping_spec.h

struct FrameContext {
  int frame = 0;  // index in the resampled trace
  double t = 0;   // seconds
  const Scene* scene = nullptr;
  const Renderer* renderer = nullptr;
  const Display* display = nullptr;  // simulated (render-scaled) display
  // render.scale: simulated pixels per display pixel along each axis. Every size a method
  // defines on the screen is a size in display pixels (or degrees) and is applied at
  // render_scale x that size in simulated pixels (docs/fidelity.md "Scale invariance of the
  // methods"), so a reduced scale approximates the native answer instead of changing the method.
  double render_scale = 1.0;
  const Camera* camera = nullptr;
  const Camera* prev_camera = nullptr;  // nullptr on the first frame
  glm::dvec3 gaze_dir{0, 0, -1};        // head space, unit
  glm::dvec2 gaze_px{0, 0};             // pixels; may lie outside the screen
  bool gaze_valid = true;
  const GBuffer* gbuffer = nullptr;  // full-res primary-ray G-buffer (channels = union of needs)
  const Image* reference = nullptr;  // full-res linear shading of `gbuffer` (direct + indirect)
  const Image* direct =
      nullptr;  // direct light, 1 sample per pixel centre (== reference at spp 1 without indirect)
  const FrameVpls* vpls = nullptr;  // the frame's VPLs; nullptr when the scene has no indirect
  // The method's lighting strategy for this frame (set by the engine when `vpls` is set):
  // methods add its indirect light at their samples (shade_buffer does).
  const LightingStrategy* lighting = nullptr;
  const std::vector<float>* eccentricity = nullptr;  // degrees per pixel, W*H
  // Tracking loss with trace.on_invalid = widen (docs/tracking.md): the foveal region's growth
  // factor k = 1 + widen_per_s * (time since the last valid sample), 1 on tracked frames.
  // `eccentricity` is then already divided by k (the methods that place their fovea by
  // eccentricity widen through it); kfr, rmfr and flc read k to widen their own parameters.
  double widen = 1.0;
  bool want_debug = false;  // fill FrameOutput::debug
};

struct FrameOutput {
  Image image;                      // linear RGB, W x H
  bool image_is_reference = false;  // set instead of copying ctx.reference into image
  Counters counters;                // see results/README.md for names
  std::vector<std::pair<std::string, Image>> debug;  // name -> image (RGB or 1-channel)
  std::vector<std::string> flags;  // limitations hit this frame (e.g. "moving_lights")
};

class FoveationMethod {
 public:
  virtual ~FoveationMethod() = default;
  virtual std::string name() const = 0;
  virtual uint32_t required_channels() const = 0;
  virtual void render(const FrameContext& ctx, FrameOutput& out) = 0;
  virtual void reset() {}
  virtual bool temporal() const { return false; }
  // Frames after a (re)start whose rows are not yet representative of the method's steady
  // state: left out of the run's means by default (sim/experiment/startup.h; TWFR's cold first
  // frame redraws every pixel). 0 for a method without temporal state.
  virtual int warmup_frames() const { return 0; }
  // Parameter values as named columns for frames.csv (e.g. {"sigma", 1.8}).
  virtual std::vector<std::pair<std::string, double>> param_columns() const { return {}; }
  // String parameters as text columns, written as given (kfr {"kernel", "sine"}), never as
  // enum indices.
  virtual std::vector<std::pair<std::string, std::string>> text_param_columns() const { return {}; }
  // The sampling geometry of image-mapping methods and baselines (density, analytic
  // counters); nullptr for the others.
  virtual const MappingSpec* mapping_spec() const { return nullptr; }

  // Temporal anti-aliasing (taa.h, docs/methods.md "Temporal anti-aliasing"): the settings of
  // its TAA post pass, on by default where its seed's pipeline ends with one; off by default.
  // render_with_lighting applies the shared pass (TaaPass) after the method's image is final,
  // unless the method applies its own (own_taa(): twfr's §6.2 pass); `full` as the
  // foveation-loss reference is made with the same settings (TaaSettings::keys).
  virtual TaaSettings taa() const { return {}; }
  virtual bool own_taa() const { return false; }
  // Back to the state before its first frame: reset(), its lighting strategy's history and the
  // shared TAA pass's history. What the engine calls.
  void restart() {
    reset();
    if (lighting_) lighting_->reset();
    taa_pass_.reset();
  }
  TaaPass& taa_pass() { return taa_pass_; }

  // Lighting strategy (lighting.h): the config's `lighting` block, all_vpls by default. Used
  // only when the scene has indirect light.
  LightingStrategy* lighting() const { return lighting_.get(); }
  void set_lighting(std::unique_ptr<LightingStrategy> l) { lighting_ = std::move(l); }
  // True when the method brings its own strategy (flc): a `lighting` block is then an error.
  virtual bool own_lighting() const { return false; }

  // Its cost without rendering (method_cost.h; its declaration is `<name>_cost()`).
  // The counters it would report per eye for f's workload on f's display at pixel_scale 1
  // (`fovsim predict`, `budget`, calibration); its lighting strategy's VPL counters are added
  // by the caller unless it declares own_vpls.
  virtual void analytic_counters(const AnalyticFrame& f, Counters& c) const = 0;
  // The parameter `fovsim budget` may change first (none by default).
  virtual BudgetKnob budget_knob(const AnalyticWorkload&) const { return {}; }
  // Tracking loss with growth factor k > 1 (FrameContext::widen): sets in p the widened value
  // of every key the widening changes, as its render widens (`predict --tracking-loss`).
  // Default: none (the method does not widen, or widens through the eccentricity map only).
  virtual void widen_cost_keys(double k, Json& p) const { (void)k, (void)p; }

 protected:
  std::unique_ptr<LightingStrategy> lighting_;
  TaaPass taa_pass_;  // the shared TAA pass's history (when taa().enabled and !own_taa())
};

}  // namespace fovsim
