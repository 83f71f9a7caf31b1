// `twfr`: time-warped foveated rendering (Franke et al. 2021). The method class is exposed so tests
// and bench/bench_twfr.cpp can inspect its per-frame buffers and stage timings; runs create it
// through the factory (create_twfr in methods.h).
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "sim/foveation/method.h"
#include "sim/foveation/method_ids.h"
#include "sim/foveation/twfr_confidence.h"
#include "sim/foveation/twfr_cull.h"
#include "sim/foveation/twfr_pushpull.h"
#include "sim/foveation/twfr_reproject.h"

namespace fovsim {

struct TwfrParams {
  twfr::ConfidenceParams conf;
  bool taa = true;                 // §6.2 TAA on redrawn + motion smoothing on reprojected pixels
  double taa_alpha = 0.1;          // §6.2 accumulation factor (applied as a float)
  bool redraw_transparent = true;  // §8.5: transparent surfaces rendered every frame
  // epsilon, phi_f, phi_0, A, D as parsed (double; the CSV columns), conf holds them as float.
  struct Given {
    double epsilon = 0.2, phi_f = 10, phi_0 = 30, A = 0.6, D = 0.75;
  } given;
  static TwfrParams from_params(Params& p);
};

// Wall time of each stage of the last frame (CPU simulation, not the GPU estimate).
struct TwfrTimings {
  double reproject_ms = 0, pushpull_ms = 0, confidence_ms = 0, cull_ms = 0, redraw_ms = 0,
         taa_ms = 0;
};

class TwfrMethod final : public FoveationMethod {
 public:
  explicit TwfrMethod(const TwfrParams& p);
  std::string name() const override { return method_id::twfr; }
  uint32_t required_channels() const override;
  void render(const FrameContext& ctx, FrameOutput& out) override;
  void reset() override;
  bool temporal() const override { return true; }
  // Its §6.2 TAA / motion smoothing is its own pass (apply_taa, on the world positions of its
  // samples); the settings are reported so that `full` as its foveation-loss reference gets the
  // shared pass with the same blend (3x3 clamp, taa_alpha).
  TaaSettings taa() const override {
    TaaSettings s;
    s.enabled = p_.taa;
    s.alpha = p_.taa_alpha;
    return s;
  }
  bool own_taa() const override { return true; }
  // The first frame after a (re)start has no history and redraws every pixel (Franke et al.
  // 2021 §4: every later frame reprojects the previous one): on the quickstart 187 ms against a
  // median of 21.6 ms. From the second frame on the redraw is the confidence map's.
  int warmup_frames() const override { return 1; }
  std::vector<std::pair<std::string, double>> param_columns() const override;
  // The redrawn pixels and the primitives kept by foveated culling from the analytic keys
  // redraw_fraction, prims_fraction (default: the workload's, Franke et al. 2021 §8.4).
  void analytic_counters(const AnalyticFrame& f, Counters& c) const override;

  const TwfrParams& params() const { return p_; }
  TwfrParams& mutable_params() { return p_; }  // tests: change epsilon between frames
  const TwfrTimings& timings() const { return timings_; }
  // Buffers of the last rendered frame (W*H, row-major) for tests and debugging.
  const std::vector<uint8_t>& redraw_map() const { return redraw_; }  // twfr::RedrawReason bits
  const std::vector<uint8_t>& shade_mask() const { return mask_; }    // pixels shaded in the redraw
  const std::vector<float>& confidence() const { return conf_; }
  const std::vector<uint8_t>& hole_level() const { return level_; }  // 0, m, or kUncovered
  const std::vector<uint8_t>& submodel_culled() const { return culled_; }
  const std::vector<twfr::Sample>& samples() const { return samples_; }  // carried to next frame
  size_t cull_conflicts() const { return conflicts_; }  // marked pixels on culled sub-models (0)

 private:
  void compute_object_motion(const Scene& scene, double t);
  // The stages of render(), in order (twfr.cpp).
  twfr::ReprojectStats reproject(const FrameContext& ctx);
  twfr::ConfidenceStats confidence(const FrameContext& ctx, bool transparency);
  twfr::CullStats cull(const FrameContext& ctx);
  size_t redraw(const FrameContext& ctx, Counters& c, Image* reprojected);
  void debug_images(FrameOutput& out, Image reprojected) const;
  void apply_taa(const FrameContext& ctx, const Image& composed, Image& out, Counters& c);

  TwfrParams p_;
  TwfrTimings timings_;
  // Temporal state (§4): last composed colour (without TAA, §6.2) + samples.
  bool has_state_ = false;
  int width_ = 0, height_ = 0;
  double prev_t_ = 0;
  Camera prev_cam_;
  Image prev_color_;
  std::vector<twfr::Sample> samples_;
  Image prev_display_;  // last TAA output (history), when taa is on
  // Per-frame buffers (kept to avoid reallocation).
  Image color_;
  std::vector<twfr::Sample> next_samples_;
  std::vector<uint8_t> covered_, fovea_, level_, dynamic_, forced_, redraw_, mask_, culled_;
  std::vector<uint16_t> age_;
  std::vector<float> cc_, conf_;
  std::vector<glm::mat4> motion_;
  std::vector<uint8_t> object_dynamic_;
  twfr::SplatBuffer splat_;
  twfr::PushPull pushpull_;
  twfr::OrMip ormip_;
  size_t conflicts_ = 0;
};

}  // namespace fovsim
