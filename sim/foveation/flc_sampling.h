// FLC shading-point selection (Yang et al. 2021 §4.2): shuffled 2D Halton proposals and the
// modified quasi-Metropolis-Hastings chains of its Algorithm 1.
#pragma once
#include <cstdint>
#include <vector>

#include "sim/core/image.h"
#include "sim/core/math.h"

namespace fovsim {

// Radical inverse of i in base b (van der Corput), in [0, 1).
double radical_inverse(uint64_t i, uint32_t base);
// n points of the 2D Halton sequence (bases 2, 3; indices 1..n), shuffled by a Fisher-Yates
// permutation seeded with `seed` (Alg. 1 input H).
std::vector<glm::vec2> shuffled_halton(size_t n, uint64_t seed);

struct ImportanceSample {
  uint32_t pixel = 0;  // y * W + x
  float weight = 0.f;  // importance p of the accepted pixel
};

// Algorithm 1: chain j starts at H[j*M] and, for the M-1 following proposals H[j*M+i], moves
// to the proposal when its importance is greater. Returns one sample per chain (N_s chains);
// H must hold at least N_s * M points in [0,1)^2, mapped to pixels of the W x H map `P`.
std::vector<ImportanceSample> flc_select_samples(const Image& P, const std::vector<glm::vec2>& H,
                                                 int n_s, int m);

}  // namespace fovsim
