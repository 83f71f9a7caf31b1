// The one launcher of viz/ scripts (sim/experiment/plots.h): quoting and the silent skip.
#include "sim/experiment/plots.h"

#include <gtest/gtest.h>

#include <cstdlib>

namespace fovsim {
namespace {

TEST(Plots, ShellQuoteSurvivesQuotesAndSpaces) {
  EXPECT_EQ(shell_quote("results/a b"), "'results/a b'");
  EXPECT_EQ(shell_quote("it's"), "'it'\\''s'");
  EXPECT_EQ(plot_command("viz/plot_run.py", {"results/x"}, true),
            "/usr/bin/python3 'viz/plot_run.py' 'results/x' >/dev/null 2>&1");
  EXPECT_EQ(plot_command("viz/plot_run.py", {"r"}, false),
            "/usr/bin/python3 'viz/plot_run.py' 'r' 2>&1");
}

TEST(Plots, EnvironmentSkipsSilently) {
  setenv("FOVSIM_NO_PLOTS", "1", 1);
  PlotOutcome p = run_plot_script("plot_run.py", {"/nonexistent"}, true);
  unsetenv("FOVSIM_NO_PLOTS");
  EXPECT_EQ(p.status, PlotOutcome::Status::Skipped);
  EXPECT_TRUE(p.message.empty());
}

TEST(Plots, MissingScriptIsASkipWithAMessage) {
  unsetenv("FOVSIM_NO_PLOTS");
  PlotOutcome p = run_plot_script("no_such_plot.py", {"x"}, true);
  EXPECT_EQ(p.status, PlotOutcome::Status::Skipped);
  EXPECT_NE(p.message.find("viz/no_such_plot.py not found"), std::string::npos) << p.message;
}

}  // namespace
}  // namespace fovsim
