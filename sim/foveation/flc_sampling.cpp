// FLC sample selection (Yang et al. 2021 §4.2, Algorithm 1). See flc_sampling.h.
#include "sim/foveation/flc_sampling.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <utility>

#include "sim/core/error.h"
#include "sim/core/rng.h"

namespace fovsim {

double radical_inverse(uint64_t i, uint32_t base) {
  const double inv = 1.0 / double(base);
  double f = inv, r = 0.0;
  while (i > 0) {
    r += double(i % base) * f;
    i /= base;
    f *= inv;
  }
  return r;
}

std::vector<glm::vec2> shuffled_halton(size_t n, uint64_t seed) {
  std::vector<glm::vec2> h(n);
  for (size_t i = 0; i < n; ++i)
    h[i] = glm::vec2(float(radical_inverse(i + 1, 2)), float(radical_inverse(i + 1, 3)));
  Rng rng(seed, 0x464c43ull);  // "FLC"
  for (size_t i = n; i > 1; --i) {
    size_t j = size_t(rng.uniform() * double(i));
    if (j >= i) j = i - 1;
    std::swap(h[i - 1], h[j]);
  }
  return h;
}

std::vector<ImportanceSample> flc_select_samples(const Image& P, const std::vector<glm::vec2>& H,
                                                 int n_s, int m) {
  FOVSIM_CHECK(n_s >= 0 && m >= 1, "flc_select_samples: invalid chain count/length");
  FOVSIM_CHECK(H.size() >= size_t(n_s) * size_t(m),
               "flc_select_samples: too few Halton points for N_s * M");
  std::vector<ImportanceSample> out(static_cast<size_t>(n_s));
  if (P.width <= 0 || P.height <= 0) return out;
  const int W = P.width, Ht = P.height;
  auto pixel_of = [&](const glm::vec2& u) {
    int x = std::clamp(int(u.x * float(W)), 0, W - 1);
    int y = std::clamp(int(u.y * float(Ht)), 0, Ht - 1);
    return uint32_t(size_t(y) * size_t(W) + size_t(x));
  };
  tbb::parallel_for(0, n_s, [&](int j) {
    const size_t base = size_t(j) * size_t(m);
    uint32_t coord = pixel_of(H[base]);  // lines 2-3
    float w = P.data[coord];
    for (int i = 1; i < m; ++i) {  // lines 4-9 (M - 1 proposals)
      uint32_t c2 = pixel_of(H[base + size_t(i)]);
      float w2 = P.data[c2];
      if (w2 > w) {
        coord = c2;
        w = w2;
      }
    }
    out[size_t(j)] = ImportanceSample{coord, w};  // line 10
  });
  return out;
}

}  // namespace fovsim
