// TWFR hole filling (Franke et al. 2021 §5.1) with the contrast confidence of §5.2.
// Push-pull [GGSC96]: a mip pyramid of the valid colours is built (average of the valid
// children); each hole is filled at the finest level m >= 1 whose covering texel holds data
// (the mip level is chosen per hole, relative to its size), bilinearly from the valid texels
// of that level. While building the pyramid each texel's alpha is the contrast confidence
//   c_c(p0..p3) = 1 - 0.5 (max L_i - min L_i)     (§5.2)
// of the (valid) children it averages, L = display luminance in [0, 1].
#pragma once
#include <cstdint>
#include <vector>

#include "sim/core/image.h"

namespace fovsim {
namespace twfr {

constexpr uint8_t kUncovered = 255;  // hole with no data anywhere in the pyramid

// Display luminance in [0, 1] of a linear RGB colour: Rec. 709 luma scaled by `exposure`,
// ACES filmic fit (Narkowicz 2015), sRGB encoding. The seed rates contrast on tone-mapped
// 8-bit colours (§4); this approximates that without depending on the run's tone mapper.
float display_luminance(const float* rgb, float exposure);

struct PushPullLevel {
  int width = 0, height = 0;
  std::vector<float> rgb;    // 3 floats per texel, average of valid children
  std::vector<float> alpha;  // contrast confidence c_c of the texel; < 0 where invalid
  std::vector<float> lum;    // display luminance of the texel's colour
};

struct PushPull {
  std::vector<PushPullLevel> levels;  // levels[0] unused (level 0 is the input image)
  std::vector<float> lum0;            // luminance of the input pixels
  int num_levels() const { return int(levels.size()); }
};

struct PushPullStats {
  std::vector<size_t> holes_per_level;  // index m = 1..num_levels-1 (index 0 unused)
  size_t holes = 0, uncovered = 0;
};

// Fills pixels with valid[i] == 0 and skip[i] == 0 (skip: e.g. the fovea, redrawn anyway) in
// `color` (W x H x 3). level_out[i] = 0 for valid pixels, m for pixels filled at level m,
// kUncovered where nothing could fill them (and for skipped pixels); cc_out[i] = contrast
// confidence (1 for valid pixels, the alpha at level m for filled, 0 otherwise).
PushPullStats push_pull_fill(Image& color, const std::vector<uint8_t>& valid, const uint8_t* skip,
                             float exposure, std::vector<uint8_t>& level_out,
                             std::vector<float>& cc_out, PushPull& scratch);

}  // namespace twfr
}  // namespace fovsim
