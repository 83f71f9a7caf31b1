// Tracking loss in a cell (docs/tracking.md, trace.on_invalid = full): a method renders as
// `full` while the tracker has lost the gaze and restarts its temporal history when tracking
// returns (what it had is from before the loss). The gaze itself comes from the cell's
// GazeSource (gaze_source.h); this is the method swap.
#pragma once
#include <memory>
#include <string>

#include "sim/foveation/method.h"

namespace fovsim {

struct TrackingSwap {
  std::unique_ptr<FoveationMethod> full;  // made on the first lost frame
  bool was_full = false;                  // the previous frame was rendered by `full`

  // The method that renders this frame: `full` while `render_full` (and the method is not
  // `full` already), else `impl`, reset first when the previous frame was `full`'s.
  FoveationMethod& select(FoveationMethod& impl, const std::string& method, bool render_full);
  // The `full` method (made on first use): the one costed when a memoised frame was rendered
  // as `full`.
  FoveationMethod& full_method();
};

}  // namespace fovsim
