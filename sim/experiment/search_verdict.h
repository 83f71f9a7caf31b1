// What a search's answer means (docs/sweeps.md "Is the answer trivial?"): whether its budget
// binds at all, whether the optimum sits on an end of the space (the space, not the objective,
// stopped it), and whether the winner beats the runner-up beyond noise. Pure functions of the
// evaluated points, so the search runner and the unit tests share them.
#pragma once
#include <string>
#include <vector>

#include "sim/experiment/sweep_spec.h"

namespace fovsim {

// One end of one axis the point lies on: `end` -1 the lower end (`from`), +1 the upper (`to`).
struct BoundaryHit {
  size_t dim = 0;
  int end = 0;
  double value = 0;
};
// The axes on which `x` (real units, one per dimension) lies at an end of its range: at `from`,
// or at the largest value the axis can take (`to`, or the last step below it). An axis with
// from == to has no ends.
std::vector<BoundaryHit> boundary_hits(const std::vector<SearchDim>& space,
                                       const std::vector<double>& x);
// "the optimum lies on the lower end of methods[kfr].sigma (1.2)" ("" without hits).
std::string describe_boundary(const std::vector<SearchDim>& space,
                              const std::vector<BoundaryHit>& hits);

// Winner against runner-up: the difference of their scores (winner − runner-up) and its 95%
// half-width. `paired`: from the per-frame differences on the frames both have finite values
// (mean_interval, sim/core/stats.h); else from the two means' half-widths,
// sqrt(ci_w² + ci_r²) (independent runs). `tied`: |Δ| <= half-width; -1 when no half-width is
// defined (too few frames for either interval).
struct ScoreComparison {
  double delta = 0, ci95 = 0;
  bool paired = false;
  size_t frames = 0;  // paired: the frames both scores are finite on
  int tied = -1;
  std::string why;  // when tied is -1: why no interval
};
ScoreComparison compare_scores(double winner, double runner_up, const std::vector<double>& w_frames,
                               const std::vector<double>& r_frames, double w_ci95, double r_ci95);
// "winner and runner-up tied within noise (Δ +0.12 ± 0.30, paired over 20 frames)" or
// "winner beats runner-up beyond noise (Δ ...)".
std::string describe_comparison(const ScoreComparison& c, const std::string& column);

// Frame-time columns: a constraint on one of them is a frame budget (headroom_ms, fits_budget,
// p_fit, est_ms_total and its percentiles and interval ends).
bool is_frame_budget_column(const std::string& column);

// Whether the search's constraints bind: `values[p][k]` is constraint k's value at evaluated
// point p. A constraint binds when some evaluated point violates it. Returns one sentence per
// constraint that no point violated (empty when every constraint binds or there are none).
std::vector<std::string> non_binding_constraints(const SearchSpec& sp,
                                                 const std::vector<std::vector<double>>& values);

// The frame-budget sentence: "budget does not bind: <what> fits at X ms of Y ms" when
// `ms` <= `budget_ms` ("" otherwise). `what`: "full", "the most expensive of 8 evaluated
// points (methods[kfr].sigma = 1.2)".
std::string budget_sentence(const std::string& what, double ms, double budget_ms);

}  // namespace fovsim
