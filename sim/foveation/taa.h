// Temporal anti-aliasing as the seeds' pipelines end with it (docs/methods.md "Temporal
// anti-aliasing"): a post pass on a method's recovered screen image that reprojects the previous
// output through the G-buffer's screen motion (kMotion), clamps the history to the current
// pixel's colour neighbourhood and blends it exponentially (Karis 2014, "High-quality temporal
// supersampling"), with Halton(2, 3) sub-pixel jitter of the reduced buffer's samples where the
// method has one. Each method declares its own settings as rows of its parameter table
// (add_taa_rows): KFR (Meng 2018 §2.3.2, TAA with Halton sampling), RMFR (Ye et al. 2022
// Table 3's TAA pass), FLC (Yang et al. 2021 §6, clamp size eta of eq. 15); TWFR keeps its own
// pass (Franke et al. 2021 §6.2, twfr.cpp) and reports its settings here only so that `full`,
// as its foveation-loss reference, gets the same TAA. The pass is applied by
// render_with_lighting (lighting.h), never by the method itself.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "sim/core/counters.h"
#include "sim/core/image.h"
#include "sim/core/math.h"
#include "sim/core/param_table.h"
#include "sim/core/params.h"
#include "sim/render/gbuffer.h"

namespace fovsim {

struct FrameContext;  // method.h

// The neighbourhood the history is clamped to: the 3x3 box of the current pixel (Karis 2014),
// or Yang et al. 2021 eq. 15's per-pixel eta x eta window, eta = 3 + 2 floor((r / e^L - 0.10) /
// 0.05) with r the distance to the gaze and e^L the largest gaze-to-corner distance, in display
// pixels (applied at render.scale times that size; at least the pixel itself).
enum class TaaClamp { Box3, Eta };

struct TaaSettings {
  bool enabled = false;
  double alpha = 0.1;  // weight of the current frame in the blend (Franke et al. 2021 §6.2: 0.1)
  TaaClamp clamp = TaaClamp::Box3;
  bool jitter = false;  // Halton(2, 3) sub-pixel offsets of the reduced buffer's sample points
  // The settings as config keys ({"taa": false} when off): `full` as foveation-loss reference is
  // made with them; the reference side is shared by methods whose keys agree.
  Json keys() const;
  bool operator==(const TaaSettings& o) const {
    return enabled == o.enabled && alpha == o.alpha && clamp == o.clamp && jitter == o.jitter;
  }
};

// The jitter of frame `frame` in units of the jittered buffer's pixels, in [-0.5, 0.5)^2:
// Halton(2, 3) points 1..16, cycled (Meng 2018 §2.3.2 "TAA with Halton sampling"). Zero when
// the settings have no jitter or TAA is off.
glm::dvec2 taa_jitter(const TaaSettings& s, int frame);

// Half size of Yang et al. 2021 eq. 15's eta x eta clamp window in simulated pixels at relative
// radius r / e^L and render.scale s: eta (odd, 1..39 display pixels) times s, halved.
int taa_eta_half(double r_over_eL, double render_scale);

// The defaults a method's table declares (its seed's pipeline) and where they come from.
struct TaaDefaults {
  bool enabled = false;
  double alpha = 0.1;
  const char* clamp = "box3";
  bool jitter = false;
  const char* source = "";  // seed section of the method's TAA ("" when its seed has none)
  bool jitter_row = true;   // false: the method has no reduced buffer to jitter (no row)
};

// Adds the rows taa, taa_alpha, taa_clamp and (jitter_row) taa_jitter to a method's table;
// `acc(s)` returns the TaaSettings member of the method's parameter struct (const or not).
template <class T, class Acc>
void add_taa_rows(ParamTable<T>& t, Acc acc, const TaaDefaults& d) {
  t.boolean(
       "taa", d.enabled, [acc](auto& s) -> auto& { return acc(s).enabled; })
      .doc(d.source, "temporal anti-aliasing post pass: reprojected history, clamped and blended")
      .number(
          "taa_alpha", d.alpha,
          Range::above(0, 1), [acc](auto& s) -> auto& { return acc(s).alpha; })
      .doc(d.source, "TAA: weight of the current frame in the exponential blend")
      .choice(
          "taa_clamp", d.clamp,
          std::vector<std::pair<std::string, TaaClamp>>{{"box3", TaaClamp::Box3},
                                                        {"eta", TaaClamp::Eta}},
          [acc](auto& s) -> auto& { return acc(s).clamp; })
      .doc(d.source,
           "TAA history clamp: 3x3 box (Karis 2014) or eta x eta (Yang et al. 2021 eq. 15)");
  if (d.jitter_row)
    t.boolean(
         "taa_jitter", d.jitter, [acc](auto& s) -> auto& { return acc(s).jitter; })
        .doc(d.source, "TAA: Halton(2, 3) sub-pixel jitter of the reduced buffer's samples");
}

struct TaaScratch;  // one apply()'s working buffers (taa.cpp)

// The pass's state: the previous output (history), kept across frames; its working buffers
// are lent per call from a pool (no per-frame allocation of full-frame buffers).
class TaaPass {
 public:
  // Replaces `img` (linear RGB, the method's output) by its TAA: per pixel the history at
  // (x + 0.5, y + 0.5) - motion (bilinear; none outside the screen, on the first frame after a
  // reset or when the size changed), clamped per channel to the min/max of the current image
  // over the clamp window, then alpha * current + (1 - alpha) * history. Misses (sky) have no
  // motion in the G-buffer (0): their history is read in place, which the clamp bounds.
  // Counter: taa_pixels (pixels that blended a history).
  void apply(const TaaSettings& s, const FrameContext& ctx, Image& img, Counters& c);
  void reset() { has_history_ = false; }
  // The bytes it keeps per method instance at a width x height image (memory plan).
  static size_t bytes(int width, int height, const TaaSettings& s);
  // The bytes of one apply()'s working buffers, lent from a pool shared by every TaaPass (one
  // per pass running at once; memory plan).
  static size_t scratch_bytes(int width, int height, const TaaSettings& s);

 private:
  void prepare_eta(const FrameContext& ctx, const Image& img, TaaScratch& sc);
  Image history_;
  bool has_history_ = false;
};

}  // namespace fovsim
