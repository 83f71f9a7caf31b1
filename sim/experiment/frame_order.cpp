#include "sim/experiment/frame_order.h"

#include <algorithm>

#include "sim/experiment/intervals.h"

namespace fovsim {

FrameOrder::FrameOrder(int count, int warmup, bool sampled, bool shuffled, uint64_t seed)
    : count_(count),
      warmup_(warmup),
      sampled_(sampled),
      shuffled_(sampled && shuffled),
      unit_(sampled ? kTargetUnitFrames : std::max(count, 1)) {
  const int units = (count_ + unit_ - 1) / unit_;
  order_.resize(size_t(units));
  for (int u = 0; u < units; ++u) order_[size_t(u)] = u;
  if (shuffled_) order_ = sampling_order(units, seed);
}

void FrameOrder::run(const Steps& steps) {
  recorded_ = warmup_done_ = 0;
  for (int k = -warmup_; k < 0; ++k) {  // frames.warmup: rendered, not recorded
    steps.frame(k, false);
    ++warmup_done_;
  }
  int next_k = 0, units_done = 0;
  for (int u : order_) {
    const int k0 = u * unit_, k1 = std::min(count_, k0 + unit_);
    if (k0 != next_k) {
      steps.discontinuity();
      for (int k = std::max(0, k0 - kTargetWarmupFrames); k < k0; ++k) {
        steps.frame(k, false);
        ++warmup_done_;
      }
    }
    for (int k = k0; k < k1; ++k) steps.frame(k, true);
    next_k = k1;
    recorded_ += k1 - k0;
    // Checked every unit: a target naming an absent column fails on the first.
    if (sampled_ && steps.unit_done(++units_done)) break;
  }
}

}  // namespace fovsim
