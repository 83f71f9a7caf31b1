// The list of command groups (commands.h register_commands): main.cpp and the flag walk of
// tests/app/flags_test.cpp register the same commands.
#include "sim/app/commands.h"

namespace fovsim::app {

void register_commands(CLI::App& app, Action& action) {
  // Explicit registration, one line per command group.
  register_run(app, action);
  register_cost(app, action);
  register_trace(app, action);
  register_sweeps(app, action);
  register_density(app, action);
  register_info(app, action);
  register_methods(app, action);
  register_compare(app, action);
  register_converge(app, action);
  register_fidelity(app, action);
  register_cache(app, action);
}

}  // namespace fovsim::app
