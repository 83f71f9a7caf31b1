// The options every way of running configs shares: `fovsim run`, `sweep`, `search`,
// `fidelity` and `converge` declare them once (sim/app/commands.h add_run_flags) and Python's
// fovsim.run / sweep / Evaluator / AskTell take the same ones (python/bindings.cpp);
// RunOptions (runner.h), SweepOptions (sweep_runner.h), FidelityOptions (fidelity.h) and
// ConvergenceOptions (convergence.h) extend it.
#pragma once
#include <string>
#include <vector>

#include "sim/core/error.h"
#include "sim/core/message_text.h"
#include "sim/core/params.h"

namespace fovsim {

struct RunControl {
  std::string models_dir;  // empty -> default_models_dir()
  int threads = 0;         // 0 = TBB default; results are identical at any count
  double watchdog_s = 60;  // WatchdogLimits::min_s (0 disables; sim/core/watchdog.h)
  // --target specs ("est_ms_total:1%", "fpsnr:0.2dB"; sim/experiment/intervals.h): frames in a
  // seeded random order of sampling units until every 95% half-width is within its target.
  std::vector<std::string> targets;
  // The reference cache (sim/experiment/reference_cache.h), when the config's cache.enabled is
  // true too. Off by default (library use, tests, Python); `fovsim run` / `sweep` turn it on.
  bool use_cache = false;

  static Range threads_range() { return Range::closed(0, 4096); }  // 0: all cores
  // Seconds; 0, outside the range, disables the watchdog (a limit below a second would
  // report every frame as a hang).
  static Range watchdog_range() { return Range::closed(1, 86400); }
  // v when it is 0 or in watchdog_range(), else fovsim::Error(where, "value V is out of range
  // [1, 86400] s (0: off)"): the check of the CLI's --watchdog and Python's watchdog=.
  static double check_watchdog(const std::string& where, double v) {
    if (v == 0) return 0;
    if (!watchdog_range().contains(v))
      throw Error(where, "value " + shortest_number(v) + " is out of range " +
                             watchdog_range().str() + " s (0: off)");
    return v;
  }
};

}  // namespace fovsim
