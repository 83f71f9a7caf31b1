// The order a group's frames are evaluated in (docs/architecture.md "Data flow of one frame": frame
// order). Frame k of the run (k = 0 .. count-1) is trace frame start + k * stride. First the
// frames.warmup frames (k = -warmup .. -1: rendered and fed to every method, not recorded), then
// the recorded frames: in trace order, or under --target in units of kTargetUnitFrames frames
// (intervals.h), in a seeded random order when no method is temporal (`shuffled`), each unit
// that does not follow the previous one preceded by kTargetWarmupFrames unrecorded frames,
// until the caller says every target holds.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

namespace fovsim {

class FrameOrder {
 public:
  // `sampled`: --target was given; `shuffled`: its units run in random order (seeded by `seed`).
  FrameOrder(int count, int warmup, bool sampled, bool shuffled, uint64_t seed);

  struct Steps {
    std::function<void(int k, bool record)> frame;  // evaluate frame k (record: rows and images)
    std::function<void()> discontinuity;  // before a unit that does not follow the last frame
    // Under --target, after each unit (units_done of them so far): true stops the run.
    std::function<bool(int units_done)> unit_done;
  };
  // Calls `steps` in evaluation order.
  void run(const Steps& steps);

  bool sampled() const { return sampled_; }
  bool shuffled() const { return shuffled_; }
  int unit_frames() const { return unit_; }
  const std::vector<int>& unit_order() const { return order_; }
  int recorded() const { return recorded_; }   // frames evaluated with record = true (after run)
  int warmup() const { return warmup_done_; }  // frames evaluated with record = false

 private:
  int count_, warmup_;
  bool sampled_, shuffled_;
  int unit_;
  std::vector<int> order_;
  int recorded_ = 0, warmup_done_ = 0;
};

}  // namespace fovsim
