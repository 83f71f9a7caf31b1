// Ask/tell search over continuous parameters (Timeloop style, docs/architecture.md "Errors and
// conventions": the search proposes, the sweep engine evaluates; neither knows the other). Used for
// the per-scene best fx, fy (and sigma, alpha) under a frame-time or shaded-sample budget, which
// RMFR (Ye et al. 2022 §7) leaves as future work.
//
// Algorithm: a seeded Latin-hypercube batch, then a batched compass (pattern) search around
// the incumbent that halves its step when a whole batch brings no improvement (Torczon 1997;
// deterministic, derivative-free, robust to the noisy-but-smooth quality surfaces here).
// Constraint handling: feasible beats infeasible; among infeasible, the smaller violation wins.
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "sim/core/rng.h"
#include "sim/experiment/sweep_spec.h"

namespace fovsim {

struct SearchEval {
  std::vector<double> x;  // real units, one per dimension
  double score = 0;       // objective (oriented by SearchSpec: maximize or minimize)
  double violation = 0;   // max(0, constraint - limit); 0 = feasible
};

// A result told from outside (the Python AskTell): the point must lie in the space (one
// finite value per dimension within [lo, hi]), the score must be finite and the violation a
// number >= 0 (inf: infinitely violated, as SearchSpec::violation gives a missing column).
// Throws fovsim::Error at `where` naming the dimension's path and its range, or the value.
// `values` false: the point only (a score taken from a run's summary is scored as `fovsim
// search` scores it, where a nan objective ranks last).
void check_told(const std::vector<SearchDim>& space, const SearchEval& e, const std::string& where,
                bool values = true);

class Searcher {
 public:
  Searcher(std::vector<SearchDim> space, bool maximize, uint64_t seed, int batch);

  // Next batch of points to evaluate (never one already told; may be fewer than `batch`).
  // Empty when the step has shrunk below the resolution of every dimension.
  std::vector<std::vector<double>> ask();
  // Results for points returned by ask (any order, any subset).
  void tell(const std::vector<SearchEval>& evals);

  bool has_best() const { return has_best_; }
  const SearchEval& best() const { return best_; }
  const std::vector<SearchEval>& history() const { return history_; }
  double step() const { return step_; }
  bool better(const SearchEval& a, const SearchEval& b) const;

  // Unit-cube <-> real coordinates (log, quantization and integer rounding applied).
  std::vector<double> to_real(const std::vector<double>& u) const;
  std::vector<double> to_unit(const std::vector<double>& x) const;

 private:
  std::string key(const std::vector<double>& x) const;
  std::vector<SearchDim> dims_;
  bool maximize_;
  int batch_;
  Rng rng_;
  bool started_ = false;
  double step_ = 0.25;  // in unit-cube coordinates
  double min_step_;
  bool improved_ = false;  // since the last ask
  bool has_best_ = false;
  SearchEval best_;
  std::vector<SearchEval> history_;
  std::map<std::string, bool> seen_;
};

}  // namespace fovsim
