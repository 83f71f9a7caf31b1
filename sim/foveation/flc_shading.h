// FLC shading with the kept VPLs (Yang et al. 2021 §6): full resolution, interleaved sampling
// (Keller & Heidrich 2001) with the 3x3 Gaussian, and shading in log-polar space (backward
// transform of the G-buffer, KFR-style buffer of (W/sigma) x (H/sigma), inverse map with
// bilinear filtering).
#pragma once
#include <cstdint>
#include <vector>

#include "sim/core/counters.h"
#include "sim/core/image.h"
#include "sim/render/gbuffer.h"
#include "sim/render/vpl.h"

namespace fovsim {

class Renderer;

// Buffers the shading passes reuse from frame to frame (no per-frame full-frame allocation);
// optional: without it the passes allocate their own.
struct FlcShadeScratch {
  Image filter_src, lp;
  std::vector<uint8_t> valid, lp_valid;
};

// Splits the weighted VPL subset into n*n interleaved groups (VPL k -> group k mod n^2), each
// VPL's weight multiplied by n^2 so every group is an unbiased estimate of the whole set.
std::vector<VplSoA> flc_interleave_groups(const std::vector<VPL>& vpls,
                                          const std::vector<uint32_t>& idx,
                                          const std::vector<float>& weight, int n);

// 3x3 Gaussian ([1 2 1]^2 / 16) over the samples with valid[i] != 0, renormalised over the
// valid neighbours (misses neither contribute nor receive). `wrap_y`: rows wrap (log-polar angle).
void flc_gauss3(Image& img, const std::vector<uint8_t>& valid, bool wrap_y,
                Image* scratch = nullptr);

// Indirect light of every G-buffer sample with interleaved groups (pixel (x, y) uses group
// (x mod n) + n (y mod n)); for n > 1 the 3x3 Gaussian follows. Misses get 0.
// Counters: shaded_samples, shaded_sample_vpls, vpl_shadow_rays.
void flc_shade_cartesian(const GBuffer& g, const std::vector<VplSoA>& groups, int n,
                         const VplShading& s, const Renderer* r, Image& out, Counters* c,
                         FlcShadeScratch* scratch = nullptr);

// Same in log-polar space around the gaze (sigma >= 1): each LP texel takes the G-buffer
// sample of the pixel it maps back to, is shaded there, then the buffer is mapped to the
// screen bilinearly. Pixels whose four LP neighbours are all invalid are shaded directly.
// `lp_debug` (optional) receives the LP buffer.
void flc_shade_logpolar(const GBuffer& g, const glm::dvec2& gaze_px, double sigma,
                        const std::vector<VplSoA>& groups, int n, const VplShading& s,
                        const Renderer* r, Image& out, Counters* c, Image* lp_debug = nullptr,
                        FlcShadeScratch* scratch = nullptr);

}  // namespace fovsim
